// The SPIR-V of every kernel in shaders/*.comp, compiled at build time and embedded.
#pragma once

#include <cstdint>
#include <span>
#include <string_view>

namespace omnisweep::gpu {

// The kernel compiled from shaders/<name>.comp; throws std::invalid_argument for unknown names.
std::span<const std::uint32_t> embedded_shader(std::string_view name);

}  // namespace omnisweep::gpu
