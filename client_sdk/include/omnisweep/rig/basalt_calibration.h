// Reads and writes rig calibrations in basalt's JSON format (ALGORITHM.md §1):
//   {"value0": {"T_imu_cam": [{px, py, pz, qx, qy, qz, qw}, ...],
//               "intrinsics": [{"camera_type": "ds", "intrinsics": {fx, fy, ...}}, ...],
//               "resolution": [[width, height], ...]}}
// T_imu_cam[c] is rig_from_cam for camera c. Other basalt fields are ignored on reading.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>

#include "omnisweep/rig/rig.h"

namespace omnisweep {

// Every message names the file (or source) and the JSON field that was wrong.
class CalibrationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Largest accepted | |q| - 1 | for a pose quaternion; within it the quaternion is normalised.
inline constexpr double kQuaternionNormTolerance = 1e-3;

Rig read_basalt_calibration(const std::filesystem::path& path);
// `source` names the text in error messages (a file name, "<stdin>", a topic).
Rig parse_basalt_calibration(std::string_view json_text, std::string_view source);

std::string to_basalt_json(const Rig& rig);
// Writes atomically (temporary file, then rename); throws CalibrationError on failure.
void write_basalt_calibration(const Rig& rig, const std::filesystem::path& path);

}  // namespace omnisweep
