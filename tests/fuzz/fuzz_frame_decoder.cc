// libFuzzer target: everything that decodes a frame received from the network. The first byte
// picks the path, so mutations reach each decoder past the CRC that guards whole frames:
//   0: a qinv16-zstd distance payload; bytes 1-7: width, height (uint16 LE, capped at 1024),
//      levels (uint16 LE), downsample (1, 2 or 4); the rest is the payload;
//   1: a JPEG colour payload; bytes 1-4: width, height; the rest is the payload;
//   2: an RgbdFrame as CDR (what DDS and MCAP carry), deserialised and decoded whole;
//   3: a conf8-zstd confidence payload; bytes 1-4: width, height; the rest is the payload;
//   4: a ConfidenceFrame as CDR, deserialised and decoded at its own size.
// Decoders may throw (that is how they report bad input); a crash, hang, leak or sanitizer
// report is a finding.
#include <cstddef>
#include <cstdint>
#include <exception>
#include <span>

#include "omnisweep/codec/codec.h"
#include "omnisweep/record/stream_recording.h"
#include "omnisweep/wire/wire.h"

namespace {

int dimension(const std::uint8_t* p) { return 1 + (p[0] | (p[1] << 8)) % 1024; }

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace omnisweep;
  if (size < 8) return 0;
  try {
    switch (data[0] % 5) {
      case 0: {
        codec::DistanceParams params;
        params.levels = 2 + (data[5] | (data[6] << 8)) % 65534;
        params.downsample = std::uint32_t(1) << (data[7] % 3);
        const auto codec = codec::make_distance_codec(codec::kQinv16Zstd);
        codec->decode(std::span(data + 8, size - 8), dimension(data + 1), dimension(data + 3),
                      params);
        break;
      }
      case 1: {
        const auto codec = codec::make_color_codec(codec::kJpeg);
        codec->decode(std::span(data + 5, size - 5), dimension(data + 1), dimension(data + 3));
        break;
      }
      case 3: {
        const auto codec = codec::make_confidence_codec(codec::kConf8Zstd);
        codec->decode(std::span(data + 5, size - 5), dimension(data + 1), dimension(data + 3));
        break;
      }
      case 4: {
        msg::ConfidenceFrame confidence;
        record::decode_message(std::span(data + 1, size - 1), confidence);
        if (confidence.width() <= 2048 && confidence.height() <= 1024)
          wire::decode_confidence(confidence, int(confidence.width()), int(confidence.height()));
        break;
      }
      default: {
        msg::RgbdFrame frame;
        record::decode_message(std::span(data + 1, size - 1), frame);
        if (frame.width() <= 2048 && frame.height() <= 1024) wire::decode_frame(frame);
        break;
      }
    }
  } catch (const std::exception&) {
  }
  return 0;
}
