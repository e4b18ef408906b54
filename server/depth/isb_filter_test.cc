// The ISB filter on the GPU against the plain C++ version of ALGORITHM.md §4, and its two
// defining properties: constants pass unchanged, sharp guide edges stop it.
#include "server/depth/isb_filter.h"

#include <gtest/gtest.h>

#include <random>

#include "server/depth/depth_fixtures.h"
#include "server/depth/depth_reference.h"
#include "tests/support/gpu_test_support.h"

namespace omnisweep::depth {
namespace {

using fixtures::isb_filter_gpu;
using omnisweep::testing::ValidatedGpuTest;

std::uint32_t pack(int a, int b, int c) {
  return std::uint32_t(a) | (std::uint32_t(b) << 8) | (std::uint32_t(c) << 16);
}

std::vector<std::uint32_t> random_guide(int pixels, std::mt19937& rng) {
  std::uniform_int_distribution<int> byte(0, 255);
  std::vector<std::uint32_t> guide(pixels);
  for (auto& g : guide) g = pack(byte(rng), byte(rng), byte(rng));
  return guide;
}

using IsbFilterTest = ValidatedGpuTest;

TEST(IsbParams, CheckNamesTheFieldAndItsValue) {
  EXPECT_NO_THROW(IsbParams{}.check());
  try {
    IsbParams{.sigma_i = 10, .sigma_s = -2}.check();
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("IsbParams.sigma_s = -2"), std::string::npos) << e.what();
  }
  EXPECT_THROW((IsbParams{.sigma_i = std::nan(""), .sigma_s = 25}.check()), std::invalid_argument);
}

TEST(IsbLevels, FollowAlgorithmMd) {
  EXPECT_EQ(isb_levels(1024, 1024), 9);  // 1024 ... 4
  EXPECT_EQ(isb_levels(37, 23), 3);
  EXPECT_EQ(isb_levels(4, 4), 1);
}

TEST_F(IsbFilterTest, ConstantInputIsUnchanged) {
  std::mt19937 rng(3);
  const int w = 67, h = 45, channels = 5;
  const std::vector<float> values(std::size_t(w) * h * channels, 3.75f);
  const auto out = isb_filter_gpu(context(), random_guide(w * h, rng), values, w, h, channels,
                                  {10.0, 25.0 * w / 1024});
  for (float v : out) ASSERT_NEAR(v, 3.75f, 3.75f * 1e-5f);
}

TEST_F(IsbFilterTest, DoesNotLeakAcrossASharpGuideEdge) {
  // Left half dark, right half bright guide (Y 16 vs 235); the values step from 0 to 100 at the
  // same edge. A plain smoothing filter would mix them; the ISB filter must not.
  const int w = 128, h = 64;
  std::vector<std::uint32_t> guide(std::size_t(w) * h);
  std::vector<float> values(std::size_t(w) * h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      guide[y * w + x] = x < w / 2 ? pack(16, 128, 128) : pack(235, 128, 128);
      values[y * w + x] = x < w / 2 ? 0.0f : 100.0f;
    }
  }
  const auto out = isb_filter_gpu(context(), guide, values, w, h, 1, {10.0, 25.0});
  float worst_adjacent = 0, worst_far = 0;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const float leak = x < w / 2 ? out[y * w + x] : 100.0f - out[y * w + x];
      const int from_edge = x < w / 2 ? w / 2 - 1 - x : x - w / 2;
      if (from_edge == 0) worst_adjacent = std::max(worst_adjacent, leak);
      if (from_edge >= 4) worst_far = std::max(worst_far, leak);
    }
  }
  std::cout << "leak across the edge: " << worst_adjacent << " % next to it, " << worst_far
            << " % from 4 pixels on\n";
  EXPECT_LT(worst_adjacent, 5.0f);
  EXPECT_LT(worst_far, 2.0f);
}

struct Comparison {
  double worst = 0;       // largest relative difference
  double within_1e3 = 0;  // share of values within 1e-3 relative
};

Comparison compare(const std::vector<float>& gpu, const std::vector<float>& cpu) {
  Comparison c;
  long close = 0;
  for (std::size_t i = 0; i < cpu.size(); ++i) {
    const double rel = std::abs(double(gpu[i]) - cpu[i]) / std::max(1.0, std::abs(double(cpu[i])));
    c.worst = std::max(c.worst, rel);
    close += rel <= 1e-3;
  }
  c.within_1e3 = double(close) / double(cpu.size());
  return c;
}

struct Case {
  int w, h, channels;
};
constexpr Case kOddSizes[] = {{37, 23, 3}, {101, 77, 32}, {63, 129, 5}, {9, 9, 1}};

std::vector<float> random_values(const Case& c, std::mt19937& rng) {
  std::uniform_real_distribution<float> cost(0.0f, 500.0f);
  std::vector<float> values(std::size_t(c.w) * c.h * c.channels);
  for (auto& v : values) v = cost(rng);
  return values;
}

