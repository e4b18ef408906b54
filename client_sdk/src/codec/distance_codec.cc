// Distance as 16-bit quantised inverse distance, LOCO-I median prediction, zigzag residuals in
// byte planes, zstd.
//
// Inverse distance is uniform in what stereo resolves, so quantising it (not distance) spends
// the levels where they matter. The map is cut into kBands horizontal bands, each predicted and
// compressed on its own, so bands encode and decode on separate threads; the band count is
// fixed, so the bytes do not depend on the machine. Payload (integers uint32 little endian):
//   "OSQ2", stored width, stored height, band count B, B compressed band sizes, then B zstd
//   frames (with content checksums), each holding the high bytes of the band's zigzagged
//   residuals, then their low bytes.
// The predictor, zigzag and plane split are written here because no library here offers them
// for 16-bit depth (PNG's filters are byte-wise and its deflate is 10x slower); zstd does the
// entropy coding.
#include <zstd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <mutex>
#include <thread>

#include "src/codec/codecs.h"

namespace omnisweep::codec {
namespace {

constexpr char kMagic[4] = {'O', 'S', 'Q', '2'};
constexpr std::size_t kFixedHeader = 16;
constexpr std::uint64_t kMaxPixels = std::uint64_t(1) << 26;
constexpr int kBands = 4;

void put_u32(std::uint8_t* p, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = std::uint8_t(v >> (8 * i));
}
std::uint32_t get_u32(const std::uint8_t* p) {
  std::uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= std::uint32_t(p[i]) << (8 * i);
  return v;
}

// LOCO-I / JPEG-LS median edge detector: a = left, b = up, c = up-left.
inline int median_predict(int a, int b, int c) {
  const int hi = std::max(a, b), lo = std::min(a, b);
  return c >= hi ? lo : (c <= lo ? hi : a + b - c);
}
inline std::uint16_t zigzag(std::uint16_t r) {
  return std::uint16_t((r << 1) ^ std::uint16_t(std::int16_t(r) >> 15));
}
inline std::uint16_t unzigzag(std::uint16_t z) { return std::uint16_t((z >> 1) ^ -(z & 1)); }

// Rows [y0, y1) of a band; a band's first row sees no row above (bands decode independently).
struct Band {
  int y0, y1;
};
std::vector<Band> bands_of(int h) {
  const int count = std::min(kBands, h);
  std::vector<Band> bands(count);
  for (int i = 0; i < count; ++i) bands[i] = {h * i / count, h * (i + 1) / count};
  return bands;
}

// Runs job(i) for every band, on up to one thread per band.
template <typename Job>
void for_each_band(int count, const Job& job) {
  const int threads = std::clamp(int(std::thread::hardware_concurrency()), 1, count);
  std::vector<std::thread> pool;
  std::vector<std::exception_ptr> errors(threads);
  auto worker = [&](int t) {
    try {
      for (int i = t; i < count; i += threads) job(i);
    } catch (...) {
      errors[t] = std::current_exception();
    }
  };
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker, t);
  worker(0);
  for (auto& thread : pool) thread.join();
  for (const auto& error : errors)
    if (error) std::rethrow_exception(error);
}

// Quantised levels (0 = no value) of rows [band.y0, band.y1) of the stored w-wide map.
void quantise(const FloatImage& distance, const DistanceParams& params, int w, const Band& band,
              std::uint16_t* q) {
  const float lo = 1.0f / params.max_distance, hi = 1.0f / params.min_distance;
  const float scale = float(params.levels - 1) / (hi - lo);
  const int ds = int(params.downsample);
  if (ds == 1) {
    const float* d = distance.data() + std::size_t(band.y0) * w;
    const std::size_t n = std::size_t(band.y1 - band.y0) * w;
    q += std::size_t(band.y0) * w;
    for (std::size_t i = 0; i < n; ++i) {  // branch-free, so the compiler can vectorise it
      const float v = d[i];
      // lo first: max(lo, NaN) is lo, so no NaN reaches the conversion to int below (UB).
      const float inv = std::min(std::max(lo, 1.0f / v), hi);
      const auto level = std::int32_t((inv - lo) * scale + 1.5f);
      const std::int32_t valid = std::int32_t(v > 0.0f) & std::int32_t(v < INFINITY);
      q[i] = std::uint16_t(level * valid);
    }
    return;
  }
  for (int y = band.y0; y < band.y1; ++y) {
    for (int x = 0; x < w; ++x) {
      float sum = 0;  // mean inverse distance of the valid pixels of the block
      int n = 0;
      for (int sy = y * ds; sy < std::min((y + 1) * ds, distance.height()); ++sy)
        for (int sx = x * ds; sx < std::min((x + 1) * ds, distance.width()); ++sx) {
          const float v = distance(sx, sy);
          if (v > 0.0f && v < INFINITY) {
            sum += 1.0f / v;
            ++n;
          }
        }
      const float inv = n ? std::min(std::max(sum / float(n), lo), hi) : 0.0f;
      q[std::size_t(y) * w + x] = std::uint16_t(n ? (inv - lo) * scale + 1.5f : 0.0f);
    }
  }
}

// What one band needs between frames: reusing the buffers and zstd contexts avoids
// allocating (and page-faulting) megabytes per frame.
struct BandScratch {
  std::vector<std::uint8_t> planes;
  Bytes frame;
  std::unique_ptr<ZSTD_CCtx, decltype(&ZSTD_freeCCtx)> cctx{nullptr, ZSTD_freeCCtx};
  std::unique_ptr<ZSTD_DCtx, decltype(&ZSTD_freeDCtx)> dctx{nullptr, ZSTD_freeDCtx};
};

// Zigzagged prediction residuals of one band as byte planes (high bytes, then low bytes).
void residual_planes(const std::uint16_t* q, int w, const Band& band, std::uint8_t* high,
                     std::uint8_t* low) {
  for (int y = band.y0; y < band.y1; ++y) {
    const std::uint16_t* row = q + std::size_t(y) * w;
    const std::uint16_t* up = row - w;
    const std::size_t o = std::size_t(y - band.y0) * w;
    auto put = [&](int x, int prediction) {
      const std::uint16_t z = zigzag(std::uint16_t(row[x] - prediction));
      high[o + x] = std::uint8_t(z >> 8);
      low[o + x] = std::uint8_t(z);
    };
    if (y == band.y0) {
      put(0, 0);
      for (int x = 1; x < w; ++x) put(x, row[x - 1]);
      continue;
    }
    put(0, up[0]);
    for (int x = 1; x < w; ++x) put(x, median_predict(row[x - 1], up[x], up[x - 1]));
  }
}

// Inverse of residual_planes; throws on a level beyond the quantisation range.
void reconstruct(const std::uint8_t* high, const std::uint8_t* low, int w, const Band& band,
                 std::uint32_t levels, std::uint16_t* q) {
  for (int y = band.y0; y < band.y1; ++y) {
    std::uint16_t* row = q + std::size_t(y) * w;
    const std::uint16_t* up = row - w;
    const std::size_t o = std::size_t(y - band.y0) * w;
    std::uint32_t worst = 0;
    auto get = [&](int x, int prediction) {
      row[x] = std::uint16_t(unzigzag(std::uint16_t((high[o + x] << 8) | low[o + x])) + prediction);
      worst = std::max<std::uint32_t>(worst, row[x]);
    };
    if (y == band.y0) {
      get(0, 0);
      for (int x = 1; x < w; ++x) get(x, row[x - 1]);
    } else {
      get(0, up[0]);
      for (int x = 1; x < w; ++x) get(x, median_predict(row[x - 1], up[x], up[x - 1]));
    }
    if (worst > levels)
      throw CodecError("qinv16-zstd: corrupt payload: level beyond the quantisation range");
  }
}

class QuantisedInverseDistanceCodec final : public DistanceCodec {
  // Scratch reused across calls; the mutex makes concurrent calls on one codec safe.
  mutable std::mutex mutex_;
  mutable std::vector<std::uint16_t> levels_;
  mutable std::array<BandScratch, kBands> bands_;

