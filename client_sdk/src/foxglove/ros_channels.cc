#include "omnisweep/foxglove/ros_channels.h"

#include "omnisweep/ros2/ros_schema.h"

namespace omnisweep::foxglove {

using dds::TopicKind;

std::vector<Channel> ros_channels(const std::string& ros_namespace) {
  std::vector<Channel> channels;
  for (const dds::TopicSpec& spec : dds::kTopics) {
    if (dds::is_stream_topic(spec.kind)) continue;
    Channel c;
    c.id = std::uint32_t(spec.kind);
    c.topic = ros2::ros_topic(ros_namespace, spec.kind);
    c.schema_name = ros2::ros_type(spec.kind);
    c.schema = ros2::message_definition(c.schema_name);
    channels.push_back(std::move(c));
  }
  return channels;
}

ros2::WantedTopics wanted(const FoxgloveServer& server) {
  const auto on = [&](TopicKind kind) { return server.subscribed(std::uint32_t(kind)); };
  return {on(TopicKind::kRosColor), on(TopicKind::kRosCompressedDepth), on(TopicKind::kRosDistance),
          on(TopicKind::kRosPoints)};
}

void publish(FoxgloveServer& server, TopicKind kind, std::uint64_t timestamp_ns,
             std::span<const std::uint8_t> cdr) {
  server.publish(std::uint32_t(kind), timestamp_ns, cdr, kind == TopicKind::kRosTfStatic);
}

void publish(FoxgloveServer& server, const ros2::FrameMessages& m) {
  const auto send = [&](TopicKind kind, const auto& message) {
    if (!message || !server.subscribed(std::uint32_t(kind))) return;
    publish(server, kind, ros2::stamp_ns(message->header().stamp()), ros2::to_cdr(*message));
  };
  send(TopicKind::kRosColor, m.color);
  send(TopicKind::kRosCompressedDepth, m.compressed_depth);
  send(TopicKind::kRosDistance, m.distance);
  send(TopicKind::kRosPoints, m.points);
}

}  // namespace omnisweep::foxglove
