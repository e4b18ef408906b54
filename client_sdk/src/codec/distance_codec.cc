// Distance as 16-bit quantised inverse distance, planar prediction, zigzag residuals sorted
// into context streams, zstd.
//
// Inverse distance is uniform in what stereo resolves, so quantising it (not distance) spends
// the levels where they matter. The map is cut into kBands horizontal bands, each predicted and
// compressed on its own, so bands encode and decode on separate threads; the band count is
// fixed, so the bytes do not depend on the machine. Payload (integers uint32 little endian):
//   "OSQ4", stored width, stored height, band count B, per band its compressed size and the
//   kContexts context-stream lengths, then B zstd frames (with content checksums), each holding
//   the band's context streams one after another, then its escape stream.
// Prediction, zigzag and context sorting are written here because no library here offers them
// for 16-bit depth (PNG's filters are byte-wise, its deflate 10x slower and 50 % larger);
// zstd does the entropy coding. Estimated maps are smooth surfaces with stitching jitter, so
// the planar predictor (left + up - up-left) beats LOCO-I's median (5 % smaller on kaist-rig),
// the contexts let zstd's Huffman tables follow the jitter's local size, and coding quiet
// pixel pairs as one byte halves what zstd has to read there.
#include <zstd.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <mutex>
#include <thread>

#include "src/codec/codecs.h"

