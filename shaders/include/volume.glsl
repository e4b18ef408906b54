// A cost volume is stored as up to kMaxChunks buffers ("chunks") of kChannels planes each, for
// every reference slot of the dispatch (gl_GlobalInvocationID.z): candidate i of pixel p of
// slot s lives in chunk i / kChannels at volume_index(s, i % kChannels, plane, p). Planes keep
// neighbouring invocations on neighbouring values (coalesced on GPUs). Chunks keep every binding
// within the device's maxStorageBufferRange and maxTexelBufferElements (plan_volume).
//
// Kernels write volumes through storage buffers and read them through texel buffers
// (CostVolume::texels: R16F views of 16-bit volumes, R32F of 32-bit ones), which are vector
// gathers on CPU devices where storage-buffer loads are a loop over the lanes, and go through
// the texture cache on GPUs. texelFetch returns the stored value exactly, as a float. Texel
// buffer arrays are indexed with constants only (not every device indexes them dynamically:
// lavapipe 22 lacks shaderUniformTexelBufferArrayDynamicIndexing): a kernel puts its work on one
// chunk in a function that takes the chunk's texel buffer, and FOR_EACH_CHUNK calls it for each
// chunk in use, CALL(c) with c a literal; the compiler drops the calls past kChunks.
const uint kMaxChunks = 8u;
layout(constant_id = 0) const uint kChannels = 32u;  // candidates per chunk
layout(constant_id = 1) const uint kChunks = 1u;     // chunks in use

#define FOR_EACH_CHUNK(CALL) \
  CALL(0) CALL(1) CALL(2) CALL(3) CALL(4) CALL(5) CALL(6) CALL(7)

uint volume_index(uint slot, uint channel, uint plane, uint pixel) {
  return (slot * kChannels + channel) * plane + pixel;
}

// The stored type of a volume's values: 32-bit floats, or, in the *_f16 builds of the volume
// kernels (shaders/CMakeLists.txt, VOLUME_F16), 16-bit floats (half the memory traffic; every
// kernel still computes in 32 bits: values are converted on load and store).
#ifdef VOLUME_F16
#define VOLUME_T float16_t
#else
#define VOLUME_T float
#endif
