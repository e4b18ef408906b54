// The synthetic rig as a camera: frames at evenly spaced poses of its loop, rendered on first
// use and cached (a frame takes ~1.5 s to ray-cast on 2 cores), so the stream changes from the
// start and runs at full speed from the second lap on.
#include "server/capture/sources.h"
#include "server/synthetic/synthetic_rig.h"

namespace omnisweep::capture {
namespace {

class SyntheticSource final : public FrameSource {
 public:
  explicit SyntheticSource(const SourceOptions& options)
      : poses_(options.synthetic_poses), cache_(std::size_t(poses_)) {
    if (poses_ < 1 || poses_ > 300)
      throw SourceError("synthetic poses must be 1-300, not " + std::to_string(poses_));
    status_.resize(std::size_t(rig_.rig().num_cameras()));
  }

  const Rig& rig() const override { return rig_.rig(); }
  std::vector<std::optional<Gray8Image>> masks() const override {
    std::vector<std::optional<Gray8Image>> out;
    for (auto& m : rig_.masks()) out.emplace_back(std::move(m));
    return out;
  }
  std::string description() const override {
    return "synthetic rig, " + std::to_string(poses_) + " poses over its " +
           std::to_string(rig_.options().frames_per_loop) + "-frame loop";
  }

  std::optional<CapturedFrame> next() override {
    const int slot = next_pose_;
    next_pose_ = (next_pose_ + 1) % poses_;
    if (cache_[slot].empty()) {
      const int index = slot * rig_.options().frames_per_loop / poses_;
      synthetic::SyntheticFrame frame = rig_.render(index, 8, 4);  // the panorama is not needed
      for (auto& camera : frame.cameras) cache_[slot].push_back(std::move(camera.rgb));
    }
    CapturedFrame out;
    for (const Rgb8Image& image : cache_[slot]) out.images.push_back(image.clone());
    stamp_all_cameras(out, status_);
    return out;
  }

  std::vector<CameraStatus> camera_status() const override { return status_; }

 private:
  synthetic::SyntheticRig rig_;
  int poses_;
  int next_pose_ = 0;
  std::vector<std::vector<Rgb8Image>> cache_;
  std::vector<CameraStatus> status_;
};

}  // namespace

std::unique_ptr<FrameSource> open_synthetic_source(const SourceOptions& options) {
  return std::make_unique<SyntheticSource>(options);
}

}  // namespace omnisweep::capture
