// Confidence as 8-bit levels (round(255 c)), stored at 1/downsample of the resolution per axis
// (each stored level the rounded mean of its block; decoding interpolates bilinearly between
// block centres), each row predicted from the sample to its left (differences mod 256), zstd
// with a content checksum. Payload (integers uint32 little endian):
//   "OSC1", width, height (the frame's), downsample (1, 2 or 4), then one zstd frame of the
//   ceil(width / downsample) x ceil(height / downsample) stored levels.
// Measured on 2048x1024 panoramas (synthetic rig, blender-hall): 530-580 KB at full resolution,
// 167-183 KB at half (the default), so the confidence costs a sixth of a default frame.
// Confidence maps are piecewise smooth with sharp drops at edges; the left difference turns
// the smooth parts into runs of small values that zstd's Huffman stage codes in 1-3 bits, and
// zstd is already a dependency. The prediction is a one-line loop, written here because no
// library here offers an 8-bit predictor in front of zstd (PNG's deflate is 3-5x slower).
#include <zstd.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "src/codec/codecs.h"

namespace omnisweep::codec {
namespace {

constexpr char kMagic[4] = {'O', 'S', 'C', '1'};
constexpr std::size_t kHeader = 16;
constexpr std::uint64_t kMaxPixels = std::uint64_t(1) << 26;
constexpr int kZstdLevel = 3;

int stored(int size, int downsample) { return (size + downsample - 1) / downsample; }

// The rounded mean level of each downsample x downsample block (clipped at the edges).
Bytes block_means(Gray8View levels, int downsample) {
  const int w = levels.width(), h = levels.height();
  const int sw = stored(w, downsample), sh = stored(h, downsample);
  Bytes out(std::size_t(sw) * sh);
  for (int by = 0; by < sh; ++by) {
    for (int bx = 0; bx < sw; ++bx) {
      int sum = 0, count = 0;
      for (int y = by * downsample; y < std::min(h, (by + 1) * downsample); ++y)
        for (int x = bx * downsample; x < std::min(w, (bx + 1) * downsample); ++x, ++count)
          sum += levels.data()[std::size_t(y) * w + x];
      out[std::size_t(by) * sw + bx] = std::uint8_t((sum + count / 2) / count);
    }
  }
  return out;
}

// Bilinear between the stored samples' centres, clamped at the edges.
Gray8Image upsample(const Bytes& samples, int sw, int sh, int w, int h, int downsample) {
  Gray8Image out(w, h);
  for (int y = 0; y < h; ++y) {
    const double fy = std::clamp((y + 0.5) / downsample - 0.5, 0.0, double(sh - 1));
    const int y0 = int(fy), y1 = std::min(y0 + 1, sh - 1);
    const double ty = fy - y0;
    for (int x = 0; x < w; ++x) {
      const double fx = std::clamp((x + 0.5) / downsample - 0.5, 0.0, double(sw - 1));
      const int x0 = int(fx), x1 = std::min(x0 + 1, sw - 1);
      const double tx = fx - x0;
      auto at = [&](int yy, int xx) { return double(samples[std::size_t(yy) * sw + xx]); };
      const double v = (1 - ty) * ((1 - tx) * at(y0, x0) + tx * at(y0, x1)) +
                       ty * ((1 - tx) * at(y1, x0) + tx * at(y1, x1));
      out.data()[std::size_t(y) * w + x] = std::uint8_t(std::lround(v));
    }
  }
  return out;
}

class Conf8Zstd final : public ConfidenceCodec {
 public:
  std::string name() const override { return std::string(kConf8Zstd); }

