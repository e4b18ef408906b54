// The synthetic rig: our own four-fisheye calibration (close to the paper's prototype: 1216^2
// double sphere cameras with 220-degree lenses, about 7 cm baselines, cameras 2 and 3 opposed),
// moving on a closed loop through a seeded procedural hall. It renders frames with exact
// ground truth and writes them as datasets in the reference layout. It is the embedded default
// source for demos and the fixture for tests.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "omnisweep/rig/rig.h"
#include "server/synthetic/photometric.h"
#include "server/synthetic/renderer.h"
#include "server/synthetic/scene.h"

namespace omnisweep::synthetic {

struct SyntheticRigOptions {
  std::uint64_t seed = 1;
  int image_size = 1216;             // fisheye width = height, pixels (default calibration only)
  int frames_per_loop = 300;         // one lap of the path (10 s at 30 fps)
  bool static_rig = false;           // every frame at the path's first pose (noise still per frame)
  double lens_half_fov_deg = 110.0;  // 220-degree lenses
  std::vector<int> references = {2, 3};
  PhotometricOptions photometric =
      {};  // none by default: every camera sees the scene's own colours
  // Throws std::invalid_argument naming the bad option.
  void check() const;
};

// The default calibration at image_size x image_size.
Rig default_synthetic_rig(int image_size = 1216);

struct SyntheticFrame {
  std::vector<RenderedImage> cameras;  // per camera: image and inverse distance
  RenderedImage panorama;              // ground truth at the viewpoint
  Rigid3d world_from_rig;
};

class SyntheticRig {
 public:
  // With no calibration given, default_synthetic_rig(options.image_size) is used.
  explicit SyntheticRig(const SyntheticRigOptions& options = {}, const Rig* calibration = nullptr);

  const Rig& rig() const { return rig_; }
  const Scene& scene() const { return scene_; }
  const SyntheticRigOptions& options() const { return options_; }
  // Mean position of the reference cameras, rig frame (ALGORITHM.md §5).
  Eigen::Vector3d viewpoint() const;
  // The rig's pose at frame `index` (the path repeats every frames_per_loop frames; with
  // static_rig, the first pose for every index).
  Rigid3d world_from_rig(int index) const;
  std::vector<Gray8Image> masks() const;
  // Camera c's gain, colour cast and vignetting (options().photometric, drawn from the seed).
  const CameraResponse& response(int camera) const { return responses_.at(camera); }

  SyntheticFrame render(int index, int panorama_width = 2048, int panorama_height = 1024) const;
  RenderedImage render_panorama_at(int index, const Eigen::Vector3d& viewpoint_in_rig, int width,
                                   int height) const;

 private:
  SyntheticRigOptions options_;
  Rig rig_;
  Scene scene_;
  std::vector<CameraResponse> responses_;
};

}  // namespace omnisweep::synthetic
