// Writes synthetic rig frames as a dataset in the reference layout (ALGORITHM.md §6), with
// exact ground truth. The file edge of the synthetic rig (the rig itself needs only Eigen).
#pragma once

#include <filesystem>
#include <functional>

#include "server/synthetic/synthetic_rig.h"

namespace omnisweep::synthetic {

struct WriteDatasetOptions {
  int first_frame = 0;
  int num_frames = 1;
  int panorama_width = 2048;
  int panorama_height = 1024;
};

// Writes calibration.json, cam<i>/mask.png, cam<i>/<frame>.png, gt/rgb_<frame>.png,
// gt/inv_distance_<frame>.exr and gt/cam<i>/inv_distance_<frame>.exr; frames are named by their
// index. `progress` (optional) is called after each frame with (frames done, total).
struct WriteDatasetStats {
  double render_seconds = 0;  // ray casting, all frames
  double write_seconds = 0;   // PNG and EXR encoding and writing, all frames
};
WriteDatasetStats write_synthetic_dataset(const SyntheticRig& rig, const std::filesystem::path& dir,
                                          const WriteDatasetOptions& options,
                                          const std::function<void(int, int)>& progress = {});

}  // namespace omnisweep::synthetic
