// The temporal filter: the GPU kernels against the plain C++ version frame by frame, and what it
// promises: less flicker on a static noisy panorama, a restart where colour or distance moves
// (where the confidence is low, once the next frame confirms the jump), everywhere when the whole
// view moves, and nothing at all with one frame.
#include "server/stitch/temporal_filter.h"

#include <gtest/gtest.h>

#include <random>

#include "omnisweep/reproject/gpu_camera.h"
#include "tests/support/gpu_test_support.h"
#include "tests/support/test_support.h"

namespace omnisweep::stitch {
namespace {

using TemporalFilterTest = omnisweep::testing::ValidatedGpuTest;

constexpr int kW = 64, kH = 32;
constexpr int kUnconfident = 8;  // columns below this have confidence 0.01, the rest 0.8

FloatImage confidence_map() {
  FloatImage confidence(kW, kH);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) confidence.data()[y * kW + x] = x < kUnconfident ? 0.01f : 0.8f;
  return confidence;
}

// A static scene (inverse distance 0.2-1.2 over x) seen with noise `sigma` (1/m) in the
// distance and +-2 levels in the colour, frame `f`; a hole (no value) at one pixel.
std::pair<FloatImage, Rgb8Image> noisy_frame(int f, double sigma) {
  std::mt19937 rng(1000 + f);
  std::normal_distribution<float> noise(0.0f, float(sigma));
  std::uniform_int_distribution<int> jitter(-2, 2);
  FloatImage distance(kW, kH);
  Rgb8Image color(kW, kH);
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) {
      const int i = y * kW + x;
      distance.data()[i] = 1.0f / (0.2f + float(x) / kW + noise(rng));
      for (int c = 0; c < 3; ++c)
        color.data()[3 * i + c] =
            std::uint8_t(std::clamp(60 + 2 * x + 30 * c + jitter(rng), 0, 255));
    }
  }
  distance.data()[5] = 0.0f;
  return {std::move(distance), std::move(color)};
}

std::vector<std::uint32_t> packed(const Rgb8Image& rgb) {
  std::vector<std::uint32_t> out(rgb.size() / 3);
  reproject::pack_rgba8(rgb, out);
  return out;
}

double flicker(const std::vector<FloatImage>& frames) {
  double sum = 0;
  long n = 0;
  for (std::size_t f = 1; f < frames.size(); ++f) {
    for (std::size_t i = 0; i < frames[f].size(); ++i) {
      const float a = frames[f].data()[i], b = frames[f - 1].data()[i];
      if (a > 0 && b > 0) sum += std::abs(1.0 / a - 1.0 / b), ++n;
    }
  }
  return sum / double(n);
}

TEST_F(TemporalFilterTest, EqualsCpuAndStopsFlicker) {
  const TemporalOptions options;
  TemporalFilter filter(context(), kW, kH, options);
  TemporalState state;
  const vk::DeviceSize bytes = vk::DeviceSize(kW) * kH * 4;
  gpu::Buffer distance(context(), bytes), color(context(), bytes), confidence(context(), bytes);
  const FloatImage confidence_cpu = confidence_map();
  confidence.upload(confidence_cpu.data(), bytes);
  gpu::Sequence seq(context());
  std::vector<FloatImage> raw, filtered;
  double worst = 0;
  for (int f = 0; f < 10; ++f) {
    auto [d, c] = noisy_frame(f, 0.02);
    if (f == 6) {  // something moves in depth in one column and in colour in another
      for (int y = 0; y < kH; ++y) d.data()[y * kW + 40] = 1.0f / 3.0f;
      for (int y = 0; y < kH; ++y) c.data()[std::ptrdiff_t(3) * (y * kW + 50)] = 255;
    }
    // Unconfident columns: one jumps in depth for frame 6 alone (noise in a guess), the other
    // from frame 6 on (the next frame confirms it).
    if (f == 6)
      for (int y = 0; y < kH; ++y) d.data()[y * kW + 3] = 1.0f / 3.0f;
    if (f >= 6)
      for (int y = 0; y < kH; ++y) d.data()[y * kW + 4] = 1.0f / 3.0f;
    raw.push_back(d.clone());
    distance.upload(d.data(), d.size() * 4);
    color.upload(std::span<const std::uint32_t>(packed(c)));
    seq.begin();
    filter.record(seq, distance, color, confidence);
    seq.submit_and_wait();
    FloatImage gpu(kW, kH);
    distance.download(gpu.data(), gpu.size() * 4);
    temporal_filter_cpu(state, d, c, confidence_cpu, options);
    for (std::size_t i = 0; i < d.size(); ++i) {
      ASSERT_EQ(gpu.data()[i] > 0, d.data()[i] > 0) << "frame " << f << " pixel " << i;
      if (d.data()[i] > 0)
        worst = std::max(worst, double(std::abs(1.0f / gpu.data()[i] - 1.0f / d.data()[i])));
    }
    if (f == 6) {
      for (int y = 0; y < kH; ++y) {  // the moved pixels start again: their new values, unmixed
        EXPECT_FLOAT_EQ(gpu.data()[y * kW + 40], 1.0f / 3.0f);
        EXPECT_FLOAT_EQ(gpu.data()[y * kW + 50], raw.back().data()[y * kW + 50]);
        // An unconfident jump joins the mean: between the mean before and the jumped value.
        for (const int x : {3, 4}) {
          const float inverse = 1.0f / gpu.data()[y * kW + x];
          EXPECT_GT(inverse, 1.0f / filtered.back().data()[y * kW + x] + 0.1f);
          EXPECT_LT(inverse, 2.0f);
        }
      }
    }
    if (f == 7) {
      for (int y = 0; y < kH; ++y) {
        EXPECT_FLOAT_EQ(gpu.data()[y * kW + 4], 1.0f / 3.0f);  // confirmed: starts again
        EXPECT_LT(1.0f / gpu.data()[y * kW + 3], 1.0f);        // not confirmed: still mixed
      }
    }
    filtered.push_back(std::move(gpu));
  }
  std::cout << "temporal filter GPU vs CPU: largest inverse-distance difference " << worst
            << "; flicker " << flicker(raw) << " -> " << flicker(filtered) << " m^-1\n";
  EXPECT_LT(worst, 1e-5);
  EXPECT_LT(flicker(filtered), 0.5 * flicker(raw));
  EXPECT_EQ(filtered[0].data()[5], 0.0f);  // no value stays no value
}

