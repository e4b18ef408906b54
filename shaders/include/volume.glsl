// A cost volume is stored as up to kMaxChunks storage buffers ("chunks") of kChannels planes
// each: candidate i of pixel p lives in chunk i / kChannels at (i % kChannels) * pixels + p.
// Planes keep neighbouring invocations on neighbouring floats (coalesced on GPUs, vector loads
// on lavapipe). Chunks keep every binding within the device's maxStorageBufferRange (128 MiB
// on lavapipe: exactly one 1024^2 x 32 float volume).
const uint kMaxChunks = 8u;
layout(constant_id = 0) const uint kChannels = 32u;  // candidates per chunk
layout(constant_id = 1) const uint kChunks = 1u;     // chunks in use

// The stored type of a volume's values: 32-bit floats, or, in the *_f16 builds of the volume
// kernels (shaders/CMakeLists.txt, VOLUME_F16), 16-bit floats (half the memory traffic; every
// kernel still computes in 32 bits: values are converted on load and store).
#ifdef VOLUME_F16
#define VOLUME_T float16_t
#else
#define VOLUME_T float
#endif
