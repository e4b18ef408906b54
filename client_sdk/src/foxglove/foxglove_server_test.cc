// Foxglove's WebSocket protocol: client messages parsed or refused with a reason, the server's
// messages as the protocol lays them out, and a server that starts on a free port, refuses a
// taken one and stops cleanly. Clients talking to a running omnisweep-server are in
// tests/ros2_test.cc (Node, @foxglove/ws-protocol).
#include "omnisweep/foxglove/foxglove_server.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "omnisweep/foxglove/ros_channels.h"

namespace omnisweep::foxglove {
namespace {

std::string error_of(std::string_view text, std::size_t max_bytes = 65536) {
  const ClientMessage m = parse_client_message(text, max_bytes);
  const auto* e = std::get_if<ParseError>(&m);
  return e ? e->message : "";
}

TEST(FoxgloveProtocol, ParsesSubscribeAndUnsubscribe) {
  const ClientMessage s = parse_client_message(
      R"({"op":"subscribe","subscriptions":[{"id":0,"channelId":5},{"id":7,"channelId":9}]})");
  ASSERT_TRUE(std::holds_alternative<Subscribe>(s));
  EXPECT_EQ(std::get<Subscribe>(s).subscriptions,
            (std::vector<std::pair<std::uint32_t, std::uint32_t>>{{0, 5}, {7, 9}}));
  const ClientMessage u = parse_client_message(R"({"op":"unsubscribe","subscriptionIds":[7]})");
  ASSERT_TRUE(std::holds_alternative<Unsubscribe>(u));
  EXPECT_EQ(std::get<Unsubscribe>(u).subscriptions, std::vector<std::uint32_t>{7});
}

TEST(FoxgloveProtocol, BadMessagesAreErrorsThatSayWhy) {
  EXPECT_EQ(error_of("{not json"), "not valid JSON");
  EXPECT_EQ(error_of("[1,2]"), "not a JSON object");
  EXPECT_EQ(error_of(R"({"subscriptions":[]})"), "no \"op\" string");
  EXPECT_EQ(error_of(R"({"op":"advertise"})"),
            "op \"advertise\" is not supported (subscribe, unsubscribe)");
  EXPECT_EQ(error_of(R"({"op":"subscribe"})"), "subscribe: no \"subscriptions\" array");
  EXPECT_EQ(error_of(R"({"op":"subscribe","subscriptions":[{"id":-1,"channelId":1}]})"),
            "subscribe: each subscription needs integer \"id\" and \"channelId\"");
  EXPECT_EQ(error_of(R"({"op":"subscribe","subscriptions":[{"id":1,"channelId":"a"}]})"),
            "subscribe: each subscription needs integer \"id\" and \"channelId\"");
  EXPECT_EQ(error_of(R"({"op":"unsubscribe","subscriptionIds":[1.5]})"),
            "unsubscribe: subscription ids must be integers");
  EXPECT_EQ(error_of(std::string(100, ' '), 64), "message of 100 bytes; the limit is 64");
  EXPECT_EQ(error_of(std::string(100000, '[')), "message of 100000 bytes; the limit is 65536");
  EXPECT_EQ(error_of(std::string(40, '[') + std::string(40, ']')),
            "JSON nested deeper than 16 levels");
  // Brackets inside strings do not count as nesting.
  EXPECT_EQ(error_of(R"({"op":"x[[[[[[[[[[[[[[[[[[[[[[[[[["})"),
            "op \"x[[[[[[[[[[[[[[[[[[[[[[[[[[\" is not supported (subscribe, unsubscribe)");
}

TEST(FoxgloveProtocol, ServerMessagesAsTheProtocolLaysThemOut) {
  const auto data =
      message_data(0x01020304, 0x1122334455667788ull, std::vector<std::uint8_t>{9, 8});
  EXPECT_EQ(data, (std::vector<std::uint8_t>{1, 4, 3, 2, 1, 0x88, 0x77, 0x66, 0x55, 0x44, 0x33,
                                             0x22, 0x11, 9, 8}));
  const auto advertise = nlohmann::json::parse(advertise_json(ros_channels("/rig")));
  EXPECT_EQ(advertise["op"], "advertise");
  ASSERT_EQ(advertise["channels"].size(), 6u);
  const auto& color = advertise["channels"][0];
  EXPECT_EQ(color["topic"], "/rig/color/image_raw/compressed");
  EXPECT_EQ(color["encoding"], "cdr");
  EXPECT_EQ(color["schemaEncoding"], "ros2msg");
  EXPECT_EQ(color["schemaName"], "sensor_msgs/msg/CompressedImage");
  EXPECT_EQ(color["id"], int(dds::TopicKind::kRosColor));
  const auto status = nlohmann::json::parse(status_json(2, "bad \xff byte"));
  EXPECT_EQ(status["level"], 2);
  const auto info = nlohmann::json::parse(server_info_json("omnisweep", "s1"));
  EXPECT_EQ(info["op"], "serverInfo");
  EXPECT_TRUE(info["capabilities"].is_array());
}

TEST(FoxgloveServer, StartsOnAFreePortRefusesATakenOneAndStops) {
  FoxgloveOptions options;
  options.address = "127.0.0.1";
  options.port = 0;
  FoxgloveServer server(options, ros_channels("/rig"));
  EXPECT_GT(server.port(), 0);
  EXPECT_FALSE(server.subscribed(std::uint32_t(dds::TopicKind::kRosColor)));
  server.publish(std::uint32_t(dds::TopicKind::kRosTfStatic), 1, std::vector<std::uint8_t>{1},
                 /*latch=*/true);  // no client: nothing sent
  EXPECT_EQ(server.stats().sent, 0u);
  options.port = server.port();
  try {
    FoxgloveServer second(options, {});
    ADD_FAILURE() << "a second server listened on the same port";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(
        std::string(e.what()).find("cannot listen on 127.0.0.1:" + std::to_string(server.port())),
        std::string::npos)
        << e.what();
  }
  options.port = 70000;
  EXPECT_THROW(FoxgloveServer(options, {}), std::invalid_argument);
}

}  // namespace
}  // namespace omnisweep::foxglove
