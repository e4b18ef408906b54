#include "server/synthetic/synthetic_dataset.h"

#include <chrono>

#include "omnisweep/dataset/dataset.h"

namespace omnisweep::synthetic {

WriteDatasetStats write_synthetic_dataset(const SyntheticRig& rig, const std::filesystem::path& dir,
                                          const WriteDatasetOptions& options,
                                          const std::function<void(int, int)>& progress) {
  using Clock = std::chrono::steady_clock;
  auto seconds_since = [](Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
  };
  WriteDatasetStats stats;
  auto t = Clock::now();
  const DatasetWriter writer(dir, rig.rig());
  const std::vector<Gray8Image> masks = rig.masks();
  for (int c = 0; c < rig.rig().num_cameras(); ++c) writer.write_mask(c, masks[c]);
  writer.write_hints({.references = rig.options().references,
                      .viewpoint = rig.viewpoint(),
                      .min_distance = std::nullopt,
                      .max_distance = std::nullopt});
  for (int i = 0; i < options.num_frames; ++i) {
    const int index = options.first_frame + i;
    const std::string name = std::to_string(index);
    stats.write_seconds += seconds_since(t);
    t = Clock::now();
    SyntheticFrame frame = rig.render(index, options.panorama_width, options.panorama_height);
    stats.render_seconds += seconds_since(t);
    t = Clock::now();
    std::vector<Rgb8Image> images;
    for (int c = 0; c < rig.rig().num_cameras(); ++c) {
      images.push_back(std::move(frame.cameras[c].rgb));
      writer.write_camera_ground_truth(name, c, frame.cameras[c].inverse_distance);
    }
    writer.write_images(name, images);
    writer.write_ground_truth(name, frame.panorama.rgb, frame.panorama.inverse_distance);
    if (progress) progress(i + 1, options.num_frames);
  }
  stats.write_seconds += seconds_since(t);
  return stats;
}

}  // namespace omnisweep::synthetic
