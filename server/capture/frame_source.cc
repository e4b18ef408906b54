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

std::string_view to_string(SourceKind kind) {
  switch (kind) {
    case SourceKind::kSynthetic:
      return "synthetic";
    case SourceKind::kDataset:
      return "dataset";
    case SourceKind::kVideo:
      return "video";
    case SourceKind::kV4l2:
      return "v4l2";
    case SourceKind::kGst:
      return "gst";
  }
  return "unknown";
}

SourceSpec parse_source_spec(const std::string& spec) {
  if (spec == to_string(SourceKind::kSynthetic)) return {};
  const std::size_t colon = spec.find(':');
  const std::string prefix = spec.substr(0, colon);
  const std::string rest = colon == std::string::npos ? "" : spec.substr(colon + 1);
  if (!rest.empty()) {
    if (prefix == to_string(SourceKind::kDataset))
      return {.kind = SourceKind::kDataset, .location = rest};
    for (const SourceKind kind : {SourceKind::kVideo, SourceKind::kV4l2, SourceKind::kGst}) {
      if (prefix != to_string(kind)) continue;
      SourceSpec parsed{.kind = kind, .cameras = split(rest, kind == SourceKind::kGst ? '|' : ',')};
      for (std::size_t i = 0; i < parsed.cameras.size(); ++i) {
        if (parsed.cameras[i].empty())
          throw SourceError("source \"" + spec + "\": camera " + std::to_string(i) + " is empty");
      }
      return parsed;
    }
  }
  throw SourceError("unknown source \"" + spec +
                    "\" (expected synthetic, dataset:DIR, video:F0,F1,..., "
                    "v4l2:/dev/videoN,... or gst:PIPELINE|PIPELINE|...)");
}

std::unique_ptr<FrameSource> open_source(const std::string& spec, const SourceOptions& options) {
  options.check();
  const SourceSpec parsed = parse_source_spec(spec);
  switch (parsed.kind) {
    case SourceKind::kSynthetic:
      return open_synthetic_source(options);
    case SourceKind::kDataset:
      return open_dataset_source(parsed.location);
    default:
      return open_video_source(parsed.kind, parsed.cameras, options);
  }
}

}  // namespace omnisweep::capture