// Filters random values guided by random guides on the GPU and in plain C++ for every odd size.
// With sigma_confident > 0 the guides' fourth byte holds random confidences as well.
template <typename Check>
void compare_on_odd_sizes(gpu::Context& context, unsigned seed, double sigma_i, Check&& check,
                          double sigma_confident = 0) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<std::uint32_t> byte(0, 255);
  for (const Case& c : kOddSizes) {
    auto guide = random_guide(c.w * c.h, rng);
    if (sigma_confident > 0)
      for (auto& g : guide) g |= byte(rng) << 24;
    const auto values = random_values(c, rng);
    const double scale = c.w / 1024.0 * 8;
    const IsbParams params{sigma_i, 25.0 * scale, sigma_confident * scale};
    check(c, compare(isb_filter_gpu(context, guide, values, c.w, c.h, c.channels, params),
                     isb_filter_cpu(guide, values, c.w, c.h, c.channels, params.sigma_i,
                                    params.sigma_s, params.sigma_s_confident)));
  }
}

TEST_F(IsbFilterTest, EqualsThePlainImplementationWhereTheGuideCannotMatter) {
  // With a huge sigma_I every range weight is 1.01 whatever the guides, so levels, spatial
  // weights and the up/down blending alone decide: GPU and C++ must agree everywhere.
  compare_on_odd_sizes(context(), 7, 1e6, [](const Case& c, const Comparison& d) {
    std::cout << c.w << "x" << c.h << "x" << c.channels
              << " (flat range weights): largest relative difference " << d.worst << "\n";
    EXPECT_LT(d.worst, 1e-3);
  });
}

TEST_F(IsbFilterTest, EqualsThePlainImplementationOnRandomGuides) {
  // Guides are rounded to 8 bits at every level (ALGORITHM.md §4). Where a weighted mean falls
  // within float noise of a half level, GPU and C++ may round it differently; a one-level guide
  // difference changes the weights near it, so a few small clusters differ by up to about 1 %.
  // Everywhere else they agree within 1e-3.
  compare_on_odd_sizes(context(), 11, 10.0, [](const Case& c, const Comparison& d) {
    std::cout << c.w << "x" << c.h << "x" << c.channels << ": " << 100 * d.within_1e3
              << " % of values within 1e-3 relative, largest difference " << d.worst << "\n";
    EXPECT_GE(d.within_1e3, 0.999);
    EXPECT_LT(d.worst, 0.02);
  });
}

// The confident sigma (isb_weights.glsl): each pixel's spatial sigma from its guide's fourth
// byte, which the down pass averages and the up pass keeps. As above, on random confidences,
// which round to 8 bits at every level like the guide: a few more values near a flipped
// rounding differ by up to a few per cent.
TEST_F(IsbFilterTest, EqualsThePlainImplementationWithAConfidentSigma) {
  compare_on_odd_sizes(
      context(), 13, 10.0,
      [](const Case& c, const Comparison& d) {
        std::cout << c.w << "x" << c.h << "x" << c.channels
                  << " (confident sigma): " << 100 * d.within_1e3
                  << " % of values within 1e-3 relative, largest difference " << d.worst << "\n";
        EXPECT_GE(d.within_1e3, 0.999);
        EXPECT_LT(d.worst, 0.05);
      },
      12.0);
  // The confidences matter: the same values filtered as if they were all 0 differ.
  std::mt19937 rng(5);
  const Case c = kOddSizes[1];
  auto guide = random_guide(c.w * c.h, rng);
  for (auto& g : guide) g |= 255u << 24;
  const auto values = random_values(c, rng);
  const double scale = c.w / 1024.0 * 8;
  const auto confident =
      isb_filter_cpu(guide, values, c.w, c.h, c.channels, 10.0, 25.0 * scale, 12.0 * scale);
  const auto paper = isb_filter_cpu(guide, values, c.w, c.h, c.channels, 10.0, 25.0 * scale);
  EXPECT_LT(compare(confident, paper).within_1e3, 0.5);
}

TEST_F(IsbFilterTest, AConfidentSigmaNeedsAFilterMadeForIt) {
  const int w = 16, h = 16;
  const VolumeLayout layout = plan_volume(context(), w, h, 1);
  CostVolume volume(context(), w, h, layout);
  gpu::Buffer guide(context(), std::size_t(w) * h * 4);
  IsbFilter paper(context(), w, h, layout), confident(context(), w, h, layout, true);
  gpu::Sequence seq(context());
  seq.begin();
  EXPECT_THROW(paper.record(seq, guide, volume, {10.0, 25.0, 12.0}), std::invalid_argument);
  EXPECT_THROW(confident.record(seq, guide, volume, {10.0, 25.0}), std::invalid_argument);
}

}  // namespace
}  // namespace omnisweep::depth
