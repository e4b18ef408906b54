#include "server/pipeline/frame_budget.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace omnisweep::pipeline {

FrameBudget::FrameBudget(int quality, std::size_t max_bytes, int floor_quality)
    : max_quality_(quality),
      floor_quality_(std::min(floor_quality, quality)),
      quality_(quality),
      max_bytes_(max_bytes) {
  if (quality < 1 || quality > 100 || floor_quality < 1)
    throw std::invalid_argument("JPEG quality must be 1-100, got " + std::to_string(quality));
  codec_at(quality);  // the name comes from it
}

codec::ColorCodec& FrameBudget::codec_at(int quality) {
  auto& codec = codecs_[quality];
  if (!codec) codec = codec::make_color_codec(codec::kJpeg, {.quality = quality});
  return *codec;
}

codec::Bytes FrameBudget::encode_at(Rgb8View rgb, int quality) {
  return codec_at(quality).encode(rgb);
}

FrameBudget::Color FrameBudget::encode(Rgb8View rgb, std::size_t distance_bytes) {
  Color out{encode_at(rgb, quality_), quality_, false};
  if (max_bytes_ == 0) return out;
  auto fits = [&](const codec::Bytes& color) {
    return distance_bytes + color.size() <= max_bytes_;
  };
  if (!fits(out.bytes)) {
    while (!fits(out.bytes) && out.quality > floor_quality_) {
      out.quality = std::max(floor_quality_, out.quality - kStep);
      out.bytes = encode_at(rgb, out.quality);
    }
    out.over_budget = !fits(out.bytes);
  } else if (out.quality < max_quality_ &&
             double(distance_bytes + out.bytes.size()) < kRoomToRaise * double(max_bytes_)) {
    // Room again (a calmer scene): try one step up, keep it if it fits.
    const int higher = std::min(max_quality_, out.quality + kStep);
    codec::Bytes better = encode_at(rgb, higher);
    if (fits(better)) out = {std::move(better), higher, false};
  }
  quality_ = out.quality;
  return out;
}

}  // namespace omnisweep::pipeline
