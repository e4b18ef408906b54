// libFuzzer target: the basalt calibration parser (client_sdk/src/rig), which reads files users
// hand to --calibration and the JSON of datasets. It may throw; it must not crash.
#include <cstddef>
#include <cstdint>
#include <exception>
#include <string_view>

#include "omnisweep/rig/basalt_calibration.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const omnisweep::Rig rig = omnisweep::parse_basalt_calibration(
        std::string_view(reinterpret_cast<const char*>(data), size), "fuzz input");
    (void)omnisweep::to_basalt_json(rig);
  } catch (const std::exception&) {
  }
  return 0;
}
