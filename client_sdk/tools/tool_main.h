// What every omnisweep-* program shares: errors become one line on stderr naming the program
// and exit code 1, and --vk-device overrides OMNISWEEP_VK_DEVICE.
#pragma once

#include <cstdio>
#include <exception>
#include <string>

#include "omnisweep/gpu/context.h"

namespace omnisweep::tools {

template <typename Run>
int run_tool(const char* name, int argc, char** argv, Run&& run) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", name, e.what());
    return 1;
  }
}

inline gpu::ContextOptions context_options(const std::string& vk_device_flag) {
  gpu::ContextOptions options = gpu::ContextOptions::from_environment();
  if (!vk_device_flag.empty()) options.device = vk_device_flag;
  return options;
}

}  // namespace omnisweep::tools
