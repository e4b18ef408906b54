// The stream codecs: round trips, the quantisation bound, sizes, and bad payloads (truncated,
// bit-flipped, mismatched) that must give CodecError, never a crash or an out-of-bounds read.
#include "omnisweep/codec/codec.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <utility>
#include <vector>

namespace omnisweep::codec {
namespace {

Rgb8Image test_image(int w, int h) {
  Rgb8Image im(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c)
        im(x, y, c) = std::uint8_t(128 + 100 * std::sin(0.05 * x * (c + 1) + 0.07 * y));
  return im;
}

// A distance map with smooth surfaces, an edge and holes (like an estimated map).
FloatImage test_distance(int w, int h) {
  FloatImage d(w, h);
  std::mt19937 rng(4);
  std::normal_distribution<float> noise(0.0f, 0.01f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float v = 0.55f + 20.0f * float(y) / float(h);
      if (x > w / 3 && x < w / 2) v = 1.5f;  // a near object
      d(x, y) = std::max(0.55f, v * (1.0f + noise(rng)));
    }
  d(3, 3) = 0.0f;  // no value
  d(4, 3) = NAN;
  return d;
}

TEST(Codec, RegistryByName) {
  EXPECT_EQ(make_color_codec("jpeg")->name(), "jpeg");
  EXPECT_EQ(make_distance_codec("qinv16-zstd")->name(), "qinv16-zstd");
  EXPECT_THROW(make_color_codec("png"), CodecError);
  EXPECT_THROW(make_distance_codec("raw"), CodecError);
  EXPECT_THROW(make_color_codec("jpeg", {.quality = 0}), CodecError);
}

TEST(JpegCodec, RoundTripAndMismatches) {
  const auto jpeg = make_color_codec("jpeg");
  const Rgb8Image im = test_image(160, 96);
  const Bytes bytes = jpeg->encode(im);
  const Rgb8Image back = jpeg->decode(bytes, 160, 96);
  double mse = 0;
  for (std::size_t i = 0; i < im.size(); ++i)
    mse += std::pow(double(im.data()[i]) - back.data()[i], 2);
  const double psnr = 10 * std::log10(255.0 * 255.0 / (mse / double(im.size())));
  std::cout << "jpeg q90: " << bytes.size() << " bytes, PSNR " << psnr << " dB\n";
  EXPECT_GT(psnr, 35.0);
  EXPECT_THROW(jpeg->decode(bytes, 161, 96), CodecError);
  EXPECT_THROW(jpeg->decode({}, 160, 96), CodecError);
}

TEST(DistanceCodec, QuantisationBoundAtDefaults) {
  const DistanceParams params;
  // Half a level of the default 10000 levels over [1/100, 1/0.55] m^-1: 9.04e-5.
  EXPECT_LT(params.max_quantisation_error(), 1e-4);
  EXPECT_NEAR(params.max_quantisation_error(), 0.5 * (1 / 0.55 - 1 / 100.0) / 9999,
              1e-10);  // float params
  // Measured over every distance in [0.55, 100] m on a fine grid.
  const int n = 200000;
  FloatImage d(n, 1);
  for (int i = 0; i < n; ++i)
    d(i, 0) = float(1.0 / (1.0 / 100 + (1 / 0.55 - 1 / 100.0) * i / (n - 1)));
  const auto codec = make_distance_codec("qinv16-zstd");
  const FloatImage back = codec->decode(codec->encode(d, params), n, 1, params);
  double worst = 0;
  for (int i = 0; i < n; ++i) worst = std::max(worst, std::abs(1.0 / back(i, 0) - 1.0 / d(i, 0)));
  std::cout << "largest inverse-distance error at defaults: " << worst << " m^-1 (bound "
            << params.max_quantisation_error() << ")\n";
  EXPECT_LE(worst, params.max_quantisation_error() * 1.01 + 1e-7);  // float storage of the input
}

TEST(DistanceCodec, RoundTripKeepsHolesAndTheLightSetting) {
  const auto codec = make_distance_codec("qinv16-zstd");
  const FloatImage d = test_distance(200, 120);
  const DistanceParams full;
  const FloatImage back = codec->decode(codec->encode(d, full), 200, 120, full);
  EXPECT_EQ(back(3, 3), 0.0f);
  EXPECT_EQ(back(4, 3), 0.0f);
  // Every sample, across bands, contexts and escapes (the holes and the object's edges are
  // residuals beyond one byte).
  for (int y = 0; y < 120; ++y)
    for (int x = 0; x < 200; ++x) {
      if ((x == 3 || x == 4) && y == 3) continue;
      ASSERT_NEAR(1.0 / back(x, y), 1.0 / d(x, y), full.max_quantisation_error() * 1.01)
          << "at " << x << "," << y;
    }
  const DistanceParams light{.levels = 4096, .downsample = 2};
  const Bytes small = codec->encode(d, light);
  const FloatImage coarse = codec->decode(small, 200, 120, light);
  EXPECT_EQ(coarse.width(), 200);
  EXPECT_GT(coarse(10, 60), 0.0f);
  EXPECT_LT(small.size(), codec->encode(d, full).size());
}

// Odd and tiny shapes (a lone last sample per row, rows of one pair, bands of one row) and
// noise from none to wild, so pair codes, escaped pairs, unpaired contexts and 16-bit escapes
// all occur: every sample comes back within the bound, holes stay holes.
TEST(DistanceCodec, RoundTripsAnyShape) {
  const auto codec = make_distance_codec("qinv16-zstd");
  const DistanceParams params;
  std::mt19937 rng(11);
  for (const auto& [w, h] : std::vector<std::pair<int, int>>{
           {1, 1}, {2, 1}, {1, 3}, {3, 5}, {7, 2}, {5, 9}, {33, 4}, {201, 9}, {64, 64}}) {
    FloatImage d(w, h);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const float amplitude = std::pow(10.0f, -4.0f + 4.0f * float(x) / float(w));  // 1e-4..1
        const float inverse =
            0.5f + 0.3f * std::sin(0.1f * float(x + y)) + amplitude * (unit(rng) - 0.5f);
        d(x, y) = unit(rng) < 0.02f ? 0.0f : 1.0f / std::clamp(inverse, 0.01f, 1.8f);
      }
    const FloatImage back = codec->decode(codec->encode(d, params), w, h, params);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        if (d(x, y) == 0.0f) {
          ASSERT_EQ(back(x, y), 0.0f) << w << "x" << h << " at " << x << "," << y;
          continue;
        }
        ASSERT_NEAR(1.0 / back(x, y), 1.0 / d(x, y), params.max_quantisation_error() * 1.01)
            << w << "x" << h << " at " << x << "," << y;
      }
  }
}

