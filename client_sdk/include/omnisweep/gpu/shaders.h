// The SPIR-V of every kernel in shaders/*.comp, compiled at build time and embedded. Kernels are
// named by their id (omnisweep/gpu/shader_ids.h, generated from the list of files).
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "omnisweep/gpu/shader_ids.h"

namespace omnisweep::gpu {

// One build of a kernel. The kernels that store a cost volume are also built for 16-bit stored
// values (VOLUME_F16, the _f16 builds) and with channels packed by four (VOLUME_PACK=4, _x4);
// those that only read one, packed by four (shaders/CMakeLists.txt, shaders/include/volume.glsl).
struct ShaderBuild {
  Shader shader;
  bool half = false;    // _f16
  bool packed = false;  // _x4

  ShaderBuild(Shader id, bool half_values = false, bool packed_by_four = false)  // NOLINT: implicit
      : shader(id), half(half_values), packed(packed_by_four) {}
};

// "sphere_sweep_cost_f16_x4": the kernel's file name and its build's suffixes.
inline std::string shader_name(ShaderBuild build) {
  return std::string(kShaderNames[int(build.shader)]) + (build.half ? "_f16" : "") +
         (build.packed ? "_x4" : "");
}

// The build's SPIR-V; throws std::invalid_argument naming it when that build is not made.
std::span<const std::uint32_t> embedded_shader(ShaderBuild build);

}  // namespace omnisweep::gpu
