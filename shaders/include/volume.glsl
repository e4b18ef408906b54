// A cost volume is stored as up to kMaxChunks buffers ("chunks") of kChannels channels each, for
// every reference slot of the dispatch (gl_GlobalInvocationID.z). Channels are packed VOLUME_PACK
// to a texel (4 candidates; 1 for one-channel volumes such as the distance maps), and a texel's
// plane holds it for every pixel: texel t (channels t * VOLUME_PACK ...) of pixel p of slot s is
// element volume_index(s, t, plane, p) of its chunk. Planes keep neighbouring invocations on
// neighbouring values (coalesced on GPUs); packing lets a kernel read or write 4 candidates with
// one access. Chunks keep every binding within the device's maxStorageBufferRange and
// maxTexelBufferElements (plan_volume).
//
// Kernels write volumes through storage buffers and read them through texel buffers
// (CostVolume::texels: RGBA16F / RGBA32F views, R16F / R32F for VOLUME_PACK 1), which are vector
// gathers on CPU devices where storage-buffer loads are a loop over the lanes, and go through
// the texture cache on GPUs. texelFetch returns the stored values exactly, as floats. Texel
// buffer arrays are indexed with constants only (not every device indexes them dynamically:
// lavapipe 22 lacks shaderUniformTexelBufferArrayDynamicIndexing): a kernel puts its work on one
// chunk in a function or macro that takes the chunk's texel buffer, and FOR_EACH_CHUNK calls it
// for each chunk in use, CALL(c) with c a literal; the compiler drops the calls past kChunks.
//
// The kernels are built in variants (shaders/CMakeLists.txt): VOLUME_F16 stores 16-bit floats
// (half the memory traffic; every kernel still computes in 32 bits: values are converted on load
// and store), VOLUME_PACK=4 packs channels by four.
const uint kMaxChunks = 8u;
layout(constant_id = 0) const uint kChannels = 32u;  // channels per chunk (a multiple of the pack)
layout(constant_id = 1) const uint kChunks = 1u;     // chunks in use

#ifndef VOLUME_PACK
#define VOLUME_PACK 1
#endif
const uint kPack = uint(VOLUME_PACK);
const uint kTexels = kChannels / kPack;  // texels per pixel in a chunk

#define FOR_EACH_CHUNK(CALL) \
  CALL(0) CALL(1) CALL(2) CALL(3) CALL(4) CALL(5) CALL(6) CALL(7)

uint volume_index(uint slot, uint texel, uint plane, uint pixel) {
  return (slot * kTexels + texel) * plane + pixel;
}

// VOLUME_V: the values of one texel as computed (float or vec4); VOLUME_T: as stored;
// VOLUME_FETCH(texels, index): one texel read from a texel buffer as VOLUME_V.
#if VOLUME_PACK == 4
#define VOLUME_V vec4
#define VOLUME_FETCH(texels, index) texelFetch(texels, index)
#ifdef VOLUME_F16
#define VOLUME_T f16vec4
#else
#define VOLUME_T vec4
#endif
#else
#define VOLUME_V float
#define VOLUME_FETCH(texels, index) texelFetch(texels, index).x
#ifdef VOLUME_F16
#define VOLUME_T float16_t
#else
#define VOLUME_T float
#endif
#endif
