// The source implementations behind open_source.
#pragma once

#include "server/capture/frame_source.h"

namespace omnisweep::capture {

std::unique_ptr<FrameSource> open_synthetic_source(const SourceOptions& options);
std::unique_ptr<FrameSource> open_dataset_source(const std::string& dir);
// kind: kVideo, kV4l2 or kGst; one OpenCV VideoCapture per entry.
std::unique_ptr<FrameSource> open_video_source(SourceKind kind,
                                               const std::vector<std::string>& entries,
                                               const SourceOptions& options);

}  // namespace omnisweep::capture
