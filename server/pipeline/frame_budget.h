// Keeps a frame (colour + distance payloads) under a byte budget by lowering the colour JPEG
// quality when a frame would not fit, as far as a floor, and raising it back towards the
// configured quality when frames have room again: rate control for links with a fixed
// bandwidth (Wi-Fi), the way video encoders keep to a bitrate. The distance payload is never
// touched: its precision is part of the stream description.
#pragma once

#include <cstddef>
#include <map>
#include <memory>
#include <string>

#include "omnisweep/codec/codec.h"

namespace omnisweep::pipeline {

class FrameBudget {
 public:
  // max_bytes 0: no budget, every frame at `quality`. floor_quality: the lowest quality used
  // (at most `quality`).
  FrameBudget(int quality, std::size_t max_bytes, int floor_quality = kFloorQuality);

  struct Color {
    codec::Bytes bytes;
    int quality = 0;
    bool over_budget = false;  // did not fit even at the floor quality
  };
  // Encodes `rgb` at the highest quality, in steps of kStep from the last frame's, at which it
  // fits beside `distance_bytes`; one encode per frame while the quality holds.
  Color encode(Rgb8View rgb, std::size_t distance_bytes);

  int quality() const { return quality_; }
  std::string codec_name() const { return codecs_.at(max_quality_)->name(); }
  std::size_t max_bytes() const { return max_bytes_; }

  static constexpr int kFloorQuality = 50;
  static constexpr int kStep = 5;
  // The quality is raised again only when a frame used less than this share of the budget.
  static constexpr double kRoomToRaise = 0.9;

 private:
  codec::ColorCodec& codec_at(int quality);  // made on first use
  codec::Bytes encode_at(Rgb8View rgb, int quality);

  int max_quality_, floor_quality_, quality_;
  std::size_t max_bytes_;
  std::map<int, std::unique_ptr<codec::ColorCodec>> codecs_;  // by quality
};

}  // namespace omnisweep::pipeline
