// Distance as 16-bit quantised inverse distance, planar prediction, zigzag residuals sorted
// into context streams, zstd.
//
// Inverse distance is uniform in what stereo resolves, so quantising it (not distance) spends
// the levels where they matter. The map is cut into kBands horizontal bands, each predicted and
// compressed on its own, so bands encode and decode on separate threads; the band count is
// fixed, so the bytes do not depend on the machine. Payload (integers uint32 little endian):
//   "OSQ3", stored width, stored height, band count B, per band its compressed size and the
//   kContexts context-stream lengths, then B zstd frames (with content checksums), each holding
//   the band's context streams one after another, then its escape stream.
// Prediction, zigzag and context sorting are written here because no library here offers them
// for 16-bit depth (PNG's filters are byte-wise, its deflate 10x slower and 50 % larger);
// zstd does the entropy coding. Estimated maps are smooth surfaces with stitching jitter, so
// the planar predictor (left + up - up-left) beats LOCO-I's median (5 % smaller on kaist-rig),
// and the contexts let zstd's Huffman tables follow the jitter's local size.
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

constexpr char kMagic[4] = {'O', 'S', 'Q', '3'};
constexpr std::size_t kFixedHeader = 16;
constexpr std::uint64_t kMaxPixels = std::uint64_t(1) << 26;
constexpr int kBands = 4;
constexpr int kContexts = 8;
// Per band: its compressed size, then the length of each context stream.
constexpr std::size_t kBandEntry = 4 + 4 * kContexts;