// The stored levels are what decode() turns into metres: level l is inverse distance
// 1/d_max + (l - 1) step, 0 is no value, at the stored (downsampled) size.
TEST(DistanceCodec, LevelsAreWhatDecodeExpands) {
  const auto codec = make_distance_codec("qinv16-zstd");
  const FloatImage d = test_distance(101, 37);
  for (const DistanceParams params :
       {DistanceParams{}, DistanceParams{.levels = 2048, .downsample = 4}}) {
    const Bytes bytes = codec->encode(d, params);
    const Image<std::uint16_t> levels = codec->decode_levels(bytes, 101, 37, params);
    const FloatImage metres = codec->decode(bytes, 101, 37, params);
    const int ds = int(params.downsample);
    ASSERT_EQ(levels.width(), (101 + ds - 1) / ds);
    ASSERT_EQ(levels.height(), (37 + ds - 1) / ds);
    const double lo = 1.0 / params.max_distance, hi = 1.0 / params.min_distance;
    const double step = (hi - lo) / (params.levels - 1);
    for (int y = 0; y < 37; ++y)
      for (int x = 0; x < 101; ++x) {
        const std::uint16_t l = levels(x / ds, y / ds);
        ASSERT_LE(l, params.levels);
        if (l == 0) {
          ASSERT_EQ(metres(x, y), 0.0f);
        } else {
          ASSERT_EQ(metres(x, y), float(1.0 / (lo + (l - 1) * step))) << x << "," << y;
        }
      }
    EXPECT_EQ(levels(3, 3) * (ds == 1), 0);  // the hole, where it is not averaged away
    EXPECT_THROW(codec->decode_levels(bytes, 100, 37, params), CodecError);
    // Levels to metres without a second decode: bit-identical to decode().
    const FloatImage from_levels = distance_from_levels(levels, 101, 37, params);
    ASSERT_EQ(from_levels.size(), metres.size());
    EXPECT_EQ(std::memcmp(from_levels.data(), metres.data(), metres.size() * sizeof(float)), 0);
    EXPECT_THROW(distance_from_levels(levels, 100 + 4 * ds, 37, params), CodecError);
  }
}

