// The codec implementations behind make_color_codec / make_distance_codec.
#pragma once

#include <memory>

#include "omnisweep/codec/codec.h"

namespace omnisweep::codec {

std::unique_ptr<ColorCodec> make_jpeg_codec(int quality);
std::unique_ptr<DistanceCodec> make_qinv16_zstd_codec();

}  // namespace omnisweep::codec