TEST_F(TemporalFilterTest, AViewThatMovesStartsAgainEverywhere) {
  TemporalOptions options;
  TemporalState state;
  auto [d0, c0] = noisy_frame(0, 0.0);
  const FloatImage confidence = confidence_map();
  temporal_filter_cpu(state, d0, c0, confidence, options);
  auto [d1, c1] = noisy_frame(1, 0.0);
  for (std::size_t i = 0; i < c1.size(); ++i) c1.data()[i] = std::uint8_t(255 - c1.data()[i]);
  for (std::size_t i = 0; i < d1.size(); ++i)
    if (d1.data()[i] > 0) d1.data()[i] *= 1.2f;  // within the jump for most pixels
  const FloatImage expected = d1.clone();
  temporal_filter_cpu(state, d1, c1, confidence, options);
  for (std::size_t i = 0; i < d1.size(); ++i)
    ASSERT_FLOAT_EQ(d1.data()[i], expected.data()[i]) << i;
  for (const float n : state.count) ASSERT_EQ(n, 1.0f);
}

TEST_F(TemporalFilterTest, OneFrameInTheMeanChangesNothing) {
  TemporalOptions options;
  options.max_frames = 1;
  TemporalState state;
  const FloatImage confidence = confidence_map();
  for (int f = 0; f < 3; ++f) {
    auto [d, c] = noisy_frame(f, 0.02);
    const FloatImage before = d.clone();
    temporal_filter_cpu(state, d, c, confidence, options);
    for (std::size_t i = 0; i < d.size(); ++i) {
      if (before.data()[i] > 0) {
        ASSERT_NEAR(1.0 / d.data()[i], 1.0 / before.data()[i], 1e-6) << i;
      }
    }
  }
}

TEST(TemporalOptions, BadOptionsAreNamed) {
  TemporalOptions options;
  options.max_frames = 0;
  EXPECT_NE(testing::error_message<std::invalid_argument>([&] {
              options.check();
            }).find("TemporalOptions.max_frames"),
            std::string::npos);
  options = {};
  options.jump = -1;
  EXPECT_THROW(options.check(), std::invalid_argument);
  options = {};
  options.reset_share = 2;
  EXPECT_THROW(options.check(), std::invalid_argument);
  options = {};
  options.confident = -0.5;
  EXPECT_NE(testing::error_message<std::invalid_argument>([&] {
              options.check();
            }).find("TemporalOptions.confident"),
            std::string::npos);
  TemporalState state;
  auto [d, c] = noisy_frame(0, 0.0);
  EXPECT_THROW(temporal_filter_cpu(state, d, c, FloatImage(kW, kH - 1), {}), std::invalid_argument);
}

}  // namespace
}  // namespace omnisweep::stitch
