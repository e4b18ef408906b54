// A server status as a loaded server sends it, for the tests of what is made from one
// (wire::from_message, the ROS 2 /diagnostics): one stage time, one drop reason, and camera 1 not
// delivering ("no image for 2 s").
#pragma once

#include <cstdint>
#include <string>

#include "omnisweep/wire/wire.h"

namespace omnisweep::testing {

inline msg::ServerStatus status_message(const std::string& state, float fps_out, float depth_ms,
                                        std::uint32_t encoder_busy_drops) {
  msg::ServerStatus m;
  m.state(state);
  m.fps_out(fps_out);
  msg::StageTime depth;
  depth.stage("depth");
  depth.ms(depth_ms);
  m.stage_ms({depth});
  msg::DropCount drop;
  drop.reason("encoder busy");
  drop.count(encoder_busy_drops);
  m.dropped({drop});
  msg::CameraHealth camera;
  camera.camera(1);
  camera.delivering(false);
  camera.message("no image for 2 s");
  m.cameras({camera});
  return m;
}

}  // namespace omnisweep::testing
