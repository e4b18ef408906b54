// libFuzzer target: the Foxglove WebSocket server's client-message parser
// (client_sdk/src/foxglove), which reads whatever text any client on the network sends. It must
// never throw or crash, and it answers every input with a message or a reason.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>
#include <variant>

#include "omnisweep/foxglove/foxglove_server.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const auto message = omnisweep::foxglove::parse_client_message(text, 4096);
  if (const auto* error = std::get_if<omnisweep::foxglove::ParseError>(&message))
    if (error->message.empty()) std::abort();  // every refusal says why
  // Whatever it says goes back to the client as a status: it must serialise.
  if (const auto* error = std::get_if<omnisweep::foxglove::ParseError>(&message))
    (void)omnisweep::foxglove::status_json(2, error->message);
  return 0;
}
