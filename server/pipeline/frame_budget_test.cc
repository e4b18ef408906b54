// FrameBudget: frames kept under the byte budget by the colour quality alone, the quality
// raised again when there is room, the floor respected and reported.
#include "server/pipeline/frame_budget.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace omnisweep::pipeline {
namespace {

// Texture with detail at every scale, so JPEG's size follows its quality.
Rgb8Image textured(int w, int h) {
  Rgb8Image im(w, h);
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> noise(-20, 20);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c)
        im(x, y, c) = std::uint8_t(std::clamp(
            128 + int(80 * std::sin(0.03 * x * (c + 1)) * std::cos(0.05 * y)) + noise(rng), 0,
            255));
  return im;
}

std::size_t jpeg_size(const Rgb8Image& im, int quality) {
  return codec::make_color_codec(codec::kJpeg, {.quality = quality})->encode(im).size();
}

TEST(FrameBudget, LowersTheColorQualityUntilTheFrameFits) {
  const Rgb8Image im = textured(512, 256);
  const std::size_t at90 = jpeg_size(im, 90), at70 = jpeg_size(im, 70), at50 = jpeg_size(im, 50);
  ASSERT_GT(at90, at70);
  ASSERT_GT(at70, at50);
  // q90 .. q75 do not fit beside this distance payload, q70 does; without it, q90 fits with
  // room to spare (so each step up is tried).
  const std::size_t distance = at90 - at70 + at90 / 5;
  FrameBudget budget(90, distance + at70);
  const FrameBudget::Color first = budget.encode(im, distance);
  EXPECT_EQ(first.quality, 70);
  EXPECT_FALSE(first.over_budget);
  EXPECT_LE(distance + first.bytes.size(), budget.max_bytes());
  // The next frame starts where this one ended.
  EXPECT_EQ(budget.encode(im, distance).quality, 70);

  // A smaller distance payload leaves room: one step up per frame, back to 90.
  int frames = 0;
  while (budget.quality() < 90 && frames < 10) {
    const FrameBudget::Color c = budget.encode(im, 0);
    EXPECT_LE(c.bytes.size(), budget.max_bytes());
    ++frames;
  }
  EXPECT_EQ(budget.quality(), 90);
  EXPECT_EQ(frames, 4);  // 75, 80, 85, 90
}

TEST(FrameBudget, TheFloorIsKeptAndAnOverrunReported) {
  const Rgb8Image im = textured(512, 256);
  FrameBudget budget(90, jpeg_size(im, 50) / 2);
  const FrameBudget::Color c = budget.encode(im, 0);
  EXPECT_EQ(c.quality, FrameBudget::kFloorQuality);
  EXPECT_TRUE(c.over_budget);
  EXPECT_FALSE(c.bytes.empty());  // sent anyway: the budget does not drop frames
}

TEST(FrameBudget, NoBudgetMeansTheConfiguredQuality) {
  const Rgb8Image im = textured(256, 128);
  FrameBudget budget(90, 0);
  const FrameBudget::Color c = budget.encode(im, 1u << 30);
  EXPECT_EQ(c.quality, 90);
  EXPECT_FALSE(c.over_budget);
  EXPECT_EQ(c.bytes.size(), jpeg_size(im, 90));
  EXPECT_THROW(FrameBudget(0, 1000), std::invalid_argument);
  EXPECT_THROW(FrameBudget(101, 1000), std::invalid_argument);
}

}  // namespace
}  // namespace omnisweep::pipeline
