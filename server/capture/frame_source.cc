#include <chrono>
#include <cmath>

#include "omnisweep/options/option_error.h"
#include "omnisweep/options/split.h"
#include "server/capture/sources.h"

namespace omnisweep::capture {

void stamp_all_cameras(CapturedFrame& frame, std::vector<CameraStatus>& status) {
  const std::uint64_t t = wall_clock_ns();
  frame.capture_time_ns.assign(frame.images.size(), t);
  for (auto& s : status) {
    ++s.frames;
    s.last_frame_ns = t;
  }
}

void SourceOptions::check() const {
  if (synthetic_poses < 1 || synthetic_poses > 100000)
    throw option_error("SourceOptions", "synthetic_poses", synthetic_poses, "within [1, 100000]");
  if (!(camera_timeout_s > 0) || !std::isfinite(camera_timeout_s))
    throw option_error("SourceOptions", "camera_timeout_s", camera_timeout_s,
                       "a positive number of seconds");
}

std::unique_ptr<FrameSource> open_source(const std::string& spec, const SourceOptions& options) {
  options.check();
  if (spec == "synthetic") return open_synthetic_source(options);
  const std::size_t colon = spec.find(':');
  const std::string kind = spec.substr(0, colon);
  const std::string rest = colon == std::string::npos ? "" : spec.substr(colon + 1);
  if (kind == "dataset" && !rest.empty()) return open_dataset_source(rest);
  if ((kind == "video" || kind == "v4l2" || kind == "gst") && !rest.empty()) {
    std::vector<std::string> entries = split(rest, kind == "gst" ? '|' : ',');
    for (std::size_t i = 0; i < entries.size(); ++i) {
      if (entries[i].empty())
        throw SourceError("source \"" + spec + "\": camera " + std::to_string(i) + " is empty");
    }
    return open_video_source(kind, entries, options);
  }
  throw SourceError("unknown source \"" + spec +
                    "\" (expected synthetic, dataset:DIR, video:F0,F1,..., "
                    "v4l2:/dev/videoN,... or gst:PIPELINE|PIPELINE|...)");
}

}  // namespace omnisweep::capture
