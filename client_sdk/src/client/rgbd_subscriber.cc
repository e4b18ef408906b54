#include "omnisweep/client/rgbd_subscriber.h"

#include <algorithm>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <mutex>

#include "omnisweep/dds/stream_subscriber.h"
#include "omnisweep/options/option_error.h"
#include "omnisweep/time/clock.h"
#include "omnisweep/wire/wire.h"

namespace omnisweep::client {

double RgbdFrame::latency_ms() const { return wire::latency_ms(capture_time_ns, decoded_time_ns); }

const char* to_string(ConnectionState state) {
  switch (state) {
    case ConnectionState::kNoServer:
      return "no server";
    case ConnectionState::kWaiting:
      return "waiting for the first frame";
    case ConnectionState::kReceiving:
      return "receiving";
    case ConnectionState::kStalled:
      return "stalled";
  }
  return "unknown";
}

void SubscriberOptions::check() const {
  if (!(stall_after_s > 0) || !std::isfinite(stall_after_s))
    throw option_error("SubscriberOptions", "stall_after_s", stall_after_s,
                       "a positive number of seconds");
  if (profile.empty())
    throw std::invalid_argument(
        "SubscriberOptions.profile is empty: must be \"live\", "
        "\"reliable\" or a data_reader profile of the QoS file");
}

namespace {

// The stream description as StreamInfo; throws wire::WireError naming the field at fault.
StreamInfo stream_info_from(const msg::StreamDescription& d) {
  StreamInfo info;
  info.topic_prefix = d.topic_prefix();
  info.revision = d.revision();
  info.rig = wire::rig_from_description(d);
  info.references.assign(d.references().begin(), d.references().end());
  info.panorama_width = int(d.panorama_width());
  info.panorama_height = int(d.panorama_height());
  info.viewpoint = {d.viewpoint().x(), d.viewpoint().y(), d.viewpoint().z()};
  info.color_codec = d.color_codec();
  info.distance_codec = d.distance_codec();
  info.distance_params = wire::from_message(d.distance_params());
  info.target_fps = d.target_fps();
  return info;
}

}  // namespace

struct RgbdSubscriber::Impl {
  Impl(const SubscriberOptions& options, FrameCallback on_frame);
  void on_frame(const msg::RgbdFrame& message);
  void on_description(const msg::StreamDescription& message);
  // The confidence of `m` if it has arrived: decoded, or empty (counted).
  FloatImage take_confidence(const msg::RgbdFrame& m);

