// The ROS 2 topics on a Foxglove WebSocket server: one channel per ROS topic (channel id = the
// topic's index in dds::kTopics), its schema the complete .msg definition, its messages the
// same CDR a DDS reader gets.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "omnisweep/dds/participant.h"
#include "omnisweep/foxglove/foxglove_server.h"
#include "omnisweep/ros2/ros_messages.h"

namespace omnisweep::foxglove {

std::vector<Channel> ros_channels(const std::string& ros_namespace);
// The frame topics some client subscribes to.
ros2::WantedTopics wanted(const FoxgloveServer& server);
// The messages of a frame to their subscribers.
void publish(FoxgloveServer& server, const ros2::FrameMessages& messages);
// One message as CDR on a ROS topic's channel (/tf_static is latched: later subscribers get it).
void publish(FoxgloveServer& server, dds::TopicKind kind, std::uint64_t timestamp_ns,
             std::span<const std::uint8_t> cdr);

}  // namespace omnisweep::foxglove
