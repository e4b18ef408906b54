// Subscribes to one omnisweep stream (a server's three topics) and hands every message to
// callbacks on Fast DDS's listener thread. The description (calibration) is TRANSIENT_LOCAL, so
// a subscriber started after the server still receives it.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "omnisweep/dds/participant.h"
#include "omnisweep_msgs.h"

namespace eprosima::fastdds::dds {
class DataReader;
}  // namespace eprosima::fastdds::dds

namespace omnisweep::dds {

struct StreamCallbacks {
  std::function<void(const msg::StreamDescription&)> description;
  std::function<void(const msg::RgbdFrame&)> frame;
  std::function<void(const msg::ServerStatus&)> status;
  std::function<void(const msg::ConfidenceFrame&)> confidence;  // with TopicKind::kConfidence
};

class StreamSubscriber {
 public:
  // `frame_profile`: "live" (best effort, newest frames; viewers) or "reliable" (every frame,
  // retransmitted; recorders), or the name of a data_reader profile in the QoS file.
  // `topics`: which of the stream's topics to read (a monitoring identity may be allowed only
  // the status; the optional confidence is read only when listed, with the frame's profile). Throws
  // DdsError naming the topic whose reader cannot be created (with DDS Security: not permitted).
  StreamSubscriber(const ParticipantOptions& options, const std::string& frame_profile,
                   StreamCallbacks callbacks,
                   std::vector<TopicKind> topics = {TopicKind::kDescription, TopicKind::kStatus,
                                                    TopicKind::kFrames});
  ~StreamSubscriber();
  StreamSubscriber(const StreamSubscriber&) = delete;
  StreamSubscriber& operator=(const StreamSubscriber&) = delete;

  std::optional<msg::StreamDescription> description() const;
  std::optional<msg::ServerStatus> status() const;
  std::uint64_t frames_received() const { return frames_; }
  // Frame writers (servers) currently matched.
  int matched_servers() const { return matched_; }

 private:
  class Listener;
  std::unique_ptr<Participant> participant_;
  std::unique_ptr<Listener> listener_;
  StreamCallbacks callbacks_;
  mutable std::mutex mutex_;
  std::optional<msg::StreamDescription> description_;
  std::optional<msg::ServerStatus> status_;
  std::atomic<std::uint64_t> frames_{0};
  std::atomic<int> matched_{0};
  std::array<eprosima::fastdds::dds::DataReader*, kTopics.size()> readers_{};
};

// "live" -> "omnisweep_live", "reliable" -> "omnisweep_reliable"; other names unchanged.
std::string frame_reader_profile(const std::string& name);

}  // namespace omnisweep::dds