 public:
  std::string name() const override { return "qinv16-zstd"; }

  Bytes encode(const FloatImage& distance, const DistanceParams& params) const override {
    params.check();
    if (distance.empty() || distance.channels() != 1)
      throw CodecError("qinv16-zstd: expects a one-channel map");
    const int ds = int(params.downsample);
    const int w = (distance.width() + ds - 1) / ds, h = (distance.height() + ds - 1) / ds;
    const std::lock_guard lock(mutex_);
    levels_.resize(std::size_t(w) * h);
    const std::vector<Band> bands = bands_of(h);
    for_each_band(int(bands.size()), [&](int i) {
      quantise(distance, params, w, bands[i], levels_.data());
      const std::size_t n = std::size_t(bands[i].y1 - bands[i].y0) * w;
      BandScratch& scratch = bands_[i];
      scratch.planes.resize(2 * n);
      residual_planes(levels_.data(), w, bands[i], scratch.planes.data(),
                      scratch.planes.data() + n);
      if (!scratch.cctx) {
        scratch.cctx.reset(ZSTD_createCCtx());
        if (!scratch.cctx) throw CodecError("qinv16-zstd: out of memory");
        ZSTD_CCtx_setParameter(scratch.cctx.get(), ZSTD_c_compressionLevel, 1);
        ZSTD_CCtx_setParameter(scratch.cctx.get(), ZSTD_c_checksumFlag, 1);
      }
      scratch.frame.resize(ZSTD_compressBound(scratch.planes.size()));
      const std::size_t size =
          ZSTD_compress2(scratch.cctx.get(), scratch.frame.data(), scratch.frame.size(),
                         scratch.planes.data(), scratch.planes.size());
      if (ZSTD_isError(size))
        throw CodecError(std::string("qinv16-zstd: zstd failed: ") + ZSTD_getErrorName(size));
      scratch.frame.resize(size);
    });
    std::size_t total = kFixedHeader + 4 * bands.size();
    for (std::size_t i = 0; i < bands.size(); ++i) total += bands_[i].frame.size();
    Bytes out(total);
    std::memcpy(out.data(), kMagic, 4);
    put_u32(out.data() + 4, std::uint32_t(w));
    put_u32(out.data() + 8, std::uint32_t(h));
    put_u32(out.data() + 12, std::uint32_t(bands.size()));
    std::size_t at = kFixedHeader + 4 * bands.size();
    for (std::size_t i = 0; i < bands.size(); ++i) {
      const Bytes& frame = bands_[i].frame;
      put_u32(out.data() + kFixedHeader + 4 * i, std::uint32_t(frame.size()));
      std::memcpy(out.data() + at, frame.data(), frame.size());
      at += frame.size();
    }
    return out;
  }

