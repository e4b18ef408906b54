// A WebSocket server on websocketpp (Debian's libwebsocketpp-dev, standalone asio), behind a
// narrow interface: websocketpp 0.8 does not compile as C++20, so websocket_server.cc is the one
// file built as C++17 and nothing else includes websocketpp. No framing is written here.
// Clients are numbered; callbacks run on the server's own network thread, started by start().
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace omnisweep::foxglove {

struct WebSocketCallbacks {
  std::function<void(std::uint64_t client)> open;
  std::function<void(std::uint64_t client)> close;
  std::function<void(std::uint64_t client, const std::string& text)> text;
  std::function<void(std::uint64_t client, std::size_t bytes)> binary;
};

class WebSocketServer final {
 public:
  // Listens on address:port (port 0: any free port) and accepts clients that ask for one of
  // `subprotocols` (others are refused in the handshake). Messages over `max_message_bytes`
  // close their connection (1009, message too big). Throws std::runtime_error naming the
  // address when it cannot listen.
  WebSocketServer(const std::string& address, int port, std::vector<std::string> subprotocols,
                  std::size_t max_message_bytes, WebSocketCallbacks callbacks);
  ~WebSocketServer();  // closes every connection, stops and joins the network thread
  // Starts the network thread: connections are served (and callbacks run) from here on.
  void start();
  WebSocketServer(const WebSocketServer&) = delete;
  WebSocketServer& operator=(const WebSocketServer&) = delete;

  int port() const;  // the port it listens on
  void send_text(std::uint64_t client, const std::string& text);
  // Queues a binary message unless the client already has `max_buffered` bytes waiting to be
  // sent (a slow or stalled reader): then it returns false and the message is dropped for it.
  bool send_binary(std::uint64_t client, const std::uint8_t* data, std::size_t size,
                   std::size_t max_buffered);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace omnisweep::foxglove
