#include "omnisweep/codec/codec.h"

#include <zlib.h>

#include <cmath>
#include <cstdio>

#include "src/codec/codecs.h"

namespace omnisweep::codec {

void DistanceParams::check() const {
  if (!(min_distance > 0) || !std::isfinite(min_distance))
    throw CodecError("distance codec: min distance must be > 0");
  if (!(max_distance > min_distance) || !std::isfinite(max_distance)) {
    throw CodecError(
        "distance codec: max distance must be finite and larger than the min distance");
  }
  if (levels < 2 || levels > 65535)
    throw CodecError("distance codec: levels must be within [2, 65535]");
  if (downsample != 1 && downsample != 2 && downsample != 4)
    throw CodecError("distance codec: downsample must be 1, 2 or 4");
}

double DistanceParams::max_quantisation_error() const {
  return 0.5 * (1.0 / min_distance - 1.0 / max_distance) / double(levels - 1);
}

std::uint32_t checksum(std::span<const std::uint8_t> payload, std::uint32_t running) {
  uLong crc = running;
  std::size_t offset = 0;
  while (offset < payload.size()) {  // zlib takes uInt lengths
    const auto chunk = uInt(std::min<std::size_t>(payload.size() - offset, 1u << 30));
    crc = crc32(crc, payload.data() + offset, chunk);
    offset += chunk;
  }
  return std::uint32_t(crc);
}

void verify_checksum(std::span<const std::uint8_t> payload, std::uint32_t expected) {
  const std::uint32_t actual = checksum(payload);
  if (actual != expected) {
    char text[96];
    std::snprintf(text, sizeof(text), "payload checksum %08x does not match %08x: corrupt payload",
                  actual, expected);
    throw CodecError(text);
  }
}

std::vector<std::string> color_codec_names() { return {std::string(kJpeg)}; }
std::vector<std::string> distance_codec_names() { return {std::string(kQinv16Zstd)}; }
std::vector<std::string> confidence_codec_names() { return {std::string(kConf8Zstd)}; }

namespace {
[[noreturn]] void unknown_codec(const char* what, std::string_view name, std::string_view known) {
  throw CodecError("unknown " + std::string(what) + " codec '" + std::string(name) +
                   "' (known: " + std::string(known) + ")");
}
}  // namespace

std::unique_ptr<ColorCodec> make_color_codec(std::string_view name, const ColorOptions& options) {
  if (name == kJpeg) return make_jpeg_codec(options.quality);
  unknown_codec("colour", name, kJpeg);
}

std::unique_ptr<DistanceCodec> make_distance_codec(std::string_view name) {
  if (name == kQinv16Zstd) return make_qinv16_zstd_codec();
  unknown_codec("distance", name, kQinv16Zstd);
}

std::unique_ptr<ConfidenceCodec> make_confidence_codec(std::string_view name) {
  if (name == kConf8Zstd) return make_conf8_zstd_codec();
  unknown_codec("confidence", name, kConf8Zstd);
}

}  // namespace omnisweep::codec