namespace omnisweep::codec {
namespace {

constexpr char kMagic[4] = {'O', 'S', 'Q', '4'};
constexpr std::size_t kFixedHeader = 16;
constexpr std::uint64_t kMaxPixels = std::uint64_t(1) << 26;
constexpr int kBands = 4;
constexpr int kContexts = 8;  // see pair_contexts
// Per band: its compressed size, then the length of each context stream.
constexpr std::size_t kBandEntry = 4 + 4 * kContexts;

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

// The loops below vectorise; on x86-64 GCC also builds them for AVX2 and picks that build at
// load time where the processor has it (function multi-versioning): Debian's baseline is SSE2,
// and AVX2 takes 40-60 % off these loops (quantiser 1.22 -> 0.72 ms, contexts 1.83 -> 0.76 ms per
// 2048x1024 map here). The results are the same bits either way (integer arithmetic, and no FMA
// in either build).
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define OMNISWEEP_AVX2_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define OMNISWEEP_AVX2_CLONES
#endif

// Levels of n distances, branch-free so the compiler vectorises it. Kept out of line: GCC 12
// vectorises this loop on its own but not once inlined into its caller ("control flow in loop").
// (A clone of it for constant bounds, which GCC may also make, is not vectorised; the
// multi-versioned build is never cloned so.)
[[gnu::noinline]] OMNISWEEP_AVX2_CLONES void quantise_span(const float* __restrict d, std::size_t n,
                                                           float lo, float hi, float scale,
                                                           std::uint16_t* __restrict out) {
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

// Levels (0 = no value) of row y of the stored w-wide map.
void quantise_row(FloatView distance, const DistanceParams& params, int w, int y,
                  std::uint16_t* q) {
  const float lo = 1.0f / params.max_distance, hi = 1.0f / params.min_distance;
  const float scale = float(params.levels - 1) / (hi - lo);
  const int ds = int(params.downsample);
  if (ds == 1) {
    quantise_span(distance.data() + std::size_t(y) * w, std::size_t(w), lo, hi, scale, q);
    return;
  }
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
    q[x] = std::uint16_t(n ? (inv - lo) * scale + 1.5f : 0.0f);
  }
}

// What one band needs between frames: reusing the buffers and zstd contexts avoids
// allocating (and page-faulting) megabytes per frame.
struct BandScratch {
  std::vector<std::uint16_t> residuals;                    // one row
  std::vector<std::uint16_t> levels;                       // encoder: this row's and the last row's
  std::vector<std::uint8_t> contexts, differences, codes;  // one row
  std::vector<std::uint8_t> escapes;                       // the band's
  std::array<std::unique_ptr<std::uint8_t[]>, kContexts> context_bytes;  // encoder
  std::size_t capacity = 0;                                              // of each
  std::vector<std::uint8_t> streams;  // the band's streams, joined
  Bytes frame;
  std::array<std::uint32_t, kContexts> lengths{};  // bytes of each context stream
  std::unique_ptr<ZSTD_CCtx, decltype(&ZSTD_freeCCtx)> cctx{nullptr, ZSTD_freeCCtx};
  std::unique_ptr<ZSTD_DCtx, decltype(&ZSTD_freeDCtx)> dctx{nullptr, ZSTD_freeDCtx};
};

// Samples are coded in horizontal pairs (x = 2j, 2j + 1). A pair's context is how much the row
// above varies over it: the bit width of s = |b0 - c| + |b1 - b0| + |d - b1| (c up-left of the
// pair, b0 b1 above it, d up-right; each term capped at 127), 0, 1, 2-3, ..., 64 and more: 8
// classes. The last class also takes a band's first row, pairs without c or d (a row's first
// pair, its last when the width is even) and the lone last sample of an odd-width row. Only the row
// above is used, so the decoder knows a row's contexts before it decodes the row. Each class's
// bytes form their own stream, which zstd codes with its own Huffman tables: a class's residuals
// are much narrower than the mixture's.
constexpr std::uint8_t kEdgeContext = kContexts - 1;
// Pairs in the classes below this are joint-coded, z0 * kPairBase + z1 in one byte when both
// zigzagged residuals are under kPairBase: where the jitter is small a byte per pair halves
// what zstd reads and codes two samples under one Huffman code, which beats the 1 bit a
// Huffman code costs at least (measured: 4-8 % smaller, 40 % fewer bytes for zstd).
constexpr int kPairedContexts = 6;
constexpr std::uint16_t kPairBase = 15;
// A pair code byte (< 225) or this byte, then the two samples' symbols.
constexpr std::uint8_t kPairEscape = 255;
// A sample's symbol: zigzagged residual z < 255 as one byte; larger ones are the byte 255 in the
// context stream and z (2 bytes, little endian) in the band's escape stream.
constexpr std::uint8_t kEscape = 255;

// Contexts of the w / 2 pairs (and a lone last sample) below `up` (nullptr: a band's first
// row) into k; e is scratch of w bytes. Both loops vectorise: the capped differences, then
// the class of each pair's sum s <= 381, its bit width read off the exponent of float(s)
// (exact for integers this small; 0 for s = 0).
OMNISWEEP_AVX2_CLONES void pair_contexts(const std::uint16_t* __restrict up, int w,
                                         std::uint8_t* __restrict e, std::uint8_t* __restrict k) {
  static_assert(std::numeric_limits<float>::is_iec559, "the class reads a float's exponent");
  const int slots = (w + 1) / 2;
  if (!up) {
    std::fill(k, k + slots, kEdgeContext);
    return;
  }
  for (int x = 1; x < w; ++x) {
    const int difference = int(up[x]) - int(up[x - 1]);
    e[x] = std::uint8_t(std::min(difference < 0 ? -difference : difference, 127));
  }
  k[0] = kEdgeContext;
  // Pair j covers samples 2j, 2j + 1: e[2j] is |b0 - c|, e[2j + 2] is |d - b1|.
  for (std::ptrdiff_t j = 1; 2 * j + 2 < w; ++j) {
    const float s = float(e[2 * j] + e[2 * j + 1] + e[2 * j + 2]);
    const std::int32_t exponent = (std::bit_cast<std::int32_t>(s) >> 23) - 126;
    k[j] = std::uint8_t(std::min(std::max(exponent, 0), kContexts - 1));
  }
  // The last pair when it has no d (even widths), or the lone last sample (odd widths).
  for (int j = std::max(1, (w - 1) / 2); j < slots; ++j) k[j] = kEdgeContext;
}

// The zigzagged residuals z of a row and every pair's joint code. The prediction is planar,
// left + up - up-left (left on a band's first row, up in the first column), in arithmetic
// modulo 2^16.
OMNISWEEP_AVX2_CLONES void row_residuals(const std::uint16_t* __restrict row,
                                         const std::uint16_t* __restrict up, int w,
                                         std::uint16_t* __restrict z,
                                         std::uint8_t* __restrict code) {
  z[0] = zigzag(std::uint16_t(row[0] - (up ? up[0] : 0)));
  if (up) {
    for (int x = 1; x < w; ++x)
      z[x] = zigzag(std::uint16_t(row[x] - row[x - 1] - up[x] + up[x - 1]));
  } else {
    for (int x = 1; x < w; ++x) z[x] = zigzag(std::uint16_t(row[x] - row[x - 1]));
  }
  for (std::ptrdiff_t j = 0; j < w / 2; ++j) {
    const std::uint32_t z0 = z[2 * j], z1 = z[2 * j + 1];
    code[j] =
        ((z0 < kPairBase) & (z1 < kPairBase)) ? std::uint8_t(z0 * kPairBase + z1) : kPairEscape;
  }
}

// Encodes rows [y0, y1) of the stored map into scratch.streams: the kContexts context streams
// one after another (byte lengths in scratch.lengths), then the escape stream. One pass: each
// row is quantised as it comes, its residuals and contexts stay in cache, and each pair goes
// straight to its context's buffer.
void residual_streams(FloatView distance, const DistanceParams& params, int w, const Band& band,
                      BandScratch& scratch) {
  const std::size_t rows = std::size_t(band.y1 - band.y0);
  // At most 3 bytes per pair (escaped pair code) and one per lone sample, in any one stream.
  const std::size_t bound = rows * (3 * std::size_t(w / 2) + 1);
  if (scratch.capacity < bound) {
    // Not zero-filled: only the bytes written are touched.
    for (auto& buffer : scratch.context_bytes) buffer.reset(new std::uint8_t[bound]);
    scratch.capacity = bound;
  }
  std::array<std::uint8_t*, kContexts> out;
  for (int k = 0; k < kContexts; ++k) out[k] = scratch.context_bytes[k].get();
  scratch.residuals.resize(w);
  scratch.contexts.resize(w);
  scratch.differences.resize(w);
  scratch.codes.resize(w);
  scratch.levels.resize(2 * std::size_t(w));
  std::uint16_t* level_row = scratch.levels.data();
  std::uint16_t* last_row = level_row + w;
  std::uint16_t* __restrict z = scratch.residuals.data();
  std::uint8_t* __restrict context = scratch.contexts.data();
  std::uint8_t* __restrict code = scratch.codes.data();
  std::vector<std::uint8_t>& escapes = scratch.escapes;
  escapes.clear();
  auto put = [&escapes](std::uint8_t*& stream, std::uint16_t v) {
    *stream++ = std::uint8_t(std::min<std::uint16_t>(v, kEscape));
    if (v >= kEscape) [[unlikely]] {
      escapes.push_back(std::uint8_t(v));
      escapes.push_back(std::uint8_t(v >> 8));
    }
  };
  const int pairs = w / 2;
  for (int y = band.y0; y < band.y1; ++y) {
    std::swap(level_row, last_row);
    quantise_row(distance, params, w, y, level_row);
    const std::uint16_t* __restrict row = level_row;
    const std::uint16_t* __restrict up = y == band.y0 ? nullptr : last_row;
    pair_contexts(up, w, scratch.differences.data(), context);
    row_residuals(row, up, w, z, code);
    for (std::ptrdiff_t j = 0; j < pairs; ++j) {
      std::uint8_t*& stream = out[context[j]];
      if (context[j] < kPairedContexts) {
        *stream++ = code[j];
        if (code[j] != kPairEscape) continue;
      }
      put(stream, z[2 * j]);
      put(stream, z[2 * j + 1]);
    }
    if (w % 2) put(out[kEdgeContext], z[w - 1]);
  }
  std::size_t total = escapes.size();
  for (int k = 0; k < kContexts; ++k) {
    scratch.lengths[k] = std::uint32_t(out[k] - scratch.context_bytes[k].get());
    total += scratch.lengths[k];
  }
  scratch.streams.resize(total);
  std::uint8_t* joined = scratch.streams.data();
  for (int k = 0; k < kContexts; ++k) {
    std::memcpy(joined, scratch.context_bytes[k].get(), scratch.lengths[k]);
    joined += scratch.lengths[k];
  }
  if (!escapes.empty()) std::memcpy(joined, escapes.data(), escapes.size());  // data() may be null
}

// Inverse of residual_streams over `content` (the decompressed band); throws on streams that
// do not add up and on a level beyond the quantisation range.
void reconstruct(std::span<const std::uint8_t> content,
                 const std::array<std::uint32_t, kContexts>& lengths, int w, const Band& band,
                 std::uint32_t levels, BandScratch& scratch, std::uint16_t* q) {
  std::array<const std::uint8_t*, kContexts> next{}, end{};
  const std::uint8_t* p = content.data();
  for (int k = 0; k < kContexts; ++k) {
    next[k] = p;
    p += lengths[k];
    end[k] = p;
  }
  const std::uint8_t* escape = p;
  const std::uint8_t* const escape_end = content.data() + content.size();
  auto corrupt = [](const char* what) {
    throw CodecError(error_prefix(kQinv16Zstd) + "corrupt payload: " + what);
  };
  auto byte = [&](int k) {
    if (next[k] == end[k]) corrupt("a context stream is short");
    return *next[k]++;
  };
  auto symbol = [&](int k) {
    std::uint16_t v = byte(k);
    if (v == kEscape) {
      if (escape_end - escape < 2) corrupt("the escape stream is short");
      v = std::uint16_t(escape[0] | (escape[1] << 8));
      escape += 2;
    }
    return v;
  };
  scratch.contexts.resize(w);
  scratch.residuals.resize(w);
  scratch.differences.resize(w);
  std::uint8_t* __restrict context = scratch.contexts.data();
  std::uint16_t* __restrict z = scratch.residuals.data();
  const int pairs = w / 2;
  for (int y = band.y0; y < band.y1; ++y) {
    std::uint16_t* __restrict row = q + std::size_t(y) * w;
    const std::uint16_t* __restrict up = y == band.y0 ? nullptr : row - w;
    // The row's residuals, from its contexts alone...
    pair_contexts(up, w, scratch.differences.data(), context);
    for (std::ptrdiff_t j = 0; j < pairs; ++j) {
      const int k = context[j];
      std::uint16_t z0 = 0, z1 = 0;
      if (k < kPairedContexts) {
        const std::uint8_t code = byte(k);
        if (code < kPairBase * kPairBase) {
          z0 = code / kPairBase;
          z1 = code % kPairBase;
        } else if (code == kPairEscape) {
          z0 = symbol(k);
          z1 = symbol(k);
        } else {
          corrupt("a pair code out of range");
        }
      } else {
        z0 = symbol(k);
        z1 = symbol(k);
      }
      z[2 * j] = unzigzag(z0);
      z[2 * j + 1] = unzigzag(z1);
    }
    if (w % 2) z[w - 1] = unzigzag(symbol(kEdgeContext));
    // ...then the levels, a running sum along the row.
    row[0] = std::uint16_t(z[0] + (up ? up[0] : 0));
    if (up) {
      for (int x = 1; x < w; ++x) row[x] = std::uint16_t(z[x] + row[x - 1] + up[x] - up[x - 1]);
    } else {
      for (int x = 1; x < w; ++x) row[x] = std::uint16_t(z[x] + row[x - 1]);
    }
    if (*std::max_element(row, row + w) > levels) corrupt("level beyond the quantisation range");
  }
  for (int k = 0; k < kContexts; ++k)
    if (next[k] != end[k]) corrupt("bytes left in a context stream");
  if (escape != escape_end) corrupt("bytes left in the escape stream");
}

class QuantisedInverseDistanceCodec final : public DistanceCodec {
  // Scratch reused across calls; the mutex makes concurrent calls on one codec safe.
  mutable std::mutex mutex_;
  mutable std::vector<std::uint16_t> levels_;  // the decoder's
  mutable std::array<BandScratch, kBands> bands_;

