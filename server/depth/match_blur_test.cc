// The matching images' blur (match_blur.comp) against its CPU check, and in the estimator: a
// blurred estimate is the plain estimate of the images match_blur_cpu blurred.
#include "server/depth/match_blur.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <random>

#include "server/depth/depth_estimator.h"
#include "server/depth/depth_fixtures.h"
#include "tests/support/gpu_test_support.h"

namespace omnisweep::depth {
namespace {

using MatchBlurTest = omnisweep::testing::ValidatedGpuTest;

// `images` blurred on the GPU.
std::vector<Rgb8Image> blurred_on_gpu(gpu::Context& context, const std::vector<Rgb8Image>& images,
                                      double sigma) {
  const int width = images[0].width(), height = images[0].height();
  const std::vector<Rgb8View> views(images.begin(), images.end());
  const std::vector<std::uint32_t> packed = fixtures::packed_images(views);
  gpu::Buffer source(context, packed.size() * 4), out(context, packed.size() * 4);
  source.upload(std::span<const std::uint32_t>(packed));
  const MatchBlur blur(context, width, height, int(images.size()), sigma);
  gpu::Sequence seq(context);
  seq.begin();
  blur.record(seq, source, out);
  seq.submit_and_wait();
  const std::vector<std::uint32_t> words = out.download<std::uint32_t>();
  for (const std::uint32_t word : words) EXPECT_EQ(word >> 24, 0xffu);  // alpha kept
  return fixtures::unpacked_images(words, width, height);
}

TEST(MatchBlurWeightsTest, NormalisedAndBounded) {
  for (const double sigma : {0.3, 0.7, 1.0, 2.0, 8.0 / 3.0}) {
    const MatchBlurWeights w = match_blur_weights(sigma);
    EXPECT_EQ(w.radius, int(std::ceil(3 * sigma)));
    double sum = w.w[0];
    for (int i = 1; i <= w.radius; ++i) {
      sum += 2 * w.w[std::size_t(i)];
      EXPECT_LT(w.w[std::size_t(i)], w.w[std::size_t(i - 1)]);
    }
    EXPECT_NEAR(sum, 1.0, 1e-6);
  }
  EXPECT_THROW(match_blur_weights(0.0), std::invalid_argument);
  EXPECT_THROW(match_blur_weights(-1.0), std::invalid_argument);
  EXPECT_THROW(match_blur_weights(3.0), std::invalid_argument);  // taps 9 pixels away
}

TEST(MatchBlurOptionsTest, CheckNamesTheOption) {
  DepthOptions options;
  options.match_blur = -1;
  try {
    options.check(4);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("match-blur"), std::string::npos) << e.what();
  }
  options.match_blur = 2.5;
  EXPECT_NO_THROW(options.check(4));
  options.matching_width = options.matching_height = 2048;  // 5 pixels there: taps 15 away
  EXPECT_THROW(options.check(4), std::invalid_argument);
}

TEST(MatchBlurCpuTest, KeepsPlainImagesAndAveragesNoise) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 4.0);
  Rgb8Image plain(40, 30), noisy(40, 30);
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40; ++x)
      for (int c = 0; c < 3; ++c) {
        plain(x, y, c) = std::uint8_t(60 + 40 * c);
        noisy(x, y, c) = std::uint8_t(std::lround(std::clamp(128 + noise(rng), 0.0, 255.0)));
      }
  const Rgb8Image same = match_blur_cpu(plain, 1.0);
  for (std::size_t i = 0; i < plain.size(); ++i) ASSERT_EQ(same.data()[i], plain.data()[i]);
  // A Gaussian of sigma 1 leaves 1 / (2 sqrt(pi)) of white noise's deviation: ~1.1 of 4 levels.
  const Rgb8Image smooth = match_blur_cpu(noisy, 1.0);
  double before = 0, after = 0;
  for (std::size_t i = 0; i < noisy.size(); ++i) {
    before += std::pow(noisy.data()[i] - 128.0, 2);
    after += std::pow(smooth.data()[i] - 128.0, 2);
  }
  EXPECT_LT(std::sqrt(after / double(noisy.size())),
            0.4 * std::sqrt(before / double(noisy.size())));
}

TEST_F(MatchBlurTest, EqualsCpu) {
  // 100 pixels: the 16 x 16 tiles do not divide it.
  const fixtures::SyntheticDepthCase f = fixtures::render_depth_case(100);
  for (const double sigma : {0.7, 8.0 / 3.0}) {
    const std::vector<Rgb8Image> gpu = blurred_on_gpu(context(), f.images, sigma);
    std::size_t differ = 0, changed = 0;
    int worst = 0;
    for (std::size_t k = 0; k < f.images.size(); ++k) {
      const Rgb8Image cpu = match_blur_cpu(f.images[k], sigma);
      for (std::size_t i = 0; i < cpu.size(); ++i) {
        differ += cpu.data()[i] != gpu[k].data()[i];
        worst = std::max(worst, std::abs(int(cpu.data()[i]) - int(gpu[k].data()[i])));
        changed += cpu.data()[i] != f.images[k].data()[i];
      }
    }
    // The same float sums in the same order: equal here (x86-64, lavapipe). A compiler that fuses
    // the CPU's multiply-adds (aarch64's default) may round a sum at .5 the other way.
    EXPECT_LE(worst, 1) << "sigma " << sigma;
    EXPECT_LE(differ, f.images[0].size() * f.images.size() / 1000) << "sigma " << sigma;
    EXPECT_GT(changed, f.images[0].size());  // it blurred
  }
}

TEST_F(MatchBlurTest, EstimatorMatchesTheBlurredImages) {
  const fixtures::SyntheticDepthCase f = fixtures::render_depth_case(96);
  DepthOptions options;
  options.matching_width = options.matching_height = 96;
  options.match_blur = 1.0 * 1024 / 96;  // 1 pixel at 96
  options.check(4);
  DepthEstimator blurring(context(), f.rig.rig(), f.usable, options);
  const DepthResult with = blurring.estimate(f.image_views());
  std::vector<Rgb8Image> blurred;
  for (const Rgb8Image& im : f.images) blurred.push_back(match_blur_cpu(im, 1.0));
  std::vector<Rgb8View> views(blurred.begin(), blurred.end());
  options.match_blur = 0;
  DepthEstimator plain(context(), f.rig.rig(), f.usable, options);
  const DepthResult without = plain.estimate(views);
  const DepthResult unblurred = plain.estimate(f.image_views());
  std::size_t moved = 0;
  for (std::size_t slot = 0; slot < with.distance.size(); ++slot) {
    for (std::size_t p = 0; p < with.distance[slot].size(); ++p) {
      ASSERT_EQ(with.distance[slot].data()[p], without.distance[slot].data()[p]) << p;
      ASSERT_EQ(with.confidence[slot].data()[p], without.confidence[slot].data()[p]) << p;
      moved += with.distance[slot].data()[p] != unblurred.distance[slot].data()[p];
    }
  }
  EXPECT_GT(moved, with.distance[0].size() / 10);  // the blur changed the distances
}

}  // namespace
}  // namespace omnisweep::depth
