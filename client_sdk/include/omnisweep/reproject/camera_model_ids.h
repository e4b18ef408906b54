// The camera model ids of the GPU kernels, defined once for both languages: C++ reads them
// through gpu_camera.h (GpuModel) and GLSL through shaders/include/camera.glsl, which includes
// this file (plain #defines are the one syntax the two share).
#ifndef OMNISWEEP_REPROJECT_CAMERA_MODEL_IDS_H_
#define OMNISWEEP_REPROJECT_CAMERA_MODEL_IDS_H_

#define OMNISWEEP_MODEL_DOUBLE_SPHERE 0
#define OMNISWEEP_MODEL_KANNALA_BRANDT 1
#define OMNISWEEP_MODEL_EXTENDED_UNIFIED 2
#define OMNISWEEP_MODEL_PINHOLE 3
#define OMNISWEEP_MODEL_EQUIRECTANGULAR 4
// Not a model: a kernel's camera role whose model is left to each camera's record (camera.glsl).
#define OMNISWEEP_MODEL_ANY 255

#endif  // OMNISWEEP_REPROJECT_CAMERA_MODEL_IDS_H_
