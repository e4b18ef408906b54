// The client SDK's subscriber: joins a server's stream (domain, topic prefix, QoS profile),
// decodes every frame it receives into colour and distance panoramas, and offers them by
// callback or by polling the latest, with the calibration, the server's status and the
// connection state. docs/client-sdk.md shows it in use.
//
//   client::RgbdSubscriber subscriber({.participant = {.domain = 0}});
//   if (auto frame = subscriber.wait_for_frame(std::chrono::seconds(5)))
//     use(frame->color, frame->distance, frame->stream->rig);
#pragma once

#include <Eigen/Core>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "omnisweep/codec/codec.h"
#include "omnisweep/dds/participant.h"
#include "omnisweep/image/image.h"
#include "omnisweep/rig/rig.h"
#include "omnisweep/wire/frame_stats.h"
#include "omnisweep/wire/server_status.h"

namespace omnisweep::client {

// The stream description (calibration and stream parameters), decoded.
struct StreamInfo {
  std::string topic_prefix;
  std::uint64_t revision = 0;
  Rig rig;
  std::vector<int> references;
  int panorama_width = 0;
  int panorama_height = 0;
  Eigen::Vector3d viewpoint = Eigen::Vector3d::Zero();  // rig frame, metres
  std::string color_codec;
  std::string distance_codec;
  codec::DistanceParams distance_params;
  double target_fps = 0;
};

// One decoded RGB-D frame. Times are wall-clock nanoseconds (omnisweep/time/clock.h).
struct RgbdFrame {
  std::uint64_t sequence_number = 0;  // consecutive per server run; gaps are frames lost
  std::uint64_t description_revision = 0;
  Rgb8Image color;      // equirectangular, ALGORITHM.md §5
  FloatImage distance;  // metres from the viewpoint, 0 = no value
  // Per pixel in [0, 1], how far to trust `distance` (docs/accuracy.md); empty unless
  // SubscriberOptions::confidence asked for it and the server publishes it (--confidence).
  FloatImage confidence;
  Eigen::Vector3d viewpoint = Eigen::Vector3d::Zero();  // rig frame
  std::shared_ptr<const StreamInfo> stream;    // the matching description; null until received
  std::vector<std::uint64_t> capture_time_ns;  // per camera
  std::uint64_t processing_start_ns = 0;
  std::uint64_t processing_end_ns = 0;
  std::uint64_t publish_time_ns = 0;
  std::uint64_t receive_time_ns = 0;
  std::uint64_t decoded_time_ns = 0;
  std::size_t color_bytes = 0;  // payload sizes as received
  std::size_t distance_bytes = 0;

  // Capture (the earliest camera) to decoded here, milliseconds.
  double latency_ms() const;
};

enum class ConnectionState {
  kNoServer,   // no server's frame writer is matched
  kWaiting,    // a server is matched and no frame has arrived yet (it may still be computing
               // its first: status() says what it is doing)
  kReceiving,  // a frame arrived within SubscriberOptions::stall_after_s, or within twice the
               // per-frame time of a running server that keeps sending status (a slow device)
  kStalled,    // frames arrived, then stopped, while a server is still matched
};
const char* to_string(ConnectionState state);

// What the subscriber's state is decided from (RgbdSubscriber::state): the stream's state machine
// as a plain function, so it is tested without DDS.
struct ConnectionInputs {
  std::uint64_t frames_received = 0;
  double since_frame_s = 0;     // since the last frame arrived
  double since_status_s = 0;    // since the last status arrived
  bool server_running = false;  // the last status said "running"
  double server_frame_s = 0;    // the slowest stage's time in that status
  int matched_servers = 0;
};
// kNoServer: no server matched and nothing arriving. kWaiting: matched, no frame yet.
// kReceiving: a frame within stall_after_s, or, while a running server keeps reporting, within
// about two of its frame times plus a second (a server slower than stall_after_s per frame is not
// stalled). kStalled: frames came, then stopped, the server still matched.
ConnectionState connection_state(const ConnectionInputs& in, double stall_after_s);

struct SubscriberOptions {
  dds::ParticipantOptions participant;
  std::string profile = "live";  // "live", "reliable" or a data_reader profile of the QoS file
  double stall_after_s = 2.0;
  // Also read <prefix>/confidence and attach each frame's confidence (RgbdFrame::confidence).
  bool confidence = false;

  // Throws std::invalid_argument naming the field, its value and what is allowed (the
  // participant's options throw dds::DdsError from ParticipantOptions::check).
  void check() const;
};

struct SubscriberStats {
  std::uint64_t frames_received = 0;
  std::uint64_t frames_decoded = 0;
  std::uint64_t decode_errors = 0;  // corrupt or mismatched payloads, dropped
  std::uint64_t frames_lost = 0;    // gaps in sequence numbers
  // With SubscriberOptions::confidence: frames whose confidence had not arrived (or was corrupt)
  // when they did; they come without one.
  std::uint64_t frames_without_confidence = 0;
  std::uint64_t bytes_received = 0;
  std::string last_error;
};

class RgbdSubscriber {
 public:
  using FrameCallback = std::function<void(const std::shared_ptr<const RgbdFrame>&)>;

  // Throws dds::DdsError naming what failed (bad option, QoS profile, DDS entity).
  // `on_frame` runs on Fast DDS's listener thread for every decoded frame.
  explicit RgbdSubscriber(const SubscriberOptions& options, FrameCallback on_frame = {});
  ~RgbdSubscriber();
  RgbdSubscriber(const RgbdSubscriber&) = delete;
  RgbdSubscriber& operator=(const RgbdSubscriber&) = delete;

  // Polling: the newest decoded frame, or null.
  std::shared_ptr<const RgbdFrame> latest_frame() const;
  // Blocks until a frame decoded after this call arrives; null after `timeout`.
  std::shared_ptr<const RgbdFrame> wait_for_frame(std::chrono::milliseconds timeout) const;

  std::shared_ptr<const StreamInfo> stream_info() const;  // null until received
  std::optional<wire::StatusReport> status() const;       // the server's newest status
  ConnectionState state() const;
  SubscriberStats stats() const;
  int matched_servers() const;

 private:
  struct Impl;  // the DDS side (client_sdk/src/client/rgbd_subscriber.cc): no DDS type here
  std::unique_ptr<Impl> impl_;
};

}  // namespace omnisweep::client
