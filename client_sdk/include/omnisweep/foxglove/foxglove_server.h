// A Foxglove WebSocket server (the foxglove.websocket.v1 protocol, also offered as
// foxglove.sdk.v1, the name foxglove_bridge 3.2+ uses): Foxglove and its forks connect to a
// running omnisweep-server or omnisweep-play and see the ROS 2 topics live, nothing installed on
// the robot (docs/ros2.md). It advertises its channels, sends only what a client subscribed to,
// and gives each client a bounded send queue, so a slow or stalled client loses messages and
// never holds up the server or another client. Bad client messages get a status message back.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

namespace omnisweep::foxglove {

inline constexpr const char* kSubprotocol = "foxglove.websocket.v1";
inline constexpr const char* kSdkSubprotocol = "foxglove.sdk.v1";

struct Channel {
  std::uint32_t id = 0;
  std::string topic;
  std::string encoding = "cdr";
  std::string schema_name;
  std::string schema;
  std::string schema_encoding = "ros2msg";
};

// What a client may send (the rest is a ParseError naming what was wrong).
struct Subscribe {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> subscriptions;  // (subscription, channel)
};
struct Unsubscribe {
  std::vector<std::uint32_t> subscriptions;
};
struct ParseError {
  std::string message;
};
using ClientMessage = std::variant<Subscribe, Unsubscribe, ParseError>;
// Parses one text message from a client. Never throws; text over `max_bytes` or nested deeper
// than 16 levels is a ParseError without being parsed.
ClientMessage parse_client_message(std::string_view text, std::size_t max_bytes = 65536);

// Server messages.
std::string server_info_json(const std::string& name, const std::string& session);
std::string advertise_json(const std::vector<Channel>& channels);
std::string status_json(int level, const std::string& message);  // 0 info, 1 warning, 2 error
// A binary message-data frame: opcode 1, uint32 subscription id, uint64 timestamp (ns), payload.
std::vector<std::uint8_t> message_data(std::uint32_t subscription, std::uint64_t timestamp_ns,
                                       std::span<const std::uint8_t> payload);

struct FoxgloveOptions {
  std::string address = "0.0.0.0";             // every interface: Foxglove runs on another machine
  int port = 8765;                             // Foxglove's default; 0 = any free port
  std::size_t client_queue_bytes = 16u << 20;  // unsent bytes per client before it loses messages
  std::size_t max_client_message_bytes = 65536;
  std::string name = "omnisweep";

  void check() const;  // throws std::invalid_argument naming the field
};

struct FoxgloveStats {
  std::size_t clients = 0;
  std::uint64_t sent = 0;     // messages sent to clients
  std::uint64_t dropped = 0;  // messages a slow client lost
  std::uint64_t refused = 0;  // bad client messages answered with a status
};

class WebSocketServer;

class FoxgloveServer {
 public:
  // Starts listening; throws std::runtime_error naming the address when it cannot.
  FoxgloveServer(const FoxgloveOptions& options, std::vector<Channel> channels);
  ~FoxgloveServer();  // closes every client and stops
  FoxgloveServer(const FoxgloveServer&) = delete;
  FoxgloveServer& operator=(const FoxgloveServer&) = delete;

  int port() const;
  // True while some client subscribes to the channel.
  bool subscribed(std::uint32_t channel) const;
  // Sends to each subscriber of the channel. `latch`: also keep it and send it to every later
  // subscriber (the static transforms).
  void publish(std::uint32_t channel, std::uint64_t timestamp_ns,
               std::span<const std::uint8_t> payload, bool latch = false);
  FoxgloveStats stats() const;

 private:
  struct Client {
    std::map<std::uint32_t, std::uint32_t> subscriptions;  // subscription id -> channel
  };
  void on_text(std::uint64_t client, const std::string& text);
  void refuse(std::uint64_t client, const std::string& why);

  FoxgloveOptions options_;
  std::vector<Channel> channels_;
  mutable std::mutex mutex_;
  std::map<std::uint64_t, Client> clients_;
  std::map<std::uint32_t, std::pair<std::uint64_t, std::vector<std::uint8_t>>> latched_;
  FoxgloveStats stats_;
  std::unique_ptr<WebSocketServer> socket_;  // last: its thread stops before the rest goes
};

}  // namespace omnisweep::foxglove
