#include "omnisweep/foxglove/foxglove_server.h"

#include <algorithm>
#include <chrono>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "src/foxglove/websocket_server.h"

namespace omnisweep::foxglove {
namespace {

using nlohmann::json;

// Deeper nesting than any valid client message, checked before parsing so that no input can
// drive the parser's recursion deep.
bool nested_deeper_than(std::string_view text, int limit) {
  int depth = 0;
  bool in_string = false, escaped = false;
  for (char c : text) {
    if (in_string) {
      if (escaped)
        escaped = false;
      else if (c == '\\')
        escaped = true;
      else if (c == '"')
        in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > limit) return true;
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return false;
}

// An id field: a JSON integer in [0, 2^32).
bool read_id(const json& object, const char* key, std::uint32_t& out) {
  const auto it = object.find(key);
  if (it == object.end() || !it->is_number_integer()) return false;
  const auto v = it->get<std::int64_t>();
  if (v < 0 || v > 0xffffffffLL) return false;
  out = std::uint32_t(v);
  return true;
}

}  // namespace

ClientMessage parse_client_message(std::string_view text, std::size_t max_bytes) {
  if (text.size() > max_bytes)
    return ParseError{"message of " + std::to_string(text.size()) + " bytes; the limit is " +
                      std::to_string(max_bytes)};
  if (nested_deeper_than(text, 16)) return ParseError{"JSON nested deeper than 16 levels"};
  const json message = json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (message.is_discarded()) return ParseError{"not valid JSON"};
  if (!message.is_object()) return ParseError{"not a JSON object"};
  const auto op = message.find("op");
  if (op == message.end() || !op->is_string()) return ParseError{"no \"op\" string"};
  const std::string name = op->get<std::string>();
  if (name == "subscribe") {
    const auto list = message.find("subscriptions");
    if (list == message.end() || !list->is_array())
      return ParseError{"subscribe: no \"subscriptions\" array"};
    Subscribe out;
    for (const json& s : *list) {
      std::uint32_t id, channel;
      if (!s.is_object() || !read_id(s, "id", id) || !read_id(s, "channelId", channel))
        return ParseError{"subscribe: each subscription needs integer \"id\" and \"channelId\""};
      out.subscriptions.emplace_back(id, channel);
    }
    return out;
  }
  if (name == "unsubscribe") {
    const auto list = message.find("subscriptionIds");
    if (list == message.end() || !list->is_array())
      return ParseError{"unsubscribe: no \"subscriptionIds\" array"};
    Unsubscribe out;
    for (const json& id : *list) {
      if (!id.is_number_integer() || id.get<std::int64_t>() < 0 ||
          id.get<std::int64_t>() > 0xffffffffLL)
        return ParseError{"unsubscribe: subscription ids must be integers"};
      out.subscriptions.push_back(std::uint32_t(id.get<std::int64_t>()));
    }
    return out;
  }
  return ParseError{"op \"" + name.substr(0, 64) + "\" is not supported (subscribe, unsubscribe)"};
}

std::string server_info_json(const std::string& name, const std::string& session) {
  return json{{"op", "serverInfo"},
              {"name", name},
              {"capabilities", json::array()},
              {"supportedEncodings", json::array()},
              {"metadata", json::object()},
              {"sessionId", session}}
      .dump();
}

std::string advertise_json(const std::vector<Channel>& channels) {
  json list = json::array();
  for (const Channel& c : channels)
    list.push_back({{"id", c.id},
                    {"topic", c.topic},
                    {"encoding", c.encoding},
                    {"schemaName", c.schema_name},
                    {"schema", c.schema},
                    {"schemaEncoding", c.schema_encoding}});
  return json{{"op", "advertise"}, {"channels", list}}.dump();
}

std::string status_json(int level, const std::string& message) {
  return json{{"op", "status"}, {"level", level}, {"message", message}}.dump(
      -1, ' ', false, json::error_handler_t::replace);
}

std::vector<std::uint8_t> message_data(std::uint32_t subscription, std::uint64_t timestamp_ns,
                                       std::span<const std::uint8_t> payload) {
  std::vector<std::uint8_t> out(13 + payload.size());
  out[0] = 1;
  for (int i = 0; i < 4; ++i) out[1 + i] = std::uint8_t(subscription >> (8 * i));
  for (int i = 0; i < 8; ++i) out[5 + i] = std::uint8_t(timestamp_ns >> (8 * i));
  std::copy(payload.begin(), payload.end(), out.begin() + 13);
  return out;
}

void FoxgloveOptions::check() const {
  if (port < 0 || port > 65535)
    throw std::invalid_argument("FoxgloveOptions.port = " + std::to_string(port) +
                                ": must be 0-65535 (0: any free port)");
  if (address.empty()) throw std::invalid_argument("FoxgloveOptions.address is empty");
  if (client_queue_bytes < 1024)
    throw std::invalid_argument("FoxgloveOptions.client_queue_bytes = " +
                                std::to_string(client_queue_bytes) + ": must be >= 1024");
}

FoxgloveServer::FoxgloveServer(const FoxgloveOptions& options, std::vector<Channel> channels)
    : options_(options), channels_(std::move(channels)) {
  options_.check();
  const std::string session = std::to_string(std::chrono::system_clock::now().time_since_epoch() /
                                             std::chrono::milliseconds(1));
  WebSocketCallbacks callbacks;
  callbacks.open = [this, session](std::uint64_t client) {
    {
      const std::lock_guard lock(mutex_);
      clients_[client];
      stats_.clients = clients_.size();
    }
    socket_->send_text(client, server_info_json(options_.name, session));
    socket_->send_text(client, advertise_json(channels_));
  };
  callbacks.close = [this](std::uint64_t client) {
    const std::lock_guard lock(mutex_);
    clients_.erase(client);
    stats_.clients = clients_.size();
  };
  callbacks.text = [this](std::uint64_t client, const std::string& text) { on_text(client, text); };
  callbacks.binary = [this](std::uint64_t client, std::size_t) {
    refuse(client, "binary client messages are not supported");
  };
  // Frames up to 16x the JSON limit reach on_text and get a status; larger ones close.
  socket_ = std::make_unique<WebSocketServer>(
      options_.address, options_.port, std::vector<std::string>{kSubprotocol, kSdkSubprotocol},
      16 * options_.max_client_message_bytes, std::move(callbacks));
  socket_->start();
}

FoxgloveServer::~FoxgloveServer() { socket_.reset(); }

int FoxgloveServer::port() const { return socket_->port(); }

void FoxgloveServer::refuse(std::uint64_t client, const std::string& why) {
  {
    const std::lock_guard lock(mutex_);
    ++stats_.refused;
  }
  socket_->send_text(client, status_json(2, why));
}

void FoxgloveServer::on_text(std::uint64_t client, const std::string& text) {
  const ClientMessage message = parse_client_message(text, options_.max_client_message_bytes);
  if (const auto* error = std::get_if<ParseError>(&message)) return refuse(client, error->message);
  std::vector<std::vector<std::uint8_t>> latched;  // sent outside the lock
  std::string problem;
  {
    const std::lock_guard lock(mutex_);
    const auto it = clients_.find(client);
    if (it == clients_.end()) return;
    if (const auto* subscribe = std::get_if<Subscribe>(&message)) {
      for (const auto& [id, channel] : subscribe->subscriptions) {
        const std::uint32_t wanted = channel;  // clang 14 lambdas cannot capture a binding
        const bool known = std::any_of(channels_.begin(), channels_.end(),
                                       [&](const Channel& c) { return c.id == wanted; });
        if (!known) {
          problem = "channel " + std::to_string(channel) + " is not advertised";
          continue;
        }
        if (it->second.subscriptions.count(id)) {
          problem = "subscription id " + std::to_string(id) + " is already in use";
          continue;
        }
        it->second.subscriptions[id] = channel;
        if (const auto l = latched_.find(channel); l != latched_.end())
          latched.push_back(message_data(id, l->second.first, l->second.second));
      }
    } else {
      for (const std::uint32_t id : std::get<Unsubscribe>(message).subscriptions) {
        if (!it->second.subscriptions.erase(id)) problem = "no subscription " + std::to_string(id);
      }
    }
  }
  if (!problem.empty()) refuse(client, problem);
  for (const auto& data : latched)
    socket_->send_binary(client, data.data(), data.size(), options_.client_queue_bytes);
}

bool FoxgloveServer::subscribed(std::uint32_t channel) const {
  const std::lock_guard lock(mutex_);
  for (const auto& [id, client] : clients_)
    for (const auto& [subscription, c] : client.subscriptions)
      if (c == channel) return true;
  return false;
}

void FoxgloveServer::publish(std::uint32_t channel, std::uint64_t timestamp_ns,
                             std::span<const std::uint8_t> payload, bool latch) {
  std::vector<std::pair<std::uint64_t, std::uint32_t>> targets;  // (client, subscription)
  {
    const std::lock_guard lock(mutex_);
    if (latch) latched_[channel] = {timestamp_ns, {payload.begin(), payload.end()}};
    for (const auto& [id, client] : clients_)
      for (const auto& [subscription, c] : client.subscriptions)
        if (c == channel) targets.emplace_back(id, subscription);
  }
  std::uint64_t sent = 0, dropped = 0;
  for (const auto& [client, subscription] : targets) {
    const auto data = message_data(subscription, timestamp_ns, payload);
    if (socket_->send_binary(client, data.data(), data.size(), options_.client_queue_bytes))
      ++sent;
    else
      ++dropped;
  }
  const std::lock_guard lock(mutex_);
  stats_.sent += sent;
  stats_.dropped += dropped;
}

FoxgloveStats FoxgloveServer::stats() const {
  const std::lock_guard lock(mutex_);
  return stats_;
}

}  // namespace omnisweep::foxglove