TEST(DistanceCodec, PreReleasePayloadsAreNamed) {
  const auto codec = make_distance_codec("qinv16-zstd");
  Bytes old = codec->encode(test_distance(64, 48), DistanceParams{});
  std::copy_n("OSQ3", 4, old.begin());
  try {
    codec->decode(old, 64, 48, DistanceParams{});
    FAIL() << "an OSQ3 payload was accepted";
  } catch (const CodecError& e) {
    EXPECT_NE(std::string(e.what()).find("an OSQ3 payload from a pre-release omnisweep"),
              std::string::npos)
        << e.what();
  }
}

TEST(DistanceCodec, BadPayloadsAreErrors) {
  const auto codec = make_distance_codec("qinv16-zstd");
  const DistanceParams params;
  const Bytes good = codec->encode(test_distance(64, 48), params);
  EXPECT_THROW(codec->decode(good, 65, 48, params), CodecError);  // mismatched size
  EXPECT_THROW(codec->decode(good, 64, 48, DistanceParams{.downsample = 2}), CodecError);
  EXPECT_THROW(codec->decode(good, 0, 48, params), CodecError);
  EXPECT_THROW(codec->decode(good, 1 << 20, 1 << 20, params), CodecError);
  for (std::size_t cut :
       {std::size_t(0), std::size_t(5), std::size_t(12), good.size() / 2, good.size() - 1}) {
    EXPECT_THROW(codec->decode(std::span(good).first(cut), 64, 48, params), CodecError)
        << "cut at " << cut;
  }
  // A flipped bit is an error (zstd's content checksum, the header checks), or lands where it
  // changes nothing (e.g. a zstd window-size field) and decodes to the very same map; it
  // never yields a different map. The CRC that travels with payloads catches all of them.
  const FloatImage original = codec->decode(good, 64, 48, params);
  const std::uint32_t crc = checksum(good);
  std::mt19937 rng(9);
  int caught = 0;
  for (int trial = 0; trial < 300; ++trial) {
    Bytes bad = good;
    bad[rng() % bad.size()] ^= std::uint8_t(1u << (rng() % 8));
    EXPECT_THROW(verify_checksum(bad, crc), CodecError);
    try {
      const FloatImage decoded = codec->decode(bad, 64, 48, params);
      ASSERT_TRUE(
          std::equal(decoded.pixels().begin(), decoded.pixels().end(), original.pixels().begin()))
          << "a flipped bit changed the map without an error";
    } catch (const CodecError&) {
      ++caught;
    }
  }
  std::cout << caught << " of 300 single-bit flips rejected by the decoder itself\n";
  EXPECT_GT(caught, 290);
}

TEST(JpegCodec, TruncatedAndFlippedPayloadsNeverCrash) {
  const auto jpeg = make_color_codec("jpeg");
  const Bytes good = jpeg->encode(test_image(96, 64));
  for (std::size_t cut :
       {std::size_t(0), std::size_t(3), std::size_t(100), good.size() / 2, good.size() - 2}) {
    EXPECT_THROW(jpeg->decode(std::span(good).first(cut), 96, 64), CodecError) << "cut at " << cut;
  }
  std::mt19937 rng(10);
  const std::uint32_t crc = checksum(good);
  for (int trial = 0; trial < 300; ++trial) {
    Bytes bad = good;
    bad[rng() % bad.size()] ^= std::uint8_t(1u << (rng() % 8));
    // The checksum that travels with every payload catches every flip...
    EXPECT_THROW(verify_checksum(bad, crc), CodecError);
    // ...and decoding a flipped JPEG anyway either fails cleanly or yields an image of the size.
    try {
      EXPECT_EQ(jpeg->decode(bad, 96, 64).width(), 96);
    } catch (const CodecError&) {
    }
  }
  EXPECT_NO_THROW(verify_checksum(good, crc));
}

