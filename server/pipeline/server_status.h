// The server's status (ServerStatus, docs/wire-format.md), assembled from what its stage threads
// report: per status window (a second) the mean time of each stage, frames in and out, drops by
// reason, the server's state and the cameras' health with each camera's frame rate. Stages
// report from their threads; the status thread takes one message per window.
#pragma once

#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "omnisweep/wire/wire.h"
#include "omnisweep_msgs.h"
#include "server/capture/frame_source.h"

namespace omnisweep::pipeline {

// What the status carries besides the board's counts.
struct StatusExtras {
  bool stopping = false;
  int matched_subscribers = 0;
  int color_quality = 0;
  std::uint64_t frames_over_budget = 0;
};

class StatusBoard {
 public:
  // `stages`: the stage names the status lists, in order (each 0 ms until it ran once).
  explicit StatusBoard(std::vector<std::string> stages);

  // The source's camera status before its first frame.
  void set_cameras(std::vector<capture::CameraStatus> cameras);
  void add_stage_time(const std::string& stage, double ms);
  void count_drop(const std::string& reason);
  // A frame captured, with the source's camera status after it; a frame published.
  void count_captured(std::vector<capture::CameraStatus> cameras);
  void count_published();
  // The source stalled (its camera status then) or ended; a stalled source delivering again
  // brings back running (or starting, before the first frame was published).
  void source_stalled(std::vector<capture::CameraStatus> cameras);
  void source_ended();
  // The first error wins; the state becomes failed.
  void fail(const std::string& error);

  wire::ServerState state() const;
  std::string error() const;

  // The status of the window that ends now; starts the next window. A stage without frames in
  // this window carries its latest mean (a server slower than one frame a second finishes none
  // in most windows, and a subscriber still learns what a frame costs).
  msg::ServerStatus take(std::uint64_t now_ns, const StatusExtras& extras);

 private:
  mutable std::mutex mutex_;
  std::vector<std::string> stages_;
  std::map<std::string, std::pair<double, int>> window_;  // sum ms, count this window
  std::map<std::string, double> last_ms_;                 // the latest window's mean with frames
  std::map<std::string, std::uint64_t> drops_;
  std::vector<capture::CameraStatus> cameras_;
  std::vector<std::uint64_t> camera_frames_before_;  // frames per camera at the last take()
  std::uint64_t captured_ = 0, published_ = 0, published_total_ = 0;
  wire::ServerState state_ = wire::ServerState::kStarting;
  std::string error_;
};

// The server's log line for a status: state, fps, stage times, drops, subscribers, frames
// published, colour quality, then `extra` (", Foxglove: ..." or empty).
std::string status_log_line(const msg::ServerStatus& status, std::uint64_t published,
                            const std::string& extra);

}  // namespace omnisweep::pipeline
