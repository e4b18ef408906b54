// Codecs for the RGB-D stream, plugin-style as in ROS 2 image_transport: each codec has a name
// and encode/decode; a frame carries the codec's name and parameters, so any receiver decodes
// any frame alone. Decoders check everything they read: a corrupt, truncated or mismatched
// payload throws CodecError and never reads out of bounds.
//
//   colour:   "jpeg"        libjpeg-turbo, quality 1-100 (default 90), 4:2:0
//   distance: "qinv16-zstd" inverse distance quantised to 16-bit levels over [1/d_max, 1/d_min]
//             (0 = no value), planar prediction, residuals sorted into 8 context streams, zstd
//             with a content checksum (docs/wire-format.md has the layout).
//   confidence: "conf8-zstd" confidence in [0, 1] as 8-bit levels round(255 c), by default at
//             half resolution, left prediction, zstd with a content checksum (optional;
//             docs/wire-format.md).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "omnisweep/image/image.h"

namespace omnisweep::codec {

class CodecError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

using Bytes = std::vector<std::uint8_t>;

// The codec names a frame's payloads carry (wire::make_payload): the one place they are spelled.
inline constexpr std::string_view kJpeg = "jpeg";               // colour
inline constexpr std::string_view kQinv16Zstd = "qinv16-zstd";  // distance
inline constexpr std::string_view kConf8Zstd = "conf8-zstd";    // confidence

class ColorCodec {
 public:
  virtual ~ColorCodec() = default;
  virtual std::string name() const = 0;
  virtual Bytes encode(Rgb8View image) const = 0;
  // Throws CodecError unless `payload` is a whole image of width x height.
  virtual Rgb8Image decode(std::span<const std::uint8_t> payload, int width, int height) const = 0;
};

// How distance maps are quantised; travels with every frame.
struct DistanceParams {
  float min_distance = 0.55f;   // metres: 1 / d_min is the top of the inverse-distance range
  float max_distance = 100.0f;  // metres
  // Quantisation levels over [1/d_max, 1/d_min] (2 .. 65535). 10000 keeps the error within
  // 1e-4 m^-1 over [0.55, 100] m (9.04e-5) without spending bits on the estimate's noise.
  std::uint32_t levels = 10000;
  std::uint32_t downsample = 1;  // stored at 1/downsample resolution per axis: 1, 2 or 4

  void check() const;  // throws CodecError naming the bad parameter
  // Largest inverse-distance error quantisation adds, m^-1 (half a level).
  double max_quantisation_error() const;
};

class DistanceCodec {
 public:
  virtual ~DistanceCodec() = default;
  virtual std::string name() const = 0;
  // `distance` in metres; <= 0 or non-finite means no value and survives as 0.
  virtual Bytes encode(FloatView distance, const DistanceParams& params) const = 0;
  // Throws CodecError unless `payload` holds a width x height map encoded with `params`.
  virtual FloatImage decode(std::span<const std::uint8_t> payload, int width, int height,
                            const DistanceParams& params) const = 0;
  // The payload's levels as stored (1/downsample of width x height; 0 = no value, level l is
  // inverse distance 1/d_max + (l - 1) (1/d_min - 1/d_max) / (levels - 1)): what decode()
  // turns into metres. Same checks and errors as decode().
  virtual Image<std::uint16_t> decode_levels(std::span<const std::uint8_t> payload, int width,
                                             int height, const DistanceParams& params) const = 0;
};

// Metres of each stored level of `params` (index 0, no value: 0): what DistanceCodec::decode
// maps levels through.
std::vector<float> level_metres(const DistanceParams& params);
// A width x height distance map in metres from levels as decode_levels() gives them (stored at
// 1/params.downsample per axis): bit-identical to decode() of the same payload, for a receiver
// that needs both the levels and the metres without decoding twice.
FloatImage distance_from_levels(ImageView<const std::uint16_t> levels, int width, int height,
                                const DistanceParams& params);

// The per-pixel confidence of a distance panorama, as 8-bit levels (0 = none, 255 = full).
class ConfidenceCodec {
 public:
  virtual ~ConfidenceCodec() = default;
  virtual std::string name() const = 0;
  // `downsample`: stored at 1/downsample of the resolution per axis (1, 2 or 4; the block means),
  // decoded back to full size by bilinear interpolation.
  virtual Bytes encode(Gray8View levels, int downsample = 2) const = 0;
  // Throws CodecError unless `payload` holds a width x height map.
  virtual Gray8Image decode(std::span<const std::uint8_t> payload, int width, int height) const = 0;
};
// Confidence in [0, 1] to levels round(255 c) (non-finite: 0), and back (level / 255).
Gray8Image confidence_levels(FloatView confidence);
FloatImage confidence_values(Gray8View levels);

struct ColorOptions {
  int quality = 90;
};

// The light setting, for links that cannot carry the default's up to 1 MB per 2048x1024 frame:
// distance at a quarter of the resolution per axis (the mean inverse distance of 4x4 blocks)
// over 2048 levels, colour at JPEG quality 60, and a frame budget of 250,000 bytes. About
// 170-225 KB per frame (docs/performance.md has the sizes and the error it adds).
inline constexpr DistanceParams kLightDistance{.levels = 2048, .downsample = 4};
inline constexpr int kLightJpegQuality = 60;
inline constexpr std::size_t kLightFrameBytes = 250000;

// CRC-32 (zlib's) of a payload. JPEG carries no checksum of its own, so every payload travels
// with this one and receivers call verify_checksum before decoding: a flipped bit anywhere is
// then an error rather than a wrong image.
// `running`: the CRC of what came before, to checksum data in pieces (MCAP chunks and summaries
// use the same CRC-32).
std::uint32_t checksum(std::span<const std::uint8_t> payload, std::uint32_t running = 0);
void verify_checksum(std::span<const std::uint8_t> payload,
                     std::uint32_t expected);  // throws CodecError

// Throws CodecError for unknown names; known names are listed by the functions below.
std::unique_ptr<ColorCodec> make_color_codec(std::string_view name = kJpeg,
                                             const ColorOptions& options = {});
std::unique_ptr<DistanceCodec> make_distance_codec(std::string_view name = kQinv16Zstd);
std::unique_ptr<ConfidenceCodec> make_confidence_codec(std::string_view name = kConf8Zstd);
std::vector<std::string> color_codec_names();
std::vector<std::string> distance_codec_names();
std::vector<std::string> confidence_codec_names();

}  // namespace omnisweep::codec
