// Where the server's camera frames come from. A source is named by a spec string:
//   synthetic            the synthetic rig moving through its scene (the default)
//   dataset:DIR          a dataset in the reference layout, looped
//   video:F0,F1,...      one video file per camera (OpenCV VideoCapture), looped
//   v4l2:/dev/videoN,... one V4L2 device per camera
//   gst:P0|P1|...        one GStreamer pipeline per camera, ending in appsink (Jetson CSI cameras)
// video, v4l2 and gst need --calibration (basalt JSON); synthetic and dataset bring their own.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "omnisweep/image/image.h"
#include "omnisweep/rig/rig.h"
#include "omnisweep/time/clock.h"

namespace omnisweep {
struct DatasetHints;  // omnisweep/dataset/dataset.h
}  // namespace omnisweep

namespace omnisweep::capture {

class SourceError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct CapturedFrame {
  std::vector<Rgb8Image> images;               // per camera, at the calibration's size
  std::vector<std::uint64_t> capture_time_ns;  // per camera, CLOCK_REALTIME
};

struct CameraStatus {
  bool delivering = true;
  std::uint64_t frames = 0;         // delivered since start
  std::uint64_t last_frame_ns = 0;  // CLOCK_REALTIME
  std::string message;              // empty when healthy
};

class FrameSource {
 public:
  virtual ~FrameSource() = default;
  virtual const Rig& rig() const = 0;
  virtual std::vector<std::optional<Gray8Image>> masks() const = 0;
  virtual std::string description() const = 0;
  // The next frame, blocking. nullopt: the source has nothing more (never for looped sources).
  // A camera that stops delivering keeps its last image and is reported by camera_status().
  // Throws SourceError when no camera delivers at all.
  virtual std::optional<CapturedFrame> next() = 0;
  virtual std::vector<CameraStatus> camera_status() const = 0;
  // Live cameras (v4l2, gst) keep capturing whether or not anyone reads them: the server drains
  // them and keeps the latest frame. Other sources (synthetic, dataset, video files) wait, so the
  // server reads them only when the depth stage has room for a frame.
  virtual bool live() const { return false; }
  // A dataset's dataset.json (references, viewpoint, distance range): the server's defaults.
  virtual const DatasetHints* hints() const { return nullptr; }
};

struct SourceOptions {
  std::string calibration;        // basalt JSON; required by video, v4l2 and gst
  int synthetic_poses = 30;       // distinct synthetic frames, spread over the rig's 300-frame loop
  double camera_timeout_s = 2.0;  // a camera silent this long counts as not delivering
  // Throws std::invalid_argument naming the field, its value and what is allowed.
  void check() const;
};

// The kinds of source a spec names: "synthetic", "dataset:DIR", "video:F0,F1,...",
// "v4l2:/dev/videoN,..." or "gst:PIPELINE|PIPELINE|...".
enum class SourceKind { kSynthetic, kDataset, kVideo, kV4l2, kGst };
std::string_view to_string(SourceKind kind);  // the spec's prefix: "synthetic", "dataset", ...

struct SourceSpec {
  SourceKind kind = SourceKind::kSynthetic;
  std::string location{};              // the dataset directory (dataset)
  std::vector<std::string> cameras{};  // one entry per camera (video, v4l2, gst)
};
// Throws SourceError naming the spec and what is wrong (unknown kind, an empty camera entry).
SourceSpec parse_source_spec(const std::string& spec);

// Opens the source named by `spec`; throws SourceError naming what failed (unknown kind,
// unreadable calibration, a camera that does not open, camera count != calibration).
std::unique_ptr<FrameSource> open_source(const std::string& spec, const SourceOptions& options);

// For sources whose cameras deliver together: every camera captured now, counted as delivering.
void stamp_all_cameras(CapturedFrame& frame, std::vector<CameraStatus>& status);

}  // namespace omnisweep::capture