// Confidence: levels survive exactly, any shape; values map to round(255 c), clamped.
TEST(ConfidenceCodec, RoundTripAndLevels) {
  const auto codec = make_confidence_codec("conf8-zstd");
  EXPECT_EQ(codec->name(), "conf8-zstd");
  EXPECT_THROW(make_confidence_codec("png"), CodecError);
  std::mt19937 rng(7);
  for (const auto& [w, h] : {std::pair{1, 1}, {3, 5}, {64, 32}, {257, 19}}) {
    FloatImage confidence(w, h);
    for (float& c : confidence.pixels())
      c = std::uniform_real_distribution<float>(-0.2f, 1.2f)(rng);
    confidence.data()[0] = std::nanf("");
    const Gray8Image levels = confidence_levels(confidence);
    for (std::size_t i = 0; i < levels.size(); ++i) {
      const float c = confidence.data()[i];
      const int expected = std::isnan(c) ? 0 : int(std::lround(std::clamp(c, 0.0f, 1.0f) * 255));
      ASSERT_EQ(levels.data()[i], expected) << i;
    }
    const Gray8Image back = codec->decode(codec->encode(levels, 1), w, h);
    EXPECT_TRUE(std::equal(back.pixels().begin(), back.pixels().end(), levels.pixels().begin()));
    // Downsampled: a constant map comes back exactly, at any size.
    Gray8Image constant = Gray8Image::filled(w, h, 77);
    for (const int downsample : {2, 4}) {
      const Gray8Image c = codec->decode(codec->encode(constant, downsample), w, h);
      EXPECT_TRUE(std::all_of(c.pixels().begin(), c.pixels().end(), [](auto v) { return v == 77; }))
          << w << "x" << h << " / " << downsample;
    }
    EXPECT_FLOAT_EQ(confidence_values(back).data()[back.size() - 1],
                    levels.data()[back.size() - 1] / 255.0f);
  }
}

// The default stores half the resolution: a smooth map comes back within a level or two,
// a quarter of the samples stored.
TEST(ConfidenceCodec, HalfResolutionKeepsSmoothMaps) {
  const auto codec = make_confidence_codec("conf8-zstd");
  Gray8Image ramp(128, 64);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 128; ++x) ramp.data()[y * 128 + x] = std::uint8_t(x + 2 * y);
  const Bytes half = codec->encode(ramp);
  const Gray8Image back = codec->decode(half, 128, 64);
  int worst = 0;
  for (int y = 1; y < 63; ++y)  // the outermost samples are extrapolated flat
    for (int x = 1; x < 127; ++x)
      worst = std::max(worst, std::abs(int(back.data()[y * 128 + x]) - ramp.data()[y * 128 + x]));
  EXPECT_LE(worst, 2);
  EXPECT_LT(half.size(), codec->encode(ramp, 1).size());
  EXPECT_THROW(codec->encode(ramp, 3), CodecError);
}

TEST(ConfidenceCodec, BadPayloadsAreErrors) {
  const auto codec = make_confidence_codec("conf8-zstd");
  Gray8Image levels(40, 20);
  for (std::size_t i = 0; i < levels.size(); ++i) levels.data()[i] = std::uint8_t(i * 7);
  const Bytes good = codec->encode(levels);
  EXPECT_THROW(codec->decode(good, 20, 40), CodecError);  // other size
  EXPECT_THROW(codec->decode(std::span(good).first(8), 40, 20), CodecError);
  for (std::size_t cut = 16; cut < good.size(); cut += 3)
    EXPECT_THROW(codec->decode(std::span(good).first(cut), 40, 20), CodecError) << cut;
  Bytes flipped = good;
  flipped.back() ^= 0x40;  // the content checksum catches it
  EXPECT_THROW(codec->decode(flipped, 40, 20), CodecError);
  Bytes huge = good;
  huge[4] = huge[5] = huge[6] = huge[7] = 0xff;
  EXPECT_THROW(codec->decode(huge, 40, 20), CodecError);
  Bytes odd_factor = good;
  odd_factor[12] = 3;
  EXPECT_THROW(codec->decode(odd_factor, 40, 20), CodecError);
  EXPECT_THROW(codec->encode(Gray8Image()), CodecError);
}

}  // namespace
}  // namespace omnisweep::codec
