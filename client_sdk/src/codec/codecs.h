// The codec implementations behind make_color_codec / make_distance_codec /
// make_confidence_codec, and the little-endian integers of their payload headers.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "omnisweep/codec/codec.h"

namespace omnisweep::codec {

std::unique_ptr<ColorCodec> make_jpeg_codec(int quality);
std::unique_ptr<DistanceCodec> make_qinv16_zstd_codec();
std::unique_ptr<ConfidenceCodec> make_conf8_zstd_codec();

// "<codec name>: ", the start of every error a codec throws.
inline std::string error_prefix(std::string_view codec) { return std::string(codec) + ": "; }

inline void put_u32(std::uint8_t* p, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = std::uint8_t(v >> (8 * i));
}
inline std::uint32_t get_u32(const std::uint8_t* p) {
  std::uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= std::uint32_t(p[i]) << (8 * i);
  return v;
}

}  // namespace omnisweep::codec
