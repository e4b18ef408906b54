// Cameras through OpenCV's VideoCapture: video files (looped), V4L2 devices and GStreamer
// pipelines (how a Jetson reads its CSI cameras: nvarguscamerasrc ... ! appsink).
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "omnisweep/rig/basalt_calibration.h"
#include "server/capture/sources.h"

namespace omnisweep::capture {
namespace {

class VideoSource final : public FrameSource {
 public:
  VideoSource(SourceKind kind, const std::vector<std::string>& entries,
              const SourceOptions& options)
      : kind_(kind),
        name_(to_string(kind)),
        entries_(entries),
        timeout_ns_(std::uint64_t(options.camera_timeout_s * 1e9)) {
    if (options.calibration.empty())
      throw SourceError("source " + name_ + ": needs --calibration (basalt JSON)");
    try {
      rig_ = read_basalt_calibration(options.calibration);
    } catch (const std::exception& e) {
      throw SourceError(e.what());
    }
    if (int(entries.size()) != rig_.num_cameras()) {
      throw SourceError("source " + name_ + " names " + std::to_string(entries.size()) +
                        " cameras, the calibration " + options.calibration + " has " +
                        std::to_string(rig_.num_cameras()));
    }
    const int api = kind == SourceKind::kV4l2  ? cv::CAP_V4L2
                    : kind == SourceKind::kGst ? cv::CAP_GSTREAMER
                                               : cv::CAP_ANY;
    for (std::size_t i = 0; i < entries.size(); ++i) {
      captures_.emplace_back(entries[i], api);
      if (!captures_.back().isOpened()) {
        throw SourceError("camera " + std::to_string(i) + " (" + name_ + " " + entries[i] +
                          ") does not open");
      }
    }
    status_.resize(entries.size());
    last_.resize(entries.size());
    last_time_.assign(entries.size(), 0);
  }

  const Rig& rig() const override { return rig_; }
  std::vector<std::optional<Gray8Image>> masks() const override {
    std::vector<std::optional<Gray8Image>> none;
    none.resize(entries_.size());
    return none;
  }
  std::string description() const override {
    return name_ + " source with " + std::to_string(entries_.size()) + " cameras";
  }
  bool live() const override { return kind_ != SourceKind::kVideo; }

  std::optional<CapturedFrame> next() override {
    // Grab every camera first, then decode, so the images are as close in time as possible.
    std::vector<bool> grabbed(captures_.size());
    for (std::size_t i = 0; i < captures_.size(); ++i) {
      grabbed[i] = captures_[i].grab();
      if (!grabbed[i] && kind_ == SourceKind::kVideo) {  // end of file: loop
        captures_[i].set(cv::CAP_PROP_POS_FRAMES, 0);
        grabbed[i] = captures_[i].grab();
      }
    }
    const std::uint64_t t = wall_clock_ns();
    int delivering = 0;
    for (std::size_t i = 0; i < captures_.size(); ++i) {
      cv::Mat bgr;
      CameraStatus& s = status_[i];
      if (grabbed[i] && captures_[i].retrieve(bgr) && !bgr.empty()) {
        const RigCamera& cam = rig_.cameras[i];
        if (bgr.cols != cam.width || bgr.rows != cam.height) {
          throw SourceError("camera " + std::to_string(i) + " (" + entries_[i] + ") delivers " +
                            std::to_string(bgr.cols) + "x" + std::to_string(bgr.rows) +
                            ", its calibration is " + std::to_string(cam.width) + "x" +
                            std::to_string(cam.height));
        }
        if (bgr.channels() == 1) cv::cvtColor(bgr, bgr, cv::COLOR_GRAY2BGR);
        Rgb8Image rgb(bgr.cols, bgr.rows);
        cv::Mat view(bgr.rows, bgr.cols, CV_8UC3, rgb.data());
        cv::cvtColor(bgr, view, cv::COLOR_BGR2RGB);
        last_[i] = std::move(rgb);
        last_time_[i] = t;
        if (!s.delivering) std::fprintf(stderr, "omnisweep-server: camera %zu delivers again\n", i);
        s.delivering = true;
        s.message.clear();
        ++s.frames;
        s.last_frame_ns = t;
      } else if (s.delivering && (last_time_[i] == 0 || t - last_time_[i] > timeout_ns_ ||
                                  kind_ == SourceKind::kVideo)) {
        s.delivering = false;
        s.message = "no image from " + entries_[i];
        std::fprintf(stderr, "omnisweep-server: camera %zu (%s) stopped delivering\n", i,
                     entries_[i].c_str());
      }
      if (s.delivering) ++delivering;
    }
    for (std::size_t i = 0; i < captures_.size(); ++i) {
      if (last_[i].empty()) {
        if (delivering == 0) throw SourceError("no camera of the " + name_ + " source delivers");
        throw SourceError("camera " + std::to_string(i) + " (" + entries_[i] +
                          ") has not delivered a first image");
      }
    }
    if (delivering == 0) throw SourceError("no camera of the " + name_ + " source delivers");
    CapturedFrame out;
    for (const Rgb8Image& image : last_) out.images.push_back(image.clone());
    out.capture_time_ns = last_time_;
    return out;
  }

  std::vector<CameraStatus> camera_status() const override { return status_; }

 private:
  SourceKind kind_;
  std::string name_;  // to_string(kind_), for messages
  std::vector<std::string> entries_;
  std::uint64_t timeout_ns_;
  Rig rig_;
  std::vector<cv::VideoCapture> captures_;
  std::vector<CameraStatus> status_;
  std::vector<Rgb8Image> last_;
  std::vector<std::uint64_t> last_time_;
};

}  // namespace

std::unique_ptr<FrameSource> open_video_source(SourceKind kind,
                                               const std::vector<std::string>& entries,
                                               const SourceOptions& options) {
  return std::make_unique<VideoSource>(kind, entries, options);
}

}  // namespace omnisweep::capture
