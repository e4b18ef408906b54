// A dataset in the reference layout as a camera: its frames in natural order, looped. Frames
// that fail to load are skipped with a message (the dataset reports which file was wrong).
#include <cstdio>

#include "omnisweep/dataset/dataset.h"
#include "server/capture/sources.h"
#include "server/depth/depth_inputs.h"

namespace omnisweep::capture {
namespace {

class DatasetSource final : public FrameSource {
 public:
  explicit DatasetSource(const std::string& dir) : dataset_(open(dir)), dir_(dir) {
    if (dataset_.frames().empty()) throw SourceError("dataset " + dir + " has no frames");
    status_.resize(std::size_t(dataset_.rig().num_cameras()));
  }

  const Rig& rig() const override { return dataset_.rig(); }
  const DatasetHints* hints() const override { return &dataset_.hints(); }
  std::vector<std::optional<Gray8Image>> masks() const override {
    std::vector<std::optional<Gray8Image>> out;
    for (const auto& mask : dataset_.masks()) {
      if (mask)
        out.emplace_back(mask->clone());
      else
        out.emplace_back();
    }
    return out;
  }
  std::string description() const override {
    return "dataset " + dir_ + " (" + std::to_string(dataset_.frames().size()) + " frames, looped)";
  }

  std::optional<CapturedFrame> next() override {
    for (std::size_t attempt = 0; attempt < dataset_.frames().size(); ++attempt) {
      const std::string& name = dataset_.frames()[next_];
      next_ = (next_ + 1) % dataset_.frames().size();
      SkippedFrame skipped;
      std::optional<Frame> frame = dataset_.try_load_frame(name, &skipped);
      if (!frame) {
        std::fprintf(stderr, "omnisweep-server: skipping frame %s: %s\n", name.c_str(),
                     skipped.reason.c_str());
        continue;
      }
      CapturedFrame out;
      out.images = depth::rgb8_images(*frame);
      stamp_all_cameras(out, status_);
      return out;
    }
    throw SourceError("no frame of dataset " + dir_ + " loads");
  }

  std::vector<CameraStatus> camera_status() const override { return status_; }

 private:
  static Dataset open(const std::string& dir) {
    try {
      return Dataset::open(dir);
    } catch (const std::exception& e) {
      throw SourceError(e.what());
    }
  }

  Dataset dataset_;
  std::string dir_;
  std::size_t next_ = 0;
  std::vector<CameraStatus> status_;
};

}  // namespace

std::unique_ptr<FrameSource> open_dataset_source(const std::string& dir) {
  return std::make_unique<DatasetSource>(dir);
}

}  // namespace omnisweep::capture
