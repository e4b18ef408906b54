// Distance as 16-bit quantised inverse distance, LOCO-I median prediction, byte planes, zstd.
//
// Payload: "OSQ1", stored width and height (uint32 little endian), then one zstd frame (with
// content checksum) holding the high bytes of every residual, then the low bytes. Inverse
// distance is uniform in what stereo resolves, so quantising it (not distance) spends the
// levels where they matter. The predictor and the plane split are written here because no
// library here offers them for 16-bit depth; zstd does the entropy coding.
#include <zstd.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "src/codec/codecs.h"

namespace omnisweep::codec {
namespace {

constexpr char kMagic[4] = {'O', 'S', 'Q', '1'};
constexpr std::size_t kHeader = 12;
constexpr std::uint64_t kMaxPixels = std::uint64_t(1) << 26;

std::uint16_t predict(const std::vector<std::uint16_t>& q, int w, int x, int y) {
  const int a = x > 0 ? q[std::size_t(y) * w + x - 1] : 0;
  const int b = y > 0 ? q[std::size_t(y - 1) * w + x] : 0;
  const int c = x > 0 && y > 0 ? q[std::size_t(y - 1) * w + x - 1] : 0;
  if (c >= std::max(a, b)) return std::uint16_t(std::min(a, b));
  if (c <= std::min(a, b)) return std::uint16_t(std::max(a, b));
  return std::uint16_t(a + b - c);
}

void put_u32(std::uint8_t* p, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = std::uint8_t(v >> (8 * i));
}
std::uint32_t get_u32(const std::uint8_t* p) {
  std::uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= std::uint32_t(p[i]) << (8 * i);
  return v;
}

class QuantisedInverseDistanceCodec final : public DistanceCodec {
 public:
  std::string name() const override { return "qinv16-zstd"; }

  Bytes encode(const FloatImage& distance, const DistanceParams& params) const override {
    params.check();
    if (distance.empty() || distance.channels() != 1)
      throw CodecError("qinv16-zstd: expects a one-channel map");
    const int ds = int(params.downsample);
    const int w = (distance.width() + ds - 1) / ds, h = (distance.height() + ds - 1) / ds;
    const double lo = 1.0 / params.max_distance, hi = 1.0 / params.min_distance;
    const double scale = double(params.levels - 1) / (hi - lo);
    std::vector<std::uint16_t> q(std::size_t(w) * h, 0);
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        double sum = 0;  // mean inverse distance of the valid pixels of the block
        int n = 0;
        for (int dy = 0; dy < ds; ++dy)
          for (int dx = 0; dx < ds; ++dx) {
            const int sx = x * ds + dx, sy = y * ds + dy;
            if (sx >= distance.width() || sy >= distance.height()) continue;
            const float d = distance(sx, sy);
            if (d > 0 && std::isfinite(d)) {
              sum += 1.0 / d;
              ++n;
            }
          }
        if (n == 0) continue;
        const double level = std::round((std::clamp(sum / n, lo, hi) - lo) * scale);
        q[std::size_t(y) * w + x] = std::uint16_t(1 + level);
      }
    }
    std::vector<std::uint8_t> planes(2 * q.size());
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const std::size_t i = std::size_t(y) * w + x;
        const auto residual = std::uint16_t(q[i] - predict(q, w, x, y));
        planes[i] = std::uint8_t(residual >> 8);
        planes[q.size() + i] = std::uint8_t(residual & 255);
      }
    }
    Bytes out(kHeader + ZSTD_compressBound(planes.size()));
    std::memcpy(out.data(), kMagic, 4);
    put_u32(out.data() + 4, std::uint32_t(w));
    put_u32(out.data() + 8, std::uint32_t(h));
    ZSTD_CCtx* cctx = ZSTD_createCCtx();
    if (!cctx) throw CodecError("qinv16-zstd: out of memory");
    ZSTD_CCtx_setParameter(cctx, ZSTD_c_compressionLevel, 1);
    ZSTD_CCtx_setParameter(cctx, ZSTD_c_checksumFlag, 1);
    const std::size_t size = ZSTD_compress2(cctx, out.data() + kHeader, out.size() - kHeader,
                                            planes.data(), planes.size());
    ZSTD_freeCCtx(cctx);
    if (ZSTD_isError(size))
      throw CodecError(std::string("qinv16-zstd: zstd failed: ") + ZSTD_getErrorName(size));
    out.resize(kHeader + size);
    return out;
  }

  FloatImage decode(std::span<const std::uint8_t> payload, int width, int height,
                    const DistanceParams& params) const override {
    params.check();
    if (payload.size() < kHeader || std::memcmp(payload.data(), kMagic, 4) != 0) {
      throw CodecError("qinv16-zstd: not a qinv16-zstd payload (" + std::to_string(payload.size()) +
                       " bytes)");
    }
    if (width <= 0 || height <= 0 || std::uint64_t(width) * height > kMaxPixels) {
      throw CodecError("qinv16-zstd: frame size " + std::to_string(width) + "x" +
                       std::to_string(height) + " is out of range");
    }
    const int ds = int(params.downsample);
    const int w = (width + ds - 1) / ds, h = (height + ds - 1) / ds;
    if (get_u32(payload.data() + 4) != std::uint32_t(w) ||
        get_u32(payload.data() + 8) != std::uint32_t(h)) {
      throw CodecError("qinv16-zstd: payload holds " + std::to_string(get_u32(payload.data() + 4)) +
                       "x" + std::to_string(get_u32(payload.data() + 8)) +
                       " samples, the frame expects " + std::to_string(w) + "x" +
                       std::to_string(h));
    }
    const std::size_t n = std::size_t(w) * h;
    const auto body = payload.subspan(kHeader);
    const unsigned long long content = ZSTD_getFrameContentSize(body.data(), body.size());
    if (content != 2 * n)
      throw CodecError(
          "qinv16-zstd: compressed frame is truncated or does not hold 2 bytes per sample");
    std::vector<std::uint8_t> planes(2 * n);
    const std::size_t got = ZSTD_decompress(planes.data(), planes.size(), body.data(), body.size());
    if (ZSTD_isError(got) || got != planes.size()) {
      throw CodecError(std::string("qinv16-zstd: corrupt payload: ") +
                       (ZSTD_isError(got) ? ZSTD_getErrorName(got) : "short"));
    }
    std::vector<std::uint16_t> q(n);
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const std::size_t i = std::size_t(y) * w + x;
        const auto residual = std::uint16_t((planes[i] << 8) | planes[n + i]);
        q[i] = std::uint16_t(residual + predict(q, w, x, y));
        if (q[i] > params.levels)
          throw CodecError("qinv16-zstd: corrupt payload: level beyond the quantisation range");
      }
    }
    const double lo = 1.0 / params.max_distance, hi = 1.0 / params.min_distance;
    const double step = (hi - lo) / double(params.levels - 1);
    FloatImage out(width, height, 1, 0.0f);
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        const std::uint16_t level = q[std::size_t(y / ds) * w + x / ds];
        if (level) out(x, y) = float(1.0 / (lo + (level - 1) * step));
      }
    }
    return out;
  }
};

}  // namespace

std::unique_ptr<DistanceCodec> make_qinv16_zstd_codec() {
  return std::make_unique<QuantisedInverseDistanceCodec>();
}

}  // namespace omnisweep::codec