  FloatImage decode(std::span<const std::uint8_t> payload, int width, int height,
                    const DistanceParams& params) const override {
    params.check();
    if (payload.size() < kFixedHeader || std::memcmp(payload.data(), kMagic, 4) != 0) {
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
    const std::vector<Band> bands = bands_of(h);
    if (get_u32(payload.data() + 12) != bands.size() ||
        payload.size() < kFixedHeader + 4 * bands.size()) {
      throw CodecError("qinv16-zstd: corrupt payload: band table does not match " +
                       std::to_string(bands.size()) + " bands");
    }
    std::vector<std::span<const std::uint8_t>> frames;
    std::size_t at = kFixedHeader + 4 * bands.size();
    for (std::size_t i = 0; i < bands.size(); ++i) {
      const std::size_t size = get_u32(payload.data() + kFixedHeader + 4 * i);
      if (size > payload.size() - at)
        throw CodecError("qinv16-zstd: payload is truncated (band " + std::to_string(i) + ")");
      frames.push_back(payload.subspan(at, size));
      at += size;
    }
    if (at != payload.size())
      throw CodecError("qinv16-zstd: corrupt payload: " + std::to_string(payload.size() - at) +
                       " bytes after the last band");
    const double lo = 1.0 / params.max_distance, hi = 1.0 / params.min_distance;
    const double step = (hi - lo) / double(params.levels - 1);
    std::vector<float> metres(params.levels + 1, 0.0f);
    for (std::uint32_t level = 1; level <= params.levels; ++level)
      metres[level] = float(1.0 / (lo + (level - 1) * step));
    FloatImage out(width, height, 1);
    const std::lock_guard lock(mutex_);
    std::vector<std::uint16_t>& q = levels_;
    q.resize(std::size_t(w) * h);
    for_each_band(int(bands.size()), [&](int i) {
      const std::size_t n = std::size_t(bands[i].y1 - bands[i].y0) * w;
      const unsigned long long content = ZSTD_getFrameContentSize(frames[i].data(), frames[i].size());
      if (content != 2 * n) {
        throw CodecError("qinv16-zstd: band " + std::to_string(i) +
                         " is truncated or does not hold 2 bytes per sample");
      }
      BandScratch& scratch = bands_[i];
      std::vector<std::uint8_t>& planes = scratch.planes;
      planes.resize(2 * n);
      if (!scratch.dctx) {
        scratch.dctx.reset(ZSTD_createDCtx());
        if (!scratch.dctx) throw CodecError("qinv16-zstd: out of memory");
      }
      const std::size_t got = ZSTD_decompressDCtx(scratch.dctx.get(), planes.data(), planes.size(),
                                                  frames[i].data(), frames[i].size());
      if (ZSTD_isError(got) || got != planes.size()) {
        throw CodecError(std::string("qinv16-zstd: corrupt payload: ") +
                         (ZSTD_isError(got) ? ZSTD_getErrorName(got) : "short"));
      }
      reconstruct(planes.data(), planes.data() + n, w, bands[i], params.levels, q.data());
      // Level -> metres by lookup, for the output rows this band covers.
      for (int y = bands[i].y0 * ds; y < std::min(bands[i].y1 * ds, height); ++y) {
        const std::uint16_t* row = q.data() + std::size_t(y / ds) * w;
        float* dst = out.data() + std::size_t(y) * width;
        if (ds == 1) {
          for (int x = 0; x < width; ++x) dst[x] = metres[row[x]];
        } else {
          for (int x = 0; x < width; ++x) dst[x] = metres[row[x / ds]];
        }
      }
    });
    return out;
  }
};

}  // namespace

std::unique_ptr<DistanceCodec> make_qinv16_zstd_codec() {
  return std::make_unique<QuantisedInverseDistanceCodec>();
}

}  // namespace omnisweep::codec
