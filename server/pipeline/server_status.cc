#include "server/pipeline/server_status.h"

#include <cstdio>
#include <utility>

namespace omnisweep::pipeline {

StatusBoard::StatusBoard(std::vector<std::string> stages) : stages_(std::move(stages)) {}

void StatusBoard::set_cameras(std::vector<capture::CameraStatus> cameras) {
  const std::lock_guard lock(mutex_);
  cameras_ = std::move(cameras);
}

void StatusBoard::add_stage_time(const std::string& stage, double ms) {
  const std::lock_guard lock(mutex_);
  auto& [sum, count] = window_[stage];
  sum += ms;
  ++count;
}

void StatusBoard::count_drop(const std::string& reason) {
  const std::lock_guard lock(mutex_);
  ++drops_[reason];
}

void StatusBoard::count_captured(std::vector<capture::CameraStatus> cameras) {
  const std::lock_guard lock(mutex_);
  cameras_ = std::move(cameras);
  ++captured_;
  if (state_ == wire::ServerState::kSourceStalled)
    state_ = published_total_ > 0 ? wire::ServerState::kRunning : wire::ServerState::kStarting;
}

void StatusBoard::count_published() {
  const std::lock_guard lock(mutex_);
  ++published_;
  ++published_total_;
  if (state_ == wire::ServerState::kStarting) state_ = wire::ServerState::kRunning;
}

void StatusBoard::source_stalled(std::vector<capture::CameraStatus> cameras) {
  const std::lock_guard lock(mutex_);
  cameras_ = std::move(cameras);
  if (state_ != wire::ServerState::kFailed) state_ = wire::ServerState::kSourceStalled;
}

void StatusBoard::source_ended() {
  const std::lock_guard lock(mutex_);
  if (state_ != wire::ServerState::kFailed) state_ = wire::ServerState::kSourceEnded;
}

void StatusBoard::fail(const std::string& error) {
  const std::lock_guard lock(mutex_);
  if (error_.empty()) error_ = error;
  state_ = wire::ServerState::kFailed;
}

wire::ServerState StatusBoard::state() const {
  const std::lock_guard lock(mutex_);
  return state_;
}

std::string StatusBoard::error() const {
  const std::lock_guard lock(mutex_);
  return error_;
}

msg::ServerStatus StatusBoard::take(std::uint64_t now_ns, const StatusExtras& extras) {
  msg::ServerStatus s;
  s.time_ns(now_ns);
  s.matched_subscribers(extras.matched_subscribers);
  s.color_quality(extras.color_quality);
  s.frames_over_budget(extras.frames_over_budget);
  const std::lock_guard lock(mutex_);
  s.state(std::string(wire::to_string(extras.stopping ? wire::ServerState::kStopping : state_)));
  s.fps_in(float(captured_));
  s.fps_out(float(published_));
  captured_ = published_ = 0;
  std::vector<msg::StageTime> stages;
  for (const std::string& name : stages_) {
    const auto it = window_.find(name);
    if (it != window_.end()) last_ms_[name] = it->second.first / it->second.second;
    const auto last = last_ms_.find(name);
    msg::StageTime t;
    t.stage(name);
    t.ms(last == last_ms_.end() ? 0.0f : float(last->second));
    stages.push_back(t);
  }
  window_.clear();
  s.stage_ms(stages);
  std::vector<msg::DropCount> dropped;
  for (const auto& [reason, count] : drops_) {
    msg::DropCount d;
    d.reason(reason);
    d.count(count);
    dropped.push_back(d);
  }
  s.dropped(dropped);
  // Each camera's fps over the window, from the source's frame counters.
  std::vector<msg::CameraHealth> cameras;
  const bool counted = camera_frames_before_.size() == cameras_.size();
  for (std::size_t i = 0; i < cameras_.size(); ++i) {
    msg::CameraHealth h;
    h.camera(std::int32_t(i));
    h.delivering(cameras_[i].delivering);
    h.last_frame_ns(cameras_[i].last_frame_ns);
    h.message(cameras_[i].message);
    h.fps(counted ? float(cameras_[i].frames - camera_frames_before_[i]) : 0.0f);
    cameras.push_back(h);
  }
  camera_frames_before_.clear();
  for (const auto& c : cameras_) camera_frames_before_.push_back(c.frames);
  s.cameras(cameras);
  return s;
}

std::string status_log_line(const msg::ServerStatus& status, std::uint64_t published,
                            const std::string& extra) {
  std::string stages;
  for (const auto& t : status.stage_ms()) {
    char buf[64];
    std::snprintf(buf, sizeof buf, " %s %.0f", t.stage().c_str(), t.ms());
    stages += buf;
  }
  std::uint64_t drops = 0;
  for (const auto& d : status.dropped()) drops += d.count();
  char line[512];
  std::snprintf(line, sizeof line,
                "%s, %.0f fps in, %.0f fps out, ms:%s, %llu dropped, %d subscribers, %llu "
                "published, colour quality %d",
                status.state().c_str(), status.fps_in(), status.fps_out(), stages.c_str(),
                static_cast<unsigned long long>(drops), status.matched_subscribers(),
                static_cast<unsigned long long>(published), status.color_quality());
  return line + extra;
}

}  // namespace omnisweep::pipeline
