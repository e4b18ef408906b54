// A server's status (ServerStatus on <prefix>/status, docs/wire-format.md) as plain values, for
// apps and tools: no generated DDS type. wire::from_message (wire.h) makes one from a message.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace omnisweep::wire {

// The server's state, as its status messages carry it (ServerStatus.state).
enum class ServerState {
  kStarting,       // no frame published yet
  kRunning,        // publishing
  kSourceStalled,  // the source's cameras stopped delivering; the server waits for them
  kSourceEnded,    // a recording source reached its end
  kStopping,       // shutting down
  kFailed,         // a stage failed
};
// The state's text on the wire: "starting", "running", "source stalled", "source ended",
// "stopping", "failed".
std::string_view to_string(ServerState state);
// The state a status's text names; nullopt for text this SDK does not know (a newer server).
std::optional<ServerState> parse_server_state(std::string_view text);

struct CameraReport {
  int camera = 0;
  bool delivering = true;
  double fps = 0;                   // images over the last status window
  std::uint64_t last_frame_ns = 0;  // wall clock
  std::string message;              // empty when healthy
};

struct StatusReport {
  std::uint64_t time_ns = 0;               // when the server sent it (wall clock)
  std::string state;                       // as sent
  std::optional<ServerState> known_state;  // parse_server_state(state)
  double fps_in = 0, fps_out = 0;          // frames captured and published over the last second
  // Per stage ("capture", "depth", "stitch", "encode", "publish", "ros"), in the server's order:
  // the mean milliseconds per frame over the last second (the latest mean when none finished).
  std::vector<std::pair<std::string, double>> stage_ms;
  std::map<std::string, std::uint64_t> dropped;  // frames dropped by reason, since the start
  int matched_subscribers = 0;
  std::vector<CameraReport> cameras;
  int color_quality = 0;                 // JPEG quality of the last frame
  std::uint64_t frames_over_budget = 0;  // frames over the byte budget even at the floor quality
};

}  // namespace omnisweep::wire
