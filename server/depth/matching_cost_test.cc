// The robust matching costs (DepthOptions::cost): their features and sweep equal the CPU's, and
// they do what they are for: a camera's gain and colour cast leave them nearly unchanged.
#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>

#include "server/depth/depth_estimator.h"
#include "server/depth/depth_fixtures.h"
#include "server/depth/depth_reference.h"
#include "server/depth/photometric_model.h"
#include "tests/support/gpu_test_support.h"
#include "tests/support/test_support.h"

namespace omnisweep::depth {
namespace {

using MatchingCostTest = omnisweep::testing::ValidatedGpuTest;
constexpr int kSize = 128;

DepthOptions options_for(MatchingCost cost) {
  DepthOptions options;
  options.matching_width = options.matching_height = kSize;
  options.cost = cost;
  options.half_costs = false;  // compare 32-bit costs
  return options;
}

// How the colour bytes of two packed feature images differ: by more than `tolerance`, and at
// all; and how many census bytes differ.
struct FeatureDifferences {
  long color_above = 0, color_any = 0, census = 0;
};
FeatureDifferences feature_differences(const std::vector<std::uint32_t>& a,
                                       const std::vector<std::uint32_t>& b, int tolerance) {
  FeatureDifferences d;
  for (std::size_t p = 0; p < std::min(a.size(), b.size()); ++p) {
    for (int k = 0; k < 3; ++k) {
      const int delta = std::abs(int((a[p] >> (8 * k)) & 255) - int((b[p] >> (8 * k)) & 255));
      d.color_above += delta > tolerance;
      d.color_any += delta != 0;
    }
    d.census += (a[p] >> 24) != (b[p] >> 24);
  }
  return d;
}

TEST_F(MatchingCostTest, FeaturesEqualCpu) {
  const auto scene = fixtures::render_depth_case(kSize);
  DepthOptions options = options_for(MatchingCost::kNormalisedCensus);
  options.feature_radius = 16;  // 2 pixels at 128 px
  options.census_radius = 16;   // 2 pixels
  DepthEstimator estimator(context(), scene.rig.rig(), scene.usable, options);
  estimator.cost_volume(scene.image_views(), 0, false);
  for (int c = 0; c < 4; ++c) {
    const auto gpu = estimator.matching_features(c);
    const auto cpu = matching_features_cpu(scene.images[c], 2, 2, options.feature_epsilon);
    ASSERT_EQ(gpu.size(), cpu.size());
    const FeatureDifferences d = feature_differences(gpu, cpu, 1);
    std::cout << "camera " << c << ": " << d.color_any << " colour bytes 1 apart, " << d.census
              << " census bytes differ, of " << cpu.size() << " pixels\n";
    EXPECT_EQ(d.color_above, 0) << "camera " << c;  // float vs double: at most 1 apart
    EXPECT_LT(d.color_any, long(cpu.size()) / 100);
    EXPECT_LT(d.census, long(cpu.size()) / 200);  // a neighbour within rounding of c + 1
  }
}

TEST_F(MatchingCostTest, RatioFeaturesEqualCpuAndSkipUnusablePixels) {
  const auto scene = fixtures::render_depth_case(kSize);
  DepthOptions options = options_for(MatchingCost::kRatio);
  options.ratio_radius = 64;   // 8 pixels at 128 px: taps 2 apart
  options.census_radius = 16;  // 2 pixels
  DepthEstimator estimator(context(), scene.rig.rig(), scene.usable, options);
  estimator.cost_volume(scene.image_views(), 0, false);
  for (int c = 0; c < 4; ++c) {
    ASSERT_TRUE(scene.usable[c].has_value()) << "the fixture's cameras have masks";
    const auto gpu = estimator.matching_features(c);
    const auto cpu =
        ratio_features_cpu(scene.images[c], &*scene.usable[c], 8, 2, options.ratio_epsilon);
    // Without the mask, the mean near the image circle is darker: the features differ there.
    const auto unmasked = ratio_features_cpu(scene.images[c], nullptr, 8, 2, options.ratio_epsilon);
    ASSERT_EQ(gpu.size(), cpu.size());
    const FeatureDifferences d = feature_differences(gpu, cpu, 1);
    const long unmasked_off = feature_differences(gpu, unmasked, 1).color_above;
    std::cout << "camera " << c << ": " << d.color_any << " colour bytes 1 apart; " << unmasked_off
              << " more than 1 apart from the mean of every pixel, of " << cpu.size()
              << " pixels\n";
    EXPECT_EQ(d.color_above, 0) << "camera " << c;
    EXPECT_LT(d.color_any, long(cpu.size()) / 100);
    EXPECT_EQ(d.census, 0) << "camera " << c;
    EXPECT_GT(unmasked_off, long(cpu.size()) / 100);
  }
}

TEST_F(MatchingCostTest, RobustSweepCostsEqualCpu) {
  const auto scene = fixtures::render_depth_case(kSize);
  for (const MatchingCost cost : {MatchingCost::kNormalised, MatchingCost::kCensus,
                                  MatchingCost::kNormalisedCensus, MatchingCost::kRatio}) {
    const DepthOptions options = options_for(cost);
    DepthEstimator estimator(context(), scene.rig.rig(), scene.usable, options);
    const auto images = scene.image_views();
    for (int slot = 0; slot < 2; ++slot) {
      const std::vector<float> gpu = estimator.cost_volume(images, slot, false);
      std::vector<std::vector<std::uint32_t>> features;
      for (int c = 0; c < 4; ++c) features.push_back(estimator.matching_features(c));
      const Image<std::int32_t> selected = estimator.selection(slot);
      std::vector<float> differences;
      for (int y = 0; y < kSize; y += 3) {
        for (int x = 0; x < kSize; x += 3) {
          const auto cpu = feature_cost_cpu(scene.rig.rig(), options.references[slot],
                                            selected(x, y), features, options, x, y);
          for (int i = 0; i < options.num_candidates; ++i) {
            differences.push_back(
                std::abs(cpu[i] - gpu[(std::size_t(y) * kSize + x) * options.num_candidates + i]));
          }
        }
      }
      std::sort(differences.begin(), differences.end());
      const float p99 = differences[differences.size() * 99 / 100], worst = differences.back();
      std::cout << name_of(cost) << " sweep cost vs CPU: 99th percentile difference " << p99
                << ", largest " << worst << "\n";
      EXPECT_LT(p99, 0.05f);   // float vs double projection moves a tap by ~1e-4 px
      EXPECT_LT(worst, 0.5f);  // measured 0.003-0.006
    }
  }
}

// Mean absolute change of the raw costs of matched pixels when every camera but the references
// gets a gain and a colour cast, relative to their mean.
double relative_change_under_gain(gpu::Context& context, MatchingCost cost) {
  const auto scene = fixtures::render_depth_case(kSize);
  const DepthOptions options = options_for(cost);
  DepthEstimator estimator(context, scene.rig.rig(), scene.usable, options);
  std::vector<Rgb8Image> changed;
  const double gain[3] = {1.25 * 1.05, 1.25, 1.25 * 0.95};
  for (int c = 0; c < 4; ++c) {
    changed.push_back(scene.images[c].clone());
    if (c == 2 || c == 3) continue;
    Rgb8Image& im = changed.back();
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x)
        for (int k = 0; k < 3; ++k)
          im(x, y, k) = std::uint8_t(std::min(255.0, std::round(im(x, y, k) * gain[k])));
  }
  double change = 0, total = 0;
  for (int slot = 0; slot < 2; ++slot) {
    const auto before = estimator.cost_volume(scene.image_views(), slot, false);
    const auto after = estimator.cost_volume(views(changed), slot, false);
    for (std::size_t i = 0; i < before.size(); ++i) {
      change += std::abs(after[i] - before[i]);
      total += before[i];
    }
  }
  return change / total;
}

TEST_F(MatchingCostTest, NormalisedCostsIgnoreAGainAndAColorCast) {
  // Measured at 128 px with the other two cameras 25 % brighter and cast by +-5 %: the paper's
  // cost moves by 1.85 times its mean, nad by 0.038, census by 0.14.
  const double ad = relative_change_under_gain(context(), MatchingCost::kAbsoluteDifference);
  const double nad = relative_change_under_gain(context(), MatchingCost::kNormalised);
  const double census = relative_change_under_gain(context(), MatchingCost::kCensus);
  const double ratio = relative_change_under_gain(context(), MatchingCost::kRatio);
  std::cout << "relative change of the raw costs under a gain: ad " << ad << ", nad " << nad
            << ", census " << census << ", ratio " << ratio << "\n";
  EXPECT_GT(ad, 0.2);
  EXPECT_LT(nad, ad / 4);
  EXPECT_LT(census, ad / 4);
  EXPECT_LT(ratio, ad / 4);
}

// End to end on a frame through lenses with realistic gains, casts and vignetting, at 256 px:
// the paper's cost loses much of its accuracy; nad, ratio, or the paper's cost on images whose
// responses photometric_model.h estimated and undid, keep most of it. (Since the synthetic
// sensor rounds once, after its response, each camera's 8-bit steps on smooth shading lie at its
// own brightness, so the lenses cost every variant some accuracy on plain surfaces.)
TEST_F(MatchingCostTest, PhotometricConditionsAreSurvivedByNadRatioAndTheCorrection) {
  const int size = 256;
  const auto clean = fixtures::render_depth_case(size);
  const auto changed =
      fixtures::render_depth_case(size, 0, 1, synthetic::PhotometricOptions::realistic());
  auto mae = [&](const fixtures::SyntheticDepthCase& scene, MatchingCost cost,
                 std::span<const Rgb8View> images) {
    DepthOptions options;
    options.matching_width = options.matching_height = size;
    options.cost = cost;
    DepthEstimator estimator(context(), scene.rig.rig(), scene.usable, options);
    const DepthResult result = estimator.estimate(images);
    double sum = 0;
    for (int slot = 0; slot < 2; ++slot) {
      const int ref = options.references[slot];
      sum += fixtures::inverse_distance_accuracy(result.distance[slot], scene.inverse_gt[ref],
                                                 *scene.usable[ref])
                 .mae /
             2;
    }
    return sum;
  };
  std::vector<Rgb8Image> corrected;
  for (const auto& im : changed.images) corrected.push_back(im.clone());
  const PhotometryFit fit =
      estimate_photometry(changed.rig.rig(), changed.image_views(), changed.usable);
  PhotometricCorrection(changed.rig.rig()).apply(fit, corrected);

  const double ad_clean = mae(clean, MatchingCost::kAbsoluteDifference, clean.image_views());
  const double ad = mae(changed, MatchingCost::kAbsoluteDifference, changed.image_views());
  const double nad = mae(changed, MatchingCost::kNormalised, changed.image_views());
  const double ratio_clean = mae(clean, MatchingCost::kRatio, clean.image_views());
  const double ratio = mae(changed, MatchingCost::kRatio, changed.image_views());
  const double ad_corrected = mae(changed, MatchingCost::kAbsoluteDifference, views(corrected));
  std::cout << "fisheye MAE at 256 px: ad " << ad_clean << " clean, " << ad
            << " through the lenses; nad " << nad << "; ratio " << ratio_clean << " clean, "
            << ratio << "; ad on corrected images " << ad_corrected << "\n";
  // Measured: ad 0.046 clean, 0.271 through the lenses; nad 0.092; ratio 0.056 clean, 0.089
  // (at 256 px its mean reaches 5 pixels only; at 1024 px it does better, docs/accuracy.md); ad
  // on the corrected images 0.059.
  EXPECT_GT(ad, 4 * ad_clean);
  EXPECT_LT(nad, ad / 2);
  EXPECT_LT(ratio, 2 * ratio_clean);
  EXPECT_LT(ratio, ad / 2);
  EXPECT_LT(ad_corrected, 1.5 * ad_clean);
}

TEST(MatchingCostOptions, NamesRoundTripAndBadValuesAreNamed) {
  for (const auto& entry : kMatchingCostNames)
    EXPECT_EQ(matching_cost_named(name_of(entry.cost)), entry.cost);
  EXPECT_FALSE(matching_cost_named("sad").has_value());
  DepthOptions options;
  options.feature_radius = 0;
  try {
    options.check(4);
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("feature-radius"), std::string::npos) << e.what();
  }
  options = {};
  options.feature_epsilon = 0;
  EXPECT_THROW(options.check(4), std::invalid_argument);
  options = {};
  options.match_cameras = 3;
  EXPECT_NE(omnisweep::testing::error_message<std::invalid_argument>([&] {
              options.check(4);
            }).find("match-cameras: 3"),
            std::string::npos);
  options = {};
  options.second_camera_power = 0;
  EXPECT_THROW(options.check(4), std::invalid_argument);
  options = {};
  options.ratio_radius = 3;
  EXPECT_NE(omnisweep::testing::error_message<std::invalid_argument>([&] {
              options.check(4);
            }).find("ratio-radius: 3"),
            std::string::npos);
  options = {};
  options.ratio_epsilon = -1;
  EXPECT_THROW(options.check(4), std::invalid_argument);
  options = {};
  options.confident_sigma_s = -3;
  EXPECT_NE(omnisweep::testing::error_message<std::invalid_argument>([&] {
              options.check(4);
            }).find("confident-sigma-s: -3"),
            std::string::npos);
}

}  // namespace
}  // namespace omnisweep::depth