  Bytes encode(Gray8View levels, int downsample) const override {
    if (levels.empty()) throw CodecError("confidence codec: expected a non-empty image");
    if (downsample != 1 && downsample != 2 && downsample != 4)
      throw CodecError("confidence codec: downsample " + std::to_string(downsample) +
                       " is not 1, 2 or 4");
    const Bytes samples = downsample == 1 ? Bytes(levels.data(), levels.data() + levels.size())
                                          : block_means(levels, downsample);
    const std::size_t sw = std::size_t(stored(levels.width(), downsample)), n = samples.size();
    Bytes residual(n);
    for (std::size_t i = 0; i < n; ++i)
      residual[i] = std::uint8_t(samples[i] - (i % sw == 0 ? 0 : samples[i - 1]));
    Bytes out(kHeader + ZSTD_compressBound(n));
    std::copy(kMagic, kMagic + 4, out.begin());
    put_u32(out.data() + 4, std::uint32_t(levels.width()));
    put_u32(out.data() + 8, std::uint32_t(levels.height()));
    put_u32(out.data() + 12, std::uint32_t(downsample));
    ZSTD_CCtx* cctx = ZSTD_createCCtx();
    ZSTD_CCtx_setParameter(cctx, ZSTD_c_compressionLevel, kZstdLevel);
    ZSTD_CCtx_setParameter(cctx, ZSTD_c_checksumFlag, 1);
    const std::size_t size =
        ZSTD_compress2(cctx, out.data() + kHeader, out.size() - kHeader, residual.data(), n);
    ZSTD_freeCCtx(cctx);
    if (ZSTD_isError(size))
      throw CodecError(std::string("confidence codec: zstd: ") + ZSTD_getErrorName(size));
    out.resize(kHeader + size);
    return out;
  }

  Gray8Image decode(std::span<const std::uint8_t> payload, int width, int height) const override {
    if (payload.size() < kHeader || !std::equal(kMagic, kMagic + 4, payload.begin()))
      throw CodecError("confidence codec: payload is not conf8-zstd (bad magic or too short)");
    const std::uint32_t w = get_u32(payload.data() + 4), h = get_u32(payload.data() + 8);
    const std::uint32_t downsample = get_u32(payload.data() + 12);
    if (w == 0 || h == 0 || std::uint64_t(w) * h > kMaxPixels || int(w) != width ||
        int(h) != height) {
      throw CodecError("confidence codec: payload holds " + std::to_string(w) + "x" +
                       std::to_string(h) + ", expected " + std::to_string(width) + "x" +
                       std::to_string(height));
    }
    if (downsample != 1 && downsample != 2 && downsample != 4)
      throw CodecError("confidence codec: downsample " + std::to_string(downsample) +
                       " is not 1, 2 or 4");
    const int sw = stored(width, int(downsample)), sh = stored(height, int(downsample));
    const std::size_t n = std::size_t(sw) * sh;
    const auto frame = payload.subspan(kHeader);
    const unsigned long long content = ZSTD_getFrameContentSize(frame.data(), frame.size());
    if (content != n)
      throw CodecError("confidence codec: the compressed frame does not hold the stored levels");
    Bytes samples(n);
    const std::size_t size = ZSTD_decompress(samples.data(), n, frame.data(), frame.size());
    if (ZSTD_isError(size) || size != n) {
      throw CodecError(std::string("confidence codec: corrupt payload: ") +
                       (ZSTD_isError(size) ? ZSTD_getErrorName(size) : "short"));
    }
    for (std::size_t i = 0; i < n; ++i) {
      if (i % std::size_t(sw) != 0) samples[i] = std::uint8_t(samples[i] + samples[i - 1]);
    }
    if (downsample == 1) {
      Gray8Image out(width, height);
      std::copy(samples.begin(), samples.end(), out.data());
      return out;
    }
    return upsample(samples, sw, sh, width, height, int(downsample));
  }
};

}  // namespace

std::unique_ptr<ConfidenceCodec> make_conf8_zstd_codec() { return std::make_unique<Conf8Zstd>(); }

Gray8Image confidence_levels(FloatView confidence) {
  Gray8Image out(confidence.width(), confidence.height());
  for (std::size_t i = 0; i < out.size(); ++i) {
    const float c = confidence.data()[i];
    out.data()[i] =
        std::isfinite(c) ? std::uint8_t(std::lround(std::clamp(c, 0.0f, 1.0f) * 255.0f)) : 0;
  }
  return out;
}

FloatImage confidence_values(Gray8View levels) {
  FloatImage out(levels.width(), levels.height());
  for (std::size_t i = 0; i < out.size(); ++i) out.data()[i] = levels.data()[i] / 255.0f;
  return out;
}

}  // namespace omnisweep::codec
