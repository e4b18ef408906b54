// Built as C++17 (see websocket_server.h).
#define ASIO_STANDALONE
#include "src/foxglove/websocket_server.h"

#include <algorithm>
#include <map>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <websocketpp/config/asio_no_tls.hpp>
#include <websocketpp/server.hpp>

namespace omnisweep::foxglove {

using Endpoint = websocketpp::server<websocketpp::config::asio>;
using Handle = websocketpp::connection_hdl;

struct WebSocketServer::Impl {
  Endpoint endpoint;
  WebSocketCallbacks callbacks;
  std::vector<std::string> subprotocols;
  std::mutex mutex;  // clients
  std::map<std::uint64_t, Handle> clients;
  std::map<Handle, std::uint64_t, std::owner_less<Handle>> ids;
  std::uint64_t next_id = 1;
  std::thread thread;
  int port = 0;

  std::uint64_t id_of(Handle h) {
    const std::lock_guard<std::mutex> lock(mutex);
    const auto it = ids.find(h);
    return it == ids.end() ? 0 : it->second;
  }
  Endpoint::connection_ptr connection(std::uint64_t client) {
    Handle h;
    {
      const std::lock_guard<std::mutex> lock(mutex);
      const auto it = clients.find(client);
      if (it == clients.end()) return nullptr;
      h = it->second;
    }
    websocketpp::lib::error_code ec;
    auto con = endpoint.get_con_from_hdl(h, ec);
    return ec ? nullptr : con;
  }
};

WebSocketServer::WebSocketServer(const std::string& address, int port,
                                 std::vector<std::string> subprotocols,
                                 std::size_t max_message_bytes, WebSocketCallbacks callbacks)
    : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  s.callbacks = std::move(callbacks);
  s.subprotocols = std::move(subprotocols);
  s.endpoint.clear_access_channels(websocketpp::log::alevel::all);
  s.endpoint.clear_error_channels(websocketpp::log::elevel::all);
  s.endpoint.init_asio();
  s.endpoint.set_reuse_addr(true);
  s.endpoint.set_max_message_size(max_message_bytes);
  s.endpoint.set_validate_handler([&s](Handle h) {
    auto con = s.endpoint.get_con_from_hdl(h);
    for (const std::string& asked : con->get_requested_subprotocols()) {
      if (std::find(s.subprotocols.begin(), s.subprotocols.end(), asked) != s.subprotocols.end()) {
        con->select_subprotocol(asked);
        return true;
      }
    }
    con->set_status(websocketpp::http::status_code::bad_request);
    con->set_body("omnisweep: ask for the WebSocket subprotocol foxglove.websocket.v1\n");
    return false;
  });
  s.endpoint.set_open_handler([&s](Handle h) {
    std::uint64_t id;
    {
      const std::lock_guard<std::mutex> lock(s.mutex);
      id = s.next_id++;
      s.clients[id] = h;
      s.ids[h] = id;
    }
    if (s.callbacks.open) s.callbacks.open(id);
  });
  s.endpoint.set_close_handler([&s](Handle h) {
    std::uint64_t id = 0;
    {
      const std::lock_guard<std::mutex> lock(s.mutex);
      const auto it = s.ids.find(h);
      if (it == s.ids.end()) return;
      id = it->second;
      s.clients.erase(id);
      s.ids.erase(it);
    }
    if (s.callbacks.close) s.callbacks.close(id);
  });
  s.endpoint.set_fail_handler([](Handle) {});
  s.endpoint.set_message_handler([&s](Handle h, Endpoint::message_ptr message) {
    const std::uint64_t id = s.id_of(h);
    if (!id) return;
    if (message->get_opcode() == websocketpp::frame::opcode::text) {
      if (s.callbacks.text) s.callbacks.text(id, message->get_payload());
    } else if (s.callbacks.binary) {
      s.callbacks.binary(id, message->get_payload().size());
    }
  });
  websocketpp::lib::error_code ec;
  s.endpoint.listen(address, std::to_string(port), ec);
  if (ec)
    throw std::runtime_error("cannot listen on " + address + ":" + std::to_string(port) + ": " +
                             ec.message());
  s.endpoint.start_accept(ec);
  if (ec) throw std::runtime_error("cannot accept WebSocket connections: " + ec.message());
  const auto local = s.endpoint.get_local_endpoint(ec);
  s.port = ec ? port : local.port();
}

void WebSocketServer::start() {
  Impl& s = *impl_;
  s.thread = std::thread([&s] {
    try {
      s.endpoint.run();
    } catch (const std::exception&) {
      // A network error ends the server thread; clients see their connection close.
    }
  });
}

WebSocketServer::~WebSocketServer() {
  Impl& s = *impl_;
  // Nothing may leave a destructor: a client that cannot be closed politely (out of memory, a
  // lock error) is dropped by stop() below all the same.
  try {
    websocketpp::lib::error_code ec;
    s.endpoint.stop_listening(ec);
    std::vector<Handle> open;
    {
      const std::lock_guard<std::mutex> lock(s.mutex);
      for (const auto& [id, h] : s.clients) open.push_back(h);
    }
    for (const Handle& h : open)
      s.endpoint.close(h, websocketpp::close::status::going_away, "server stopping", ec);
  } catch (...) {
  }
  try {
    s.endpoint.stop();
    if (s.thread.joinable()) s.thread.join();
  } catch (...) {
    // join() throws only for a thread that is not joinable or is this one: neither can be.
  }
}

int WebSocketServer::port() const { return impl_->port; }

void WebSocketServer::send_text(std::uint64_t client, const std::string& text) {
  if (auto con = impl_->connection(client)) con->send(text, websocketpp::frame::opcode::text);
}

bool WebSocketServer::send_binary(std::uint64_t client, const std::uint8_t* data, std::size_t size,
                                  std::size_t max_buffered) {
  auto con = impl_->connection(client);
  if (!con) return false;
  if (con->get_buffered_amount() > max_buffered) return false;
  con->send(data, size, websocketpp::frame::opcode::binary);
  return true;
}

}  // namespace omnisweep::foxglove
