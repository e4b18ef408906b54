// Between omnisweep's types and the DDS messages of idl/omnisweep_msgs.idl. Everything that
// comes off the network is checked: a bad message throws WireError naming the field.
#pragma once

#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>

#include "omnisweep/codec/codec.h"
#include "omnisweep/rig/rig.h"
#include "omnisweep/wire/server_status.h"
#include "omnisweep_msgs.h"

namespace omnisweep::wire {

class WireError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The status as plain values (server_status.h); throws nothing (an unknown state stays text).
StatusReport from_message(const msg::ServerStatus& status);
// The same for a status that may not have arrived yet (a subscriber's newest, or none).
std::optional<StatusReport> from_message(const std::optional<msg::ServerStatus>& status);

msg::CameraCalibration to_message(const RigCamera& camera);
msg::DistanceCodecParams to_message(const codec::DistanceParams& params);
codec::DistanceParams from_message(const msg::DistanceCodecParams& params);  // throws WireError

// The rig described by a stream description; throws WireError naming the field at fault.
Rig rig_from_description(const msg::StreamDescription& description);
void add_rig(const Rig& rig, msg::StreamDescription* description);

// A payload with its codec name and CRC-32.
msg::Payload make_payload(std::string_view codec_name, const codec::Bytes& data);
// The payload's bytes after checking its CRC-32; throws WireError naming `what` on a mismatch.
std::span<const std::uint8_t> checked_bytes(const msg::Payload& payload, const std::string& what);

struct DecodedFrame {
  std::uint64_t sequence_number = 0;
  Rgb8Image rgb;
  FloatImage distance;  // metres, 0 = no value
};

// Checks and decodes a frame whole, or throws WireError / codec::CodecError.
DecodedFrame decode_frame(const msg::RgbdFrame& frame);

// Checks and decodes a frame's confidence (levels, 255 = full confidence) for a width x height
// frame, or throws WireError / codec::CodecError.
Gray8Image decode_confidence(const msg::ConfidenceFrame& confidence, int width, int height);

}  // namespace omnisweep::wire