void put_u32(std::uint8_t* p, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = std::uint8_t(v >> (8 * i));
}
std::uint32_t get_u32(const std::uint8_t* p) {
  std::uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= std::uint32_t(p[i]) << (8 * i);
  return v;
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

// Levels of n distances, branch-free so the compiler vectorises it. Not inlined: GCC 12
// vectorises this loop on its own but not once inlined into quantise ("control flow in loop").
[[gnu::noinline]] void quantise_span(const float* __restrict d, std::size_t n, float lo, float hi,
                                     float scale, std::uint16_t* __restrict out) {
  for (std::size_t i = 0; i < n; ++i) {
    const float v = d[i], r = 1.0f / v;
    // A NaN r fails r > lo and becomes lo: no NaN reaches the conversion to int below (UB).
    const float clamped = r > lo ? r : lo;
    const float inv = clamped < hi ? clamped : hi;
    const auto level = std::int32_t((inv - lo) * scale + 1.5f);
    const std::int32_t valid = std::int32_t(v > 0.0f) & std::int32_t(v < INFINITY);
    out[i] = std::uint16_t(level * valid);
  }
}

// Quantised levels (0 = no value) of rows [band.y0, band.y1) of the stored w-wide map.
void quantise(const FloatImage& distance, const DistanceParams& params, int w, const Band& band,
              std::uint16_t* q) {
  const float lo = 1.0f / params.max_distance, hi = 1.0f / params.min_distance;
  const float scale = float(params.levels - 1) / (hi - lo);
  const int ds = int(params.downsample);
  if (ds == 1) {
    const std::size_t offset = std::size_t(band.y0) * w;
    quantise_span(distance.data() + offset, std::size_t(band.y1 - band.y0) * w, lo, hi, scale,
                  q + offset);
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
  std::vector<std::uint16_t> residuals;         // one row
  std::vector<std::uint8_t> contexts, escapes;  // one row; the band's escapes
  std::array<std::unique_ptr<std::uint8_t[]>, kContexts> context_bytes;  // encoder, n each
  std::size_t capacity = 0;                                              // of context_bytes
  std::vector<std::uint8_t> streams;  // the band's streams, joined
  Bytes frame;
  std::array<std::uint32_t, kContexts> counts{};
  std::unique_ptr<ZSTD_CCtx, decltype(&ZSTD_freeCCtx)> cctx{nullptr, ZSTD_freeCCtx};
  std::unique_ptr<ZSTD_DCtx, decltype(&ZSTD_freeDCtx)> dctx{nullptr, ZSTD_freeDCtx};
};

// Context of a sample: how much the row above varies around it, s = |b - c| + |d - b| (b up,
// c up-left, d up-right), as the bit width of s: 0, 1, 2-3, 4-7, ..., 64 and more (8 classes);
// the last class also takes a band's first row and the first and last columns. Residuals of
// one class share a distribution much narrower than the mixture's, and zstd codes each class's
// stream with its own Huffman tables: 5 % smaller than one stream on estimated maps (as small
// as 12 finer classes). Only the row above is used, so the decoder knows a row's contexts
// before it decodes the row and rebuilds the row with a running sum.
constexpr std::uint8_t kEdgeContext = kContexts - 1;

// Contexts of the w samples below `up` (nullptr: a band's first row). Written in 16-bit
// saturating arithmetic and comparisons, which compilers vectorise (SSE2's psubusw, NEON's
// uqsub): |p - q| = (p -sat q) | (q -sat p), each capped at 127 so the sum fits, and the bit
// width of s <= 127 as the count of the bounds 0, 1, 3, ..., 63 below it.
inline std::uint16_t saturating_sub(std::uint16_t a, std::uint16_t b) {
  return a > b ? std::uint16_t(a - b) : std::uint16_t(0);
}
inline void row_contexts(const std::uint16_t* __restrict up, int w, std::uint8_t* __restrict k) {
  static_assert(kContexts == 8, "the bounds below make 8 contexts");
  if (!up) {
    std::fill(k, k + w, kEdgeContext);
    return;
  }
  k[0] = kEdgeContext;
  for (int x = 1; x < w - 1; ++x) {
    const std::uint16_t left = saturating_sub(up[x], up[x - 1]) | saturating_sub(up[x - 1], up[x]);
    const std::uint16_t right = saturating_sub(up[x + 1], up[x]) | saturating_sub(up[x], up[x + 1]);
    const std::uint16_t s = std::uint16_t(left - saturating_sub(left, 127)) +
                            std::uint16_t(right - saturating_sub(right, 127));
    k[x] = std::uint8_t((s > 0) + (s > 1) + (s > 3) + (s > 7) + (s > 15) + (s > 31) + (s > 63));
  }
  if (w > 1) k[w - 1] = kEdgeContext;
}

// Zigzagged residual z < 255 is one byte of its context's stream; larger ones are the byte
// 255 there and z (2 bytes, little endian) in the escape stream.
constexpr std::uint8_t kEscape = 255;

// Encodes rows [y0, y1) of the stored map into scratch.streams: the kContexts context streams
// one after another (lengths in scratch.counts), then the escape stream. The prediction is
// planar, left + up - up-left (left on a band's first row, up in the first column), in
// arithmetic modulo 2^16. One pass: each row's residuals and contexts stay in cache, and each
// symbol goes straight to its context's buffer.
void residual_streams(const std::uint16_t* q, int w, const Band& band, BandScratch& scratch) {
  const std::size_t n = std::size_t(band.y1 - band.y0) * w;
  if (scratch.capacity < n) {
    // Not zero-filled: only the bytes written are touched.
    for (auto& buffer : scratch.context_bytes) buffer.reset(new std::uint8_t[n]);
    scratch.capacity = n;
  }
  std::array<std::uint8_t*, kContexts> out;
  for (int k = 0; k < kContexts; ++k) out[k] = scratch.context_bytes[k].get();
  scratch.residuals.resize(w);
  scratch.contexts.resize(w);
  std::uint16_t* __restrict z = scratch.residuals.data();
  std::uint8_t* __restrict context = scratch.contexts.data();
  std::vector<std::uint8_t>& escapes = scratch.escapes;
  escapes.clear();
  for (int y = band.y0; y < band.y1; ++y) {
    const std::uint16_t* __restrict row = q + std::size_t(y) * w;
    const std::uint16_t* __restrict up = y == band.y0 ? nullptr : row - w;
    row_contexts(up, w, context);
    z[0] = zigzag(std::uint16_t(row[0] - (up ? up[0] : 0)));
    if (up) {
      for (int x = 1; x < w; ++x)
        z[x] = zigzag(std::uint16_t(row[x] - row[x - 1] - up[x] + up[x - 1]));
    } else {
      for (int x = 1; x < w; ++x) z[x] = zigzag(std::uint16_t(row[x] - row[x - 1]));
    }
    for (int x = 0; x < w; ++x) {
      const std::uint16_t v = z[x];
      *out[context[x]]++ = std::uint8_t(std::min<std::uint16_t>(v, kEscape));
      if (v >= kEscape) [[unlikely]] {
        escapes.push_back(std::uint8_t(v));
        escapes.push_back(std::uint8_t(v >> 8));
      }
    }
  }
  scratch.streams.resize(n + escapes.size());
  std::uint8_t* joined = scratch.streams.data();
  for (int k = 0; k < kContexts; ++k) {
    scratch.counts[k] = std::uint32_t(out[k] - scratch.context_bytes[k].get());
    std::memcpy(joined, scratch.context_bytes[k].get(), scratch.counts[k]);
    joined += scratch.counts[k];
  }
  if (!escapes.empty()) std::memcpy(joined, escapes.data(), escapes.size());  // data() may be null
}

// Inverse of residual_streams over `content` (the decompressed band); throws on streams that
// do not add up and on a level beyond the quantisation range.
void reconstruct(std::span<const std::uint8_t> content,
                 const std::array<std::uint32_t, kContexts>& counts, int w, const Band& band,
                 std::uint32_t levels, BandScratch& scratch, std::uint16_t* q) {
  const std::size_t n = std::size_t(band.y1 - band.y0) * w;
  std::array<const std::uint8_t*, kContexts> next{}, end{};
  const std::uint8_t* p = content.data();
  for (int k = 0; k < kContexts; ++k) {
    next[k] = p;
    p += counts[k];
    end[k] = p;
  }
  const std::uint8_t* escape = content.data() + n;
  const std::uint8_t* const escape_end = content.data() + content.size();
  auto corrupt = [](const char* what) {
    throw CodecError(std::string("qinv16-zstd: corrupt payload: ") + what);
  };
  scratch.contexts.resize(w);
  scratch.residuals.resize(w);
  std::uint8_t* __restrict context = scratch.contexts.data();
  std::uint16_t* __restrict z = scratch.residuals.data();
  for (int y = band.y0; y < band.y1; ++y) {
    std::uint16_t* __restrict row = q + std::size_t(y) * w;
    const std::uint16_t* __restrict up = y == band.y0 ? nullptr : row - w;
    // The row's residuals, from its contexts alone...
    row_contexts(up, w, context);
    for (int x = 0; x < w; ++x) {
      const std::uint8_t k = context[x];
      if (next[k] == end[k]) corrupt("a context stream is short");
      std::uint16_t v = *next[k]++;
      if (v == kEscape) {
        if (escape_end - escape < 2) corrupt("the escape stream is short");
        v = std::uint16_t(escape[0] | (escape[1] << 8));
        escape += 2;
      }
      z[x] = unzigzag(v);
    }
    // ...then the levels, a running sum along the row.
    row[0] = std::uint16_t(z[0] + (up ? up[0] : 0));
    if (up) {
      for (int x = 1; x < w; ++x) row[x] = std::uint16_t(z[x] + row[x - 1] + up[x] - up[x - 1]);
    } else {
      for (int x = 1; x < w; ++x) row[x] = std::uint16_t(z[x] + row[x - 1]);
    }
    if (*std::max_element(row, row + w) > levels) corrupt("level beyond the quantisation range");
  }
  if (escape != escape_end) corrupt("bytes left in the escape stream");
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
      BandScratch& scratch = bands_[i];
      residual_streams(levels_.data(), w, bands[i], scratch);
      if (!scratch.cctx) {
        scratch.cctx.reset(ZSTD_createCCtx());
        if (!scratch.cctx) throw CodecError("qinv16-zstd: out of memory");
        ZSTD_CCtx_setParameter(scratch.cctx.get(), ZSTD_c_compressionLevel, 1);
        // A 256-entry match table: on these streams the longer matches a larger table finds
        // do not pay for the literals they split (3 % smaller, and faster).
        ZSTD_CCtx_setParameter(scratch.cctx.get(), ZSTD_c_hashLog, 8);
        ZSTD_CCtx_setParameter(scratch.cctx.get(), ZSTD_c_checksumFlag, 1);
      }
      scratch.frame.resize(ZSTD_compressBound(scratch.streams.size()));
      const std::size_t size =
          ZSTD_compress2(scratch.cctx.get(), scratch.frame.data(), scratch.frame.size(),
                         scratch.streams.data(), scratch.streams.size());
      if (ZSTD_isError(size))
        throw CodecError(std::string("qinv16-zstd: zstd failed: ") + ZSTD_getErrorName(size));
      scratch.frame.resize(size);
    });
    const std::size_t table = kFixedHeader + kBandEntry * bands.size();
    std::size_t total = table;
    for (std::size_t i = 0; i < bands.size(); ++i) total += bands_[i].frame.size();
    Bytes out(total);
    std::memcpy(out.data(), kMagic, 4);
    put_u32(out.data() + 4, std::uint32_t(w));
    put_u32(out.data() + 8, std::uint32_t(h));
    put_u32(out.data() + 12, std::uint32_t(bands.size()));
    std::size_t at = table;
    for (std::size_t i = 0; i < bands.size(); ++i) {
      const BandScratch& band = bands_[i];
      std::uint8_t* entry = out.data() + kFixedHeader + kBandEntry * i;
      put_u32(entry, std::uint32_t(band.frame.size()));
      for (int k = 0; k < kContexts; ++k) put_u32(entry + 4 + 4 * k, band.counts[k]);
      std::memcpy(out.data() + at, band.frame.data(), band.frame.size());
      at += band.frame.size();
    }
    return out;
  }

  FloatImage decode(std::span<const std::uint8_t> payload, int width, int height,
                    const DistanceParams& params) const override {
    params.check();
    if (payload.size() >= 4 && std::memcmp(payload.data(), "OSQ2", 4) == 0) {
      throw CodecError(
          "qinv16-zstd: an OSQ2 payload (median prediction, byte planes) from a pre-release "
          "omnisweep; this version reads OSQ3");
    }
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
        payload.size() < kFixedHeader + kBandEntry * bands.size()) {
      throw CodecError("qinv16-zstd: corrupt payload: band table does not match " +
                       std::to_string(bands.size()) + " bands");
    }
    std::vector<std::span<const std::uint8_t>> frames;
    std::vector<std::array<std::uint32_t, kContexts>> counts(bands.size());
    std::size_t at = kFixedHeader + kBandEntry * bands.size();
    for (std::size_t i = 0; i < bands.size(); ++i) {
      const std::uint8_t* entry = payload.data() + kFixedHeader + kBandEntry * i;
      const std::size_t size = get_u32(entry);
      if (size > payload.size() - at)
        throw CodecError("qinv16-zstd: payload is truncated (band " + std::to_string(i) + ")");
      frames.push_back(payload.subspan(at, size));
      at += size;
      std::uint64_t samples = 0;
      for (int k = 0; k < kContexts; ++k) samples += counts[i][k] = get_u32(entry + 4 + 4 * k);
      if (samples != std::uint64_t(bands[i].y1 - bands[i].y0) * std::uint64_t(w))
        throw CodecError("qinv16-zstd: corrupt payload: band " + std::to_string(i) +
                         " context streams do not add up to its samples");
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
      // n one-byte symbols, then 2 bytes per escaped one (at most one per sample).
      const unsigned long long content =
          ZSTD_getFrameContentSize(frames[i].data(), frames[i].size());
      if (content == ZSTD_CONTENTSIZE_UNKNOWN || content == ZSTD_CONTENTSIZE_ERROR || content < n ||
          content > 3 * n || (content - n) % 2 != 0) {
        throw CodecError("qinv16-zstd: band " + std::to_string(i) +
                         " is truncated or does not hold one symbol per sample");
      }
      BandScratch& scratch = bands_[i];
      std::vector<std::uint8_t>& streams = scratch.streams;
      streams.resize(content);
      if (!scratch.dctx) {
        scratch.dctx.reset(ZSTD_createDCtx());
        if (!scratch.dctx) throw CodecError("qinv16-zstd: out of memory");
      }
      const std::size_t got = ZSTD_decompressDCtx(
          scratch.dctx.get(), streams.data(), streams.size(), frames[i].data(), frames[i].size());
      if (ZSTD_isError(got) || got != streams.size()) {
        throw CodecError(std::string("qinv16-zstd: corrupt payload: ") +
                         (ZSTD_isError(got) ? ZSTD_getErrorName(got) : "short"));
      }
      reconstruct(streams, counts[i], w, bands[i], params.levels, scratch, q.data());
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