  SubscriberOptions options_;
  FrameCallback callback_;
  mutable std::mutex mutex_;
  mutable std::condition_variable frame_arrived_;
  std::shared_ptr<const RgbdFrame> latest_;
  std::shared_ptr<const StreamInfo> stream_;
  SubscriberStats stats_;
  std::uint64_t frame_count_ = 0;
  wire::GapCounter gaps_;
  std::deque<msg::ConfidenceFrame> confidences_;  // the newest few, waiting for their frames
  std::chrono::steady_clock::time_point last_frame_time_;
  // When the last status arrived, whether it said "running", and the slowest stage's time in it:
  // a server slower than stall_after_s per frame is not stalled while it reports working.
  std::chrono::steady_clock::time_point last_status_time_;
  bool server_running_ = false;
  double server_frame_s_ = 0;
  std::unique_ptr<dds::StreamSubscriber> subscriber_;  // last: its callbacks use the above
};

RgbdSubscriber::RgbdSubscriber(const SubscriberOptions& options, FrameCallback on_frame)
    : impl_(std::make_unique<Impl>(options, std::move(on_frame))) {}

RgbdSubscriber::Impl::Impl(const SubscriberOptions& options, FrameCallback on_frame)
    : options_(options), callback_(std::move(on_frame)) {
  options.check();
  dds::StreamCallbacks callbacks;
  callbacks.frame = [this](const msg::RgbdFrame& m) { this->on_frame(m); };
  callbacks.description = [this](const msg::StreamDescription& m) { on_description(m); };
  callbacks.status = [this](const msg::ServerStatus& m) {
    double slowest_ms = 0;
    for (const auto& stage : m.stage_ms()) slowest_ms = std::max(slowest_ms, double(stage.ms()));
    const std::lock_guard lock(mutex_);
    last_status_time_ = std::chrono::steady_clock::now();
    server_running_ = wire::parse_server_state(m.state()) == wire::ServerState::kRunning;
    server_frame_s_ = slowest_ms * 1e-3;
  };
  std::vector<dds::TopicKind> topics = {dds::TopicKind::kDescription, dds::TopicKind::kStatus,
                                        dds::TopicKind::kFrames};
  if (options.confidence) {
    callbacks.confidence = [this](const msg::ConfidenceFrame& m) {
      const std::lock_guard lock(mutex_);
      confidences_.push_back(m);
      if (confidences_.size() > 4) confidences_.pop_front();
    };
    topics.push_back(dds::TopicKind::kConfidence);
  }
  subscriber_ = std::make_unique<dds::StreamSubscriber>(options.participant, options.profile,
                                                        std::move(callbacks), topics);
}

RgbdSubscriber::~RgbdSubscriber() { impl_->subscriber_.reset(); }

void RgbdSubscriber::Impl::on_description(const msg::StreamDescription& message) {
  try {
    auto info = std::make_shared<const StreamInfo>(stream_info_from(message));
    const std::lock_guard lock(mutex_);
    stream_ = std::move(info);
  } catch (const std::exception& e) {
    const std::lock_guard lock(mutex_);
    stats_.last_error = std::string("bad stream description: ") + e.what();
  }
}

FloatImage RgbdSubscriber::Impl::take_confidence(const msg::RgbdFrame& m) {
  std::optional<msg::ConfidenceFrame> found;
  {
    const std::lock_guard lock(mutex_);
    for (auto it = confidences_.begin(); it != confidences_.end(); ++it) {
      if (it->sequence_number() == m.sequence_number()) {
        found = std::move(*it);
        confidences_.erase(confidences_.begin(), it + 1);  // older ones have lost their frames
        break;
      }
    }
  }
  try {
    if (found)
      return codec::confidence_values(
          wire::decode_confidence(*found, int(m.width()), int(m.height())));
  } catch (const std::exception& e) {
    const std::lock_guard lock(mutex_);
    stats_.last_error =
        "confidence of frame " + std::to_string(m.sequence_number()) + ": " + e.what();
  }
  const std::lock_guard lock(mutex_);
  ++stats_.frames_without_confidence;
  return {};
}

void RgbdSubscriber::Impl::on_frame(const msg::RgbdFrame& m) {
  const std::uint64_t received = wall_clock_ns();
  const std::size_t bytes = m.color().data().size() + m.distance().data().size();
  {
    const std::lock_guard lock(mutex_);
    ++stats_.frames_received;
    stats_.bytes_received += bytes;
    stats_.frames_lost += gaps_.see(m.sequence_number());
    last_frame_time_ = std::chrono::steady_clock::now();
  }
  auto frame = std::make_shared<RgbdFrame>();
  try {
    wire::DecodedFrame decoded = wire::decode_frame(m);
    frame->color = std::move(decoded.rgb);
    frame->distance = std::move(decoded.distance);
    if (options_.confidence) frame->confidence = take_confidence(m);
  } catch (const std::exception& e) {
    const std::lock_guard lock(mutex_);
    ++stats_.decode_errors;
    stats_.last_error = "frame " + std::to_string(m.sequence_number()) + ": " + e.what();
    return;
  }
  frame->sequence_number = m.sequence_number();
  frame->description_revision = m.description_revision();
  frame->viewpoint = {m.viewpoint().x(), m.viewpoint().y(), m.viewpoint().z()};
  frame->capture_time_ns.assign(m.capture_time_ns().begin(), m.capture_time_ns().end());
  frame->processing_start_ns = m.processing_start_ns();
  frame->processing_end_ns = m.processing_end_ns();
  frame->publish_time_ns = m.publish_time_ns();
  frame->receive_time_ns = received;
  frame->color_bytes = m.color().data().size();
  frame->distance_bytes = m.distance().data().size();
  frame->decoded_time_ns = wall_clock_ns();
  {
    const std::lock_guard lock(mutex_);
    if (stream_ && stream_->revision == frame->description_revision) frame->stream = stream_;
    latest_ = frame;
    ++stats_.frames_decoded;
    ++frame_count_;
  }
  frame_arrived_.notify_all();
  if (callback_) callback_(frame);
}

std::shared_ptr<const RgbdFrame> RgbdSubscriber::latest_frame() const {
  const std::lock_guard lock(impl_->mutex_);
  return impl_->latest_;
}

std::shared_ptr<const RgbdFrame> RgbdSubscriber::wait_for_frame(
    std::chrono::milliseconds timeout) const {
  Impl& i = *impl_;
  std::unique_lock lock(i.mutex_);
  const std::uint64_t seen = i.frame_count_;
  if (!i.frame_arrived_.wait_for(lock, timeout, [&] { return i.frame_count_ > seen; }))
    return nullptr;
  return i.latest_;
}

std::shared_ptr<const StreamInfo> RgbdSubscriber::stream_info() const {
  const std::lock_guard lock(impl_->mutex_);
  return impl_->stream_;
}

std::optional<wire::StatusReport> RgbdSubscriber::status() const {
  return wire::from_message(impl_->subscriber_->status());
}

int RgbdSubscriber::matched_servers() const { return impl_->subscriber_->matched_servers(); }

ConnectionState connection_state(const ConnectionInputs& in, double stall_after_s) {
  if (in.frames_received > 0) {
    double allowed = stall_after_s;
    // A running server still reporting (status comes once a second) whose slowest stage takes
    // longer than that: a frame is due within about one frame time (the stages overlap).
    if (in.server_running && in.since_status_s < stall_after_s)
      allowed = std::max(allowed, 2.0 * in.server_frame_s + 1.0);
    if (in.since_frame_s < allowed) return ConnectionState::kReceiving;
  }
  if (in.matched_servers == 0) return ConnectionState::kNoServer;
  return in.frames_received > 0 ? ConnectionState::kStalled : ConnectionState::kWaiting;
}

ConnectionState RgbdSubscriber::state() const {
  const Impl& i = *impl_;
  const int matched = i.subscriber_->matched_servers();
  const std::lock_guard lock(i.mutex_);
  const auto now = std::chrono::steady_clock::now();
  return connection_state(
      {.frames_received = i.stats_.frames_received,
       .since_frame_s = std::chrono::duration<double>(now - i.last_frame_time_).count(),
       .since_status_s = std::chrono::duration<double>(now - i.last_status_time_).count(),
       .server_running = i.server_running_,
       .server_frame_s = i.server_frame_s_,
       .matched_servers = matched},
      i.options_.stall_after_s);
}

SubscriberStats RgbdSubscriber::stats() const {
  const std::lock_guard lock(impl_->mutex_);
  return impl_->stats_;
}

}  // namespace omnisweep::client
