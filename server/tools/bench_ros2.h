// omnisweep-bench's ros2 section: what the ROS 2 topics cost the server per 2048x1024 frame.
#pragma once

#include "omnisweep/gpu/context.h"

namespace omnisweep::tools {

// Estimates the synthetic rig's 2048x1024 panorama at the defaults, encodes it as the stream
// does (JPEG quality 90, qinv16-zstd), then measures per ROS topic the CPU a frame costs with
// one subscriber (making the message from the stream's payloads and serialising it to CDR) and
// the message's size; and with no subscriber, the cost of RosPublisher::publish_frame on a
// participant where nothing reads (the check of the matched readers).
void ros2_section(gpu::Context& context, bool json);

}  // namespace omnisweep::tools