 public:
  std::string name() const override { return std::string(kQinv16Zstd); }

  Bytes encode(FloatView distance, const DistanceParams& params) const override {
    params.check();
    if (distance.empty()) throw CodecError(error_prefix(kQinv16Zstd) + "expects a non-empty map");
    const int ds = int(params.downsample);
    const int w = (distance.width() + ds - 1) / ds, h = (distance.height() + ds - 1) / ds;
    const std::lock_guard lock(mutex_);
    const std::vector<Band> bands = bands_of(h);
    for_each_band(int(bands.size()), [&](int i) {
      BandScratch& scratch = bands_[i];
      residual_streams(distance, params, w, bands[i], scratch);
      if (!scratch.cctx) {
        scratch.cctx.reset(ZSTD_createCCtx());
        if (!scratch.cctx) throw CodecError(error_prefix(kQinv16Zstd) + "out of memory");
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
        throw CodecError(error_prefix(kQinv16Zstd) + "zstd failed: " + ZSTD_getErrorName(size));
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
      for (std::size_t k = 0; k < kContexts; ++k) put_u32(entry + 4 + 4 * k, band.lengths[k]);
      std::memcpy(out.data() + at, band.frame.data(), band.frame.size());
      at += band.frame.size();
    }
    return out;
  }

  FloatImage decode(std::span<const std::uint8_t> payload, int width, int height,
                    const DistanceParams& params) const override {
    params.check();
    const std::vector<float> metres = level_metres(params);
    FloatImage out;
    const int ds = int(params.downsample);
    const int w = (width + ds - 1) / ds;
    const std::lock_guard lock(mutex_);
    const auto allocate = [&] { out = FloatImage(width, height); };
    decode_bands(payload, width, height, params, allocate, [&](const Band& band) {
      // Level -> metres by lookup, for the output rows this band covers.
      for (int y = band.y0 * ds; y < std::min(band.y1 * ds, height); ++y) {
        const std::uint16_t* row = levels_.data() + std::size_t(y / ds) * w;
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

  Image<std::uint16_t> decode_levels(std::span<const std::uint8_t> payload, int width, int height,
                                     const DistanceParams& params) const override {
    const int ds = int(params.downsample);
    const int w = (width + ds - 1) / ds;
    const std::lock_guard lock(mutex_);
    decode_bands(
        payload, width, height, params, [] {}, [](const Band&) {});
    Image<std::uint16_t> out(w, int(levels_.size() / std::size_t(w)));
    std::copy(levels_.begin(), levels_.end(), out.data());
    return out;
  }

 private:
  // Checks `payload` and reconstructs its levels into levels_ (stored resolution), band by band
  // on the band threads: `on_checked()` runs once the header is checked (the sizes are sane),
  // `on_band(band)` on a band's thread once its rows are in levels_. The caller holds mutex_.
  template <typename OnChecked, typename OnBand>
  void decode_bands(std::span<const std::uint8_t> payload, int width, int height,
                    const DistanceParams& params, const OnChecked& on_checked,
                    const OnBand& on_band) const {
    params.check();
    if (payload.size() >= 4 && (std::memcmp(payload.data(), "OSQ2", 4) == 0 ||
                                std::memcmp(payload.data(), "OSQ3", 4) == 0)) {
      throw CodecError(error_prefix(kQinv16Zstd) + "an " +
                       std::string(payload.begin(), payload.begin() + 4) +
                       " payload from a pre-release omnisweep; this version reads OSQ4");
    }
    if (payload.size() < kFixedHeader || std::memcmp(payload.data(), kMagic, 4) != 0) {
      throw CodecError(error_prefix(kQinv16Zstd) + "not a " + std::string(kQinv16Zstd) +
                       " payload (" + std::to_string(payload.size()) + " bytes)");
    }
    if (width <= 0 || height <= 0 || std::uint64_t(width) * height > kMaxPixels) {
      throw CodecError(error_prefix(kQinv16Zstd) + "frame size " + std::to_string(width) + "x" +
                       std::to_string(height) + " is out of range");
    }
    const int ds = int(params.downsample);
    const int w = (width + ds - 1) / ds, h = (height + ds - 1) / ds;
    if (get_u32(payload.data() + 4) != std::uint32_t(w) ||
        get_u32(payload.data() + 8) != std::uint32_t(h)) {
      throw CodecError(error_prefix(kQinv16Zstd) + "payload holds " +
                       std::to_string(get_u32(payload.data() + 4)) + "x" +
                       std::to_string(get_u32(payload.data() + 8)) +
                       " samples, the frame expects " + std::to_string(w) + "x" +
                       std::to_string(h));
    }
    const std::vector<Band> bands = bands_of(h);
    if (get_u32(payload.data() + 12) != bands.size() ||
        payload.size() < kFixedHeader + kBandEntry * bands.size()) {
      throw CodecError(error_prefix(kQinv16Zstd) + "corrupt payload: band table does not match " +
                       std::to_string(bands.size()) + " bands");
    }
    std::vector<std::span<const std::uint8_t>> frames;
    std::vector<std::array<std::uint32_t, kContexts>> lengths(bands.size());
    std::size_t at = kFixedHeader + kBandEntry * bands.size();
    for (std::size_t i = 0; i < bands.size(); ++i) {
      const std::uint8_t* entry = payload.data() + kFixedHeader + kBandEntry * i;
      const std::size_t size = get_u32(entry);
      if (size > payload.size() - at)
        throw CodecError(error_prefix(kQinv16Zstd) + "payload is truncated (band " +
                         std::to_string(i) + ")");
      frames.push_back(payload.subspan(at, size));
      at += size;
      for (std::size_t k = 0; k < kContexts; ++k) lengths[i][k] = get_u32(entry + 4 + 4 * k);
    }
    if (at != payload.size())
      throw CodecError(error_prefix(kQinv16Zstd) + "corrupt payload: " +
                       std::to_string(payload.size() - at) + " bytes after the last band");
    std::vector<std::uint16_t>& q = levels_;
    q.resize(std::size_t(w) * h);
    on_checked();
    for_each_band(int(bands.size()), [&](int i) {
      const std::size_t n = std::size_t(bands[i].y1 - bands[i].y0) * w;
      // The context streams (at most 2 bytes per sample: 3 per pair, 1 per lone sample), then
      // the escape stream, 2 bytes per escaped sample.
      std::uint64_t streams_length = 0;
      for (const std::uint32_t length : lengths[i]) streams_length += length;
      const unsigned long long content =
          ZSTD_getFrameContentSize(frames[i].data(), frames[i].size());
      if (content == ZSTD_CONTENTSIZE_UNKNOWN || content == ZSTD_CONTENTSIZE_ERROR ||
          content > 4 * std::uint64_t(n) || streams_length > content ||
          (content - streams_length) % 2 != 0) {
        throw CodecError(error_prefix(kQinv16Zstd) + "band " + std::to_string(i) +
                         " is truncated or its streams do not add up");
      }
      BandScratch& scratch = bands_[i];
      std::vector<std::uint8_t>& streams = scratch.streams;
      streams.resize(content);
      if (!scratch.dctx) {
        scratch.dctx.reset(ZSTD_createDCtx());
        if (!scratch.dctx) throw CodecError(error_prefix(kQinv16Zstd) + "out of memory");
      }
      const std::size_t got = ZSTD_decompressDCtx(
          scratch.dctx.get(), streams.data(), streams.size(), frames[i].data(), frames[i].size());
      if (ZSTD_isError(got) || got != streams.size()) {
        throw CodecError(error_prefix(kQinv16Zstd) + "corrupt payload: " +
                         (ZSTD_isError(got) ? ZSTD_getErrorName(got) : "short"));
      }
      reconstruct(streams, lengths[i], w, bands[i], params.levels, scratch, q.data());
      on_band(bands[i]);
    });
  }
};

}  // namespace

std::unique_ptr<DistanceCodec> make_qinv16_zstd_codec() {
  return std::make_unique<QuantisedInverseDistanceCodec>();
}

std::vector<float> level_metres(const DistanceParams& params) {
  const double lo = 1.0 / params.max_distance, hi = 1.0 / params.min_distance;
  const double step = (hi - lo) / double(params.levels - 1);
  std::vector<float> metres(params.levels + 1, 0.0f);
  for (std::uint32_t level = 1; level <= params.levels; ++level)
    metres[level] = float(1.0 / (lo + (level - 1) * step));
  return metres;
}

FloatImage distance_from_levels(ImageView<const std::uint16_t> levels, int width, int height,
                                const DistanceParams& params) {
  params.check();
  const int ds = int(params.downsample);
  if (width <= 0 || height <= 0 || levels.width() != (width + ds - 1) / ds ||
      levels.height() != (height + ds - 1) / ds) {
    throw CodecError("distance_from_levels: levels of " + std::to_string(levels.width()) + "x" +
                     std::to_string(levels.height()) + " do not store a " + std::to_string(width) +
                     "x" + std::to_string(height) + " map at 1/" + std::to_string(ds));
  }
  const std::vector<float> metres = level_metres(params);
  FloatImage out(width, height);
  for (int y = 0; y < height; ++y) {
    const std::uint16_t* row = levels.data() + std::size_t(y / ds) * std::size_t(levels.width());
    float* dst = out.data() + std::size_t(y) * std::size_t(width);
    for (int x = 0; x < width; ++x) {
      const std::uint16_t level = row[x / ds];
      if (level > params.levels)
        throw CodecError("distance_from_levels: level " + std::to_string(level) + " over " +
                         std::to_string(params.levels));
      dst[x] = metres[level];
    }
  }
  return out;
}

}  // namespace omnisweep::codec
