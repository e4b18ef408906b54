// Distance estimation end to end on synthetic frames with exact ground truth.
#include "server/depth/depth_estimator.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>

#include "server/depth/depth_fixtures.h"
#include "server/depth/depth_reference.h"
#include "tests/support/gpu_test_support.h"

namespace omnisweep::depth {
namespace {

using omnisweep::testing::ValidatedGpuTest;
using DepthEstimatorTest = ValidatedGpuTest;

// Largest minus smallest value in the 5x5 window around (x, y), over the three channels;
// -1 when the window leaves the lens (the black outside it is no texture).
int local_contrast(const Rgb8Image& im, const Gray8Image& usable, int x, int y) {
  int worst = 0;
  for (int k = 0; k < 3; ++k) {
    int lo = 255, hi = 0;
    for (int dy = -2; dy <= 2; ++dy)
      for (int dx = -2; dx <= 2; ++dx) {
        if (!usable.contains(x + dx, y + dy) || !usable(x + dx, y + dy)) return -1;
        const int v = im(x + dx, y + dy, k);
        lo = std::min(lo, v);
        hi = std::max(hi, v);
      }
    worst = std::max(worst, hi - lo);
  }
  return worst;
}

// Whether the surface seen at reference pixel (x, y) is visible in camera `other`: its own
// ground truth sees the same distance there (else the point is occluded and no cost can match).
bool visible_in_selected(const fixtures::SyntheticDepthCase& scene, int ref, int other, int x,
                         int y) {
  const Rig& rig = scene.rig.rig();
  Eigen::Vector3d ray;
  if (!rig.cameras[ref].model.unproject(Eigen::Vector2d(x, y), &ray)) return false;
  const Eigen::Vector3d p = rig.cam_from_cam(other, ref) * (ray / scene.inverse_gt[ref](x, y));
  Eigen::Vector2d uv;
  if (!rig.cameras[other].model.project(p, &uv)) return false;
  const int u = int(std::lround(uv.x())), v = int(std::lround(uv.y()));
  if (!scene.inverse_gt[other].contains(u, v)) return false;
  return std::abs(scene.inverse_gt[other](u, v) * p.norm() - 1.0) < 0.02;
}

TEST_F(DepthEstimatorTest, RawCostIsMinimalAtTheTrueCandidateOnTexturedPixels) {
  // Measured (synthetic hall, 32 candidates): at 384, 512 and 1024 px one of the two candidates
  // around the true distance has the lowest cost, within 2 levels, for 68-73 % of textured,
  // visible, depth-smooth pixels; the first argmin alone falls there for 42-50 %. The rest are
  // single-pixel ambiguities the filter is there to resolve: repeated tiles and paint-plain
  // stretches of the epipolar curve, where a far-off candidate also costs 0-2.
  const int size = 512;
  const auto scene = fixtures::render_depth_case(size);
  DepthOptions options;
  options.matching_width = options.matching_height = size;
  DepthEstimator estimator(context(), scene.rig.rig(), scene.usable, options);
  const int n = options.num_candidates;
  for (std::size_t slot = 0; slot < 2; ++slot) {
    const int ref = options.references[slot];
    const std::vector<float> cost = estimator.cost_volume(scene.image_views(), int(slot), false);
    const Image<std::int32_t> selected = estimator.selection(int(slot));
    const FloatImage& gt = scene.inverse_gt[ref];
    long counted = 0, correct = 0, strict = 0;
    for (int y = 2; y < size - 2; ++y) {
      for (int x = 2; x < size - 2; ++x) {
        if (selected(x, y) < 0 || gt(x, y) <= 0 ||
            local_contrast(scene.images[ref], *scene.usable[ref], x, y) < 24)
          continue;
        // Skip depth edges: the 3x3 ground truth must be smooth.
        float lo = gt(x, y), hi = gt(x, y);
        for (int d = -1; d <= 1; ++d) {
          lo = std::min({lo, gt(x + d, y), gt(x, y + d)});
          hi = std::max({hi, gt(x + d, y), gt(x, y + d)});
        }
        if (hi - lo > 0.02f) continue;
        if (!visible_in_selected(scene, ref, selected(x, y), x, y)) continue;
        const double k = (gt(x, y) - 1.0 / options.min_distance) /
                         (1.0 / options.max_distance - 1.0 / options.min_distance) * (n - 1);
        const float* c = &cost[(std::size_t(y) * size + x) * n];
        const int best = int(std::min_element(c, c + n) - c);
        // The true distance lies between candidates floor(k) and ceil(k): one of them should
        // have the lowest cost, ties (plain paint, repeated tiles) included.
        const int below = std::clamp(int(std::floor(k)), 0, n - 1),
                  above = std::clamp(int(std::ceil(k)), 0, n - 1);
        ++counted;
        correct += std::min(c[below], c[above]) <= c[best] + 2.0f;
        strict += std::abs(best - k) < 1.0;
      }
    }
    const double rate = double(correct) / double(counted);

    std::cout << "reference " << ref << ": raw cost minimal (within 2) at the true candidates for "
              << 100 * rate << " % of " << counted
              << " textured pixels; the first minimum alone lies there for "
              << 100.0 * strict / counted << " %\n";
    EXPECT_GT(counted, 20000);
    EXPECT_GT(rate, 0.62);
  }
}

// Options for checks against the CPU of the winner in the ISB filter's last pass: n x n
// matching, no post-filter, 32-bit costs, the curve's own confidence (no coarse or raw agreement).
DepthOptions unfiltered_cpu_check_options(int n) {
  DepthOptions options;
  options.matching_width = options.matching_height = n;
  options.post_filter = false;
  options.half_costs = false;
  options.coarse_agreement = 0;
  options.raw_agreement = 0;
  return options;
}

// estimate() takes the winner inside the filter's last pass (isb_upsample.comp with
// kWinnerTakesAll); the CPU takes it from the volume the unfused filter leaves. 32-bit costs: the
// unfused filter's 16-bit store of its last pass (which the fused winner never sees) would flip
// near-ties (what 16-bit costs do to accuracy: HalfCostsKeepTheAccuracy).
TEST_F(DepthEstimatorTest, WinnerTakesAllEqualsCpu) {
  const auto scene = fixtures::render_depth_case(96);
  DepthOptions options = unfiltered_cpu_check_options(96);
  DepthEstimator estimator(context(), scene.rig.rig(), scene.usable, options);
  const auto filtered = estimator.cost_volume(scene.image_views(), 0, true);
  const DepthResult result = estimator.estimate(scene.image_views());
  double worst = 0;
  for (int p = 0; p < 96 * 96; ++p) {
    const float cpu =
        winner_take_all_cpu(&filtered[std::size_t(p) * options.num_candidates], options);
    worst = std::max(worst, std::abs(1.0 / result.distance[0].data()[p] - 1.0 / cpu));
  }
  std::cout << "winner takes all vs CPU: largest inverse-distance difference " << worst
            << " m^-1\n";
  EXPECT_LT(worst, 1e-4);

  // The confidence taken in the same pass (wta.glsl) against the CPU's, on the same curves.
  double worst_confidence = 0, mean_confidence = 0;
  for (int p = 0; p < 96 * 96; ++p) {
    const float cpu = cost_confidence_cpu(&filtered[std::size_t(p) * options.num_candidates],
                                          options.num_candidates);
    const float gpu = result.confidence[0].data()[p];
    ASSERT_TRUE(gpu >= 0 && gpu <= 1) << "pixel " << p << ": " << gpu;
    worst_confidence = std::max(worst_confidence, double(std::abs(gpu - cpu)));
    mean_confidence += gpu / (96.0 * 96.0);
  }
  std::cout << "confidence vs CPU: largest difference " << worst_confidence << ", mean "
            << mean_confidence << "\n";
  EXPECT_LT(worst_confidence, 1e-4);
  EXPECT_GT(mean_confidence, 0.05);  // not all flat
}

// The confident sigma (DepthOptions::confident_sigma_s): the sweep writes each pixel's raw curve
// confidence into its guide's fourth byte, and the filter lowers its spatial sigma there. The
// CPU does the same from the GPU's raw volume (cost_confidence_cpu, isb_filter_cpu,
// winner_take_all_cpu) and must find the same distances, which differ from the paper's.
TEST_F(DepthEstimatorTest, ConfidentSigmaEqualsCpu) {
  const int n = 96;
  const auto scene = fixtures::render_depth_case(n);
  DepthOptions options = unfiltered_cpu_check_options(n);
  options.confident_sigma_s = 12;
  DepthEstimator estimator(context(), scene.rig.rig(), scene.usable, options);
  const auto raw = estimator.cost_volume(scene.image_views(), 0, false);
  const DepthResult result = estimator.estimate(scene.image_views());
  auto guide = ycbcr_guide_cpu(scene.images[std::size_t(options.references[0])]);
  const int candidates = options.num_candidates;
  double mean_confidence = 0;
  for (std::size_t p = 0; p < guide.size(); ++p) {
    const float c = cost_confidence_cpu(&raw[p * candidates], candidates);
    guide[p] |= std::uint32_t(std::clamp(std::floor(c * 255.0f + 0.5f), 0.0f, 255.0f)) << 24;
    mean_confidence += c / double(guide.size());
  }
  const auto filtered =
      isb_filter_cpu(guide, raw, n, n, candidates, options.sigma_i, options.scaled_sigma_s(),
                     options.scaled_confident_sigma_s());
  const auto paper =
      isb_filter_cpu(guide, raw, n, n, candidates, options.sigma_i, options.scaled_sigma_s());
  int close = 0, differ_from_paper = 0;
  for (int p = 0; p < n * n; ++p) {
    const double cpu = 1.0 / winner_take_all_cpu(&filtered[std::size_t(p) * candidates], options);
    const double gpu = 1.0 / result.distance[0].data()[p];
    close += std::abs(gpu - cpu) < 1e-3;
    differ_from_paper +=
        std::abs(cpu - 1.0 / winner_take_all_cpu(&paper[std::size_t(p) * candidates], options)) >
        1e-3;
  }
  std::cout << "confident sigma vs CPU: " << 100.0 * close / (n * n)
            << " % of pixels within 1e-3 m^-1; " << 100.0 * differ_from_paper / (n * n)
            << " % differ from the paper's filter; mean raw confidence " << mean_confidence << "\n";
  EXPECT_GE(close, n * n * 99 / 100);
  EXPECT_GT(differ_from_paper, n * n / 20);
}

// The coarse agreement (coarse_agreement.comp): the confidence with it is the confidence without
// it times coarse_agreement_cpu's factor, computed from the filter's level 1 as the GPU left it
// and the final (post-filtered) distances; the distances stay the same.
TEST_F(DepthEstimatorTest, CoarseAgreementEqualsCpu) {
  const auto scene = fixtures::render_depth_case(96);
  DepthOptions options;
  options.matching_width = options.matching_height = 96;
  options.coarse_agreement = 0;
  DepthEstimator plain(context(), scene.rig.rig(), scene.usable, options);
  const DepthResult without = plain.estimate(scene.image_views());
  options.coarse_agreement = 0.05;
  DepthEstimator estimator(context(), scene.rig.rig(), scene.usable, options);
  ASSERT_EQ(estimator.group_size(), int(options.references.size()));
  const DepthResult with = estimator.estimate(scene.image_views());
  for (int slot = 0; slot < int(options.references.size()); ++slot) {
    int level_width = 0, level_height = 0;
    const std::vector<float> level =
        estimator.filter_level_costs(slot, &level_width, &level_height);
    EXPECT_EQ(level_width, 48);
    const std::vector<float> factor =
        coarse_agreement_cpu(level, level_width, level_height, with.distance[slot], options);
    double worst = 0, mean_factor = 0;
    int lowered = 0;
    for (std::size_t p = 0; p < factor.size(); ++p) {
      ASSERT_EQ(with.distance[slot].data()[p], without.distance[slot].data()[p]) << p;
      const float want = without.confidence[slot].data()[p] * factor[p];
      worst = std::max(worst, double(std::abs(with.confidence[slot].data()[p] - want)));
      mean_factor += factor[p] / double(factor.size());
      lowered += factor[p] < 0.5f;
    }
    std::cout << "slot " << slot << ": coarse agreement vs CPU, largest difference " << worst
              << "; mean factor " << mean_factor << ", " << lowered << " pixels below 0.5\n";
    EXPECT_LT(worst, 1e-5);
    EXPECT_GT(mean_factor, 0.5);  // most pixels agree with their block
    EXPECT_GT(lowered, 0);        // and some do not: edges between near and far surfaces
  }
}

// The raw agreement (wta.glsl): the fused winner follows each pixel's raw curve too, and the
// confidence with it is the confidence without it times raw_agreement_cpu's factor, from the raw
// volume and the unfused filter's (32-bit costs, so the two filters pick the same candidates but
// at near-ties); the distances stay the same.
TEST_F(DepthEstimatorTest, RawAgreementEqualsCpu) {
  const int n = 96;
  const auto scene = fixtures::render_depth_case(n);
  DepthOptions options = unfiltered_cpu_check_options(n);
  DepthEstimator plain(context(), scene.rig.rig(), scene.usable, options);
  const DepthResult without = plain.estimate(scene.image_views());
  options.raw_agreement = 0.3;
  DepthEstimator estimator(context(), scene.rig.rig(), scene.usable, options);
  const auto raw = estimator.cost_volume(scene.image_views(), 0, false);
  const auto filtered = estimator.cost_volume(scene.image_views(), 0, true);
  const DepthResult with = estimator.estimate(scene.image_views());
  const int candidates = options.num_candidates;
  int close = 0, lowered = 0;
  for (int p = 0; p < n * n; ++p) {
    ASSERT_EQ(with.distance[0].data()[p], without.distance[0].data()[p]) << p;
    const std::size_t at = std::size_t(p) * candidates;
    const float factor =
        raw_agreement_cpu(&filtered[at], &raw[at], candidates, options.raw_agreement);
    const float want = without.confidence[0].data()[p] * factor;
    close += std::abs(with.confidence[0].data()[p] - want) < 1e-4f;
    lowered += factor < 0.5f;
  }
  std::cout << "raw agreement vs CPU: " << 100.0 * close / (n * n) << " % of pixels within 1e-4; "
            << lowered << " pixels with a factor below 0.5\n";
  EXPECT_GE(close, n * n * 995 / 1000);
  EXPECT_GT(lowered, n * n / 200);  // the filter carries distances in somewhere
  EXPECT_LT(lowered, n * n / 2);    // but most pixels' own curves agree
}

// The raw agreement's factor on curves whose answer is known.
TEST(RawAgreement, OfKnownCurves) {
  const std::vector<float> raw = {4, 1, 3, 5};  // lowest 1, highest 5: power 0.8
  const std::vector<float> agrees = {3, 1, 2, 3}, disputes = {3, 2, 1, 3};
  EXPECT_FLOAT_EQ(raw_agreement_cpu(agrees.data(), raw.data(), 4, 0.3), 1.0f);
  const float x = (3.0f - 1.0f) / 4.0f * 0.8f / 0.3f;  // raw[2] is halfway up
  EXPECT_FLOAT_EQ(raw_agreement_cpu(disputes.data(), raw.data(), 4, 0.3), std::exp(-x * x));
  EXPECT_FLOAT_EQ(raw_agreement_cpu(disputes.data(), raw.data(), 4, 0), 1.0f);  // off
  const std::vector<float> flat = {2, 2, 2, 2};
  EXPECT_FLOAT_EQ(raw_agreement_cpu(disputes.data(), flat.data(), 4, 0.3), 1.0f);
  // Candidate 0 is the nearest: a raw curve whose lowest lies beyond the filtered winner is not
  // heard, however high the winner sits on it.
  const std::vector<float> nearer = {1, 3, 3, 3};
  EXPECT_FLOAT_EQ(raw_agreement_cpu(nearer.data(), raw.data(), 4, 0.3), 1.0f);
}

// The confidence on curves whose answer is known: sqrt(peak ratio x sharpness).
TEST(CostConfidence, OfKnownCurves) {
  auto expected = [](double lowest, double second, double curvature) {
    return float(std::sqrt((1 - lowest / second) * curvature / (curvature + lowest + 1e-12)));
  };
  const std::vector<float> flat(8, 2.0f);
  EXPECT_EQ(cost_confidence_cpu(flat.data(), 8), 0.0f);
  const std::vector<float> one_minimum = {4, 3, 2, 1, 2, 3, 4, 8};  // second = highest
  EXPECT_FLOAT_EQ(cost_confidence_cpu(one_minimum.data(), 8), expected(1, 8, 2));
  const std::vector<float> two_minima = {4, 1, 4, 4, 2, 4, 4, 4};
  EXPECT_FLOAT_EQ(cost_confidence_cpu(two_minima.data(), 8), expected(1, 2, 6));
  const std::vector<float> tie = {4, 1, 4, 1, 4};
  EXPECT_EQ(cost_confidence_cpu(tie.data(), 5), 0.0f);
  const std::vector<float> ends = {1, 2, 3, 2, 1.5f};  // both ends are minima; one-sided curvature
  EXPECT_FLOAT_EQ(cost_confidence_cpu(ends.data(), 5), expected(1, 1.5, 2));
  const std::vector<float> plateau = {3, 2, 2, 2, 3, 4, 3};  // the plateau counts once
  EXPECT_FLOAT_EQ(cost_confidence_cpu(plateau.data(), 7), expected(2, 3, 1));
  const std::vector<float> perfect = {5, 0, 5};  // a zero cost with a sharp minimum
  EXPECT_FLOAT_EQ(cost_confidence_cpu(perfect.data(), 3), 1.0f);
}

// Measured on lavapipe, 512 px matching, defaults otherwise (frames 0 and 120, references 2, 3):
// MAE 0.018-0.043 m^-1, > 0.1: 0.35-9.3 %, > 0.4: 0-1.6 % of the pixels inside the lenses.
// Frame 0 is the harder one: the near sphere at 0.7 m and plain ceiling above it.
TEST_F(DepthEstimatorTest, FisheyeDistanceMatchesGroundTruth) {
  for (const int frame : {0, 120}) {
    const auto scene = fixtures::render_depth_case(512, frame);
    DepthOptions options;
    options.matching_width = options.matching_height = 512;
    DepthEstimator estimator(context(), scene.rig.rig(), scene.usable, options);
    const DepthResult result = estimator.estimate(scene.image_views());
    ASSERT_EQ(result.distance.size(), 2u);
    for (std::size_t slot = 0; slot < 2; ++slot) {
      const int ref = options.references[slot];
      const fixtures::Accuracy a = fixtures::inverse_distance_accuracy(
          result.distance[slot], scene.inverse_gt[ref], *scene.usable[ref]);
      std::cout << "frame " << frame << " reference " << ref << ": MAE " << a.mae
                << " m^-1, >0.1: " << 100 * a.bad_0_1 << " %, >0.4: " << 100 * a.bad_0_4
                << " % over " << a.pixels << " pixels\n";
      EXPECT_LT(a.mae, 0.05);
      EXPECT_LT(a.bad_0_1, 0.11);
      EXPECT_LT(a.bad_0_4, 0.02);
    }
    for (const auto& [stage, ms] : result.stage_ms)
      std::cout << "  " << stage << ": " << ms << " ms\n";
  }
}

// 16-bit cost storage (the default where the device has it) against 32-bit on the same frames:
// the accuracy against the ground truth stays within 1 % (MAE) and 0.1 percentage points (the
// bad-pixel rates), and the two distance maps agree on nearly every pixel.
TEST_F(DepthEstimatorTest, HalfCostsKeepTheAccuracy) {
  for (const int frame : {0, 120}) {
    const auto scene = fixtures::render_depth_case(256, frame);
    std::vector<DepthResult> results;
    bool half_used = false;
    for (const bool half : {false, true}) {
      DepthOptions options;
      options.matching_width = options.matching_height = 256;
      options.half_costs = half;
      DepthEstimator estimator(context(), scene.rig.rig(), scene.usable, options);
      half_used = estimator.volume_layout().half;
      results.push_back(estimator.estimate(scene.image_views()));
    }
    if (!half_used) GTEST_SKIP() << "the device stores no 16-bit floats";
    for (std::size_t slot = 0; slot < 2; ++slot) {
      const int ref = DepthOptions().references[slot];
      const fixtures::Accuracy full = fixtures::inverse_distance_accuracy(
          results[0].distance[slot], scene.inverse_gt[ref], *scene.usable[ref]);
      const fixtures::Accuracy half = fixtures::inverse_distance_accuracy(
          results[1].distance[slot], scene.inverse_gt[ref], *scene.usable[ref]);
      long apart = 0, pixels = 0;
      for (std::size_t p = 0; p < results[0].distance[slot].size(); ++p) {
        const float a = results[0].distance[slot].data()[p],
                    b = results[1].distance[slot].data()[p];
        ++pixels;
        apart += std::abs(1.0f / a - 1.0f / b) > 0.01f;
      }
      std::cout << "frame " << frame << " reference " << ref << ": MAE 32-bit " << full.mae
                << ", 16-bit " << half.mae << "; > 0.4: " << 100 * full.bad_0_4 << " / "
                << 100 * half.bad_0_4 << " %; " << 100.0 * apart / pixels
                << " % of pixels more than 0.01 m^-1 apart\n";
      EXPECT_LT(half.mae, 1.01 * full.mae);
      EXPECT_LT(half.bad_0_1, full.bad_0_1 + 0.001);
      EXPECT_LT(half.bad_0_4, full.bad_0_4 + 0.001);
      EXPECT_LT(double(apart) / pixels, 0.01);
    }
  }
}

// References taken in groups (DepthOptions::max_group) give the same maps, bit for bit, as all
// of them in each dispatch: every slot computes the same, whichever dispatch it is in.
TEST_F(DepthEstimatorTest, GroupsOfReferencesGiveTheSameMaps) {
  const auto scene = fixtures::render_depth_case(64);
  std::vector<DepthResult> results;
  for (const int group : {0, 2, 1}) {
    DepthOptions options;
    options.matching_width = options.matching_height = 64;
    options.references = {0, 1, 2, 3};
    options.max_group = group;
    DepthEstimator estimator(context(), scene.rig.rig(), scene.usable, options);
    EXPECT_EQ(estimator.group_size(), group == 0 ? 4 : group);
    results.push_back(estimator.estimate(scene.image_views()));
    ASSERT_EQ(results.back().distance.size(), 4u);
  }
  for (std::size_t r = 1; r < results.size(); ++r) {
    for (std::size_t slot = 0; slot < 4; ++slot) {
      const FloatImage& a = results[0].distance[slot];
      const FloatImage& b = results[r].distance[slot];
      EXPECT_TRUE(std::equal(a.data(), a.data() + a.size(), b.data())) << r << " " << slot;
    }
  }
  // Each slot's map is its own reference's: not a copy of another's.
  EXPECT_FALSE(std::equal(results[0].distance[0].data(),
                          results[0].distance[0].data() + results[0].distance[0].size(),
                          results[0].distance[1].data()));
}

TEST_F(DepthEstimatorTest, RejectsBadInput) {
  const auto scene = fixtures::render_depth_case(64);
  DepthOptions options;
  options.matching_width = options.matching_height = 64;
  options.references = {2, 9};
  EXPECT_THROW(DepthEstimator(context(), scene.rig.rig(), scene.usable, options),
               std::invalid_argument);
  options.references = {0, 1, 2, 3, 0, 1, 2, 3, 0};  // too many (and repeated)
  EXPECT_THROW(DepthEstimator(context(), scene.rig.rig(), scene.usable, options),
               std::invalid_argument);
  options.references = {2, 3};
  options.max_group = -1;
  EXPECT_THROW(DepthEstimator(context(), scene.rig.rig(), scene.usable, options),
               std::invalid_argument);
  options.max_group = 0;
  options.num_candidates = 1;
  EXPECT_THROW(DepthEstimator(context(), scene.rig.rig(), scene.usable, options),
               std::invalid_argument);
  options.num_candidates = 32;
  options.matching_width = 128;  // rig is at 64
  EXPECT_THROW(DepthEstimator(context(), scene.rig.rig(), scene.usable, options),
               std::invalid_argument);
  options.matching_width = 64;
  DepthEstimator estimator(context(), scene.rig.rig(), scene.usable, options);
  std::vector<Rgb8View> three = scene.image_views();
  three.pop_back();
  EXPECT_THROW(estimator.estimate(three), std::invalid_argument);
}

}  // namespace
}  // namespace omnisweep::depth
