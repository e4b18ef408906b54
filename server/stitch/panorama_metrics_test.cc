// The sparsification curve and its figures on a panorama small enough to count by hand.
#include "server/stitch/panorama_metrics.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

#include "server/stitch/same_size.h"
#include "tests/support/test_support.h"

namespace omnisweep::stitch {
namespace {

FloatImage image_of(const std::vector<float>& values) {
  FloatImage image(int(values.size()), 1);
  for (std::size_t i = 0; i < values.size(); ++i) image.data()[i] = values[i];
  return image;
}

// Five pixels at 1 m (inverse distance 1) whose truths are off by 0.1, 0.2, 0.3, 0.4 and 0.5.
struct Fixture {
  FloatImage distance = image_of({1, 1, 1, 1, 1});
  FloatImage truth = image_of({1.1f, 1.2f, 1.3f, 1.4f, 1.5f});
};

TEST(SparsificationTest, ACurveCountedByHand) {
  const Fixture f;
  // The confidence ranks the 0.3 error first, then 0.1, 0.2, 0.5 and 0.4 last.
  const FloatImage confidence = image_of({0.8f, 0.7f, 0.9f, 0.1f, 0.2f});
  const Sparsification s = sparsification(f.distance, confidence, f.truth, 5);
  ASSERT_EQ(s.removed.size(), 5u);
  // Kept after removing 0, 1, 2, 3, 4 of the 5 least confident: {all}, {0.3 0.1 0.2 0.5},
  // {0.3 0.1 0.2}, {0.3 0.1}, {0.3}.
  const std::vector<double> mae = {0.3, 0.275, 0.2, 0.2, 0.3};
  const std::vector<double> oracle = {0.3, 0.25, 0.2, 0.15, 0.1};
  for (std::size_t i = 0; i < mae.size(); ++i) {
    EXPECT_NEAR(s.removed[i], 0.2 * double(i), 1e-12);
    EXPECT_NEAR(s.mae[i], mae[i], 1e-6) << i;
    EXPECT_NEAR(s.oracle[i], oracle[i], 1e-6) << i;
  }
  EXPECT_NEAR(s.mae_at_80, 0.275, 1e-6);
  EXPECT_NEAR(s.oracle_at_80, 0.25, 1e-6);
  EXPECT_NEAR(s.ause, (0.025 + 0.05 + 0.2) / 5, 1e-6);
  EXPECT_FALSE(s.monotonic);  // the last step rises (0.2 to 0.3)
}

TEST(SparsificationTest, AConfidenceThatRanksLikeTheErrorIsTheOracle) {
  const Fixture f;
  const FloatImage confidence = image_of({0.9f, 0.8f, 0.7f, 0.6f, 0.5f});
  const Sparsification s = sparsification(f.distance, confidence, f.truth, 5);
  EXPECT_EQ(s.mae, s.oracle);
  EXPECT_DOUBLE_EQ(s.mae_at_80, s.oracle_at_80);
  EXPECT_NEAR(s.ause, 0.0, 1e-12);
  EXPECT_TRUE(s.monotonic);
}

TEST(SparsificationTest, BadSizesAreNamed) {
  const Fixture f;
  EXPECT_EQ(
      omnisweep::testing::error_message<std::invalid_argument>([&] {
        sparsification(f.distance, image_of({1, 1}), f.truth);
      }),
      "sparsification: the confidence panorama is 2x1, the ground-truth inverse distance 5x1");
  EXPECT_THROW(sparsification(f.distance, image_of({1, 1, 1, 1, 1}), f.truth, 1),
               std::invalid_argument);
}

// The MAE by eighth of the rows: each eighth alone, the top first, and their mean the MAE of all
// (the eighths are equal); a height that 8 does not divide gives its rows to the eighths as
// y * 8 / height does.
TEST(PanoramaMetricsTest, MaeByEighthOfTheRows) {
  const int width = 8, height = 16;  // SSIM needs 7 x 7
  const FloatImage distance = FloatImage::filled(width, height, 1.0f);
  FloatImage truth(width, height);
  for (int y = 0; y < height; ++y) {
    const int eighth = y / 2;
    for (int x = 0; x < width; ++x) truth.data()[y * width + x] = 1.0f + 0.01f * float(eighth);
  }
  const Rgb8Image rgb(width, height);
  const PanoramaMetrics m = evaluate_panorama(rgb, distance, rgb, truth);
  double mean = 0;
  for (int b = 0; b < 8; ++b) {
    EXPECT_NEAR(m.mae_by_eighth[std::size_t(b)], 0.01 * b, 1e-6) << "eighth " << b;
    mean += m.mae_by_eighth[std::size_t(b)] / 8;
  }
  EXPECT_NEAR(mean, m.mae, 1e-9);

  // 12 rows: the eighths hold rows {0, 1}, {2}, {3, 4}, {5}, {6, 7}, {8}, {9, 10}, {11}.
  FloatImage truth12(width, 12);
  for (int y = 0; y < 12; ++y) {
    for (int x = 0; x < width; ++x) truth12.data()[y * width + x] = 1.0f + 0.01f * float(y);
  }
  const Rgb8Image rgb12(width, 12);
  const PanoramaMetrics m12 =
      evaluate_panorama(rgb12, FloatImage::filled(width, 12, 1.0f), rgb12, truth12);
  const double expected[8] = {0.005, 0.02, 0.035, 0.05, 0.065, 0.08, 0.095, 0.11};
  for (int b = 0; b < 8; ++b)
    EXPECT_NEAR(m12.mae_by_eighth[std::size_t(b)], expected[b], 1e-6) << "eighth " << b;
}

// Every pass's CPU reference and every metric checks its inputs' sizes with this one message.
TEST(SameSizeTest, NamesThePassAndTheFirstImageThatDiffers) {
  const FloatImage a(4, 2), b(4, 2), c(2, 4), d(3, 3);
  EXPECT_NO_THROW(require_same_size("pass", {sized("distance", a), sized("confidence", b)}));
  EXPECT_NO_THROW(require_same_size("pass", {}));
  EXPECT_EQ(omnisweep::testing::error_message<std::invalid_argument>([&] {
              require_same_size("plane fill", {sized("distance", a), sized("colour", b),
                                               sized("confidence", c), sized("other", d)});
            }),
            "plane fill: the confidence is 2x4, the distance 4x2");
  EXPECT_EQ(omnisweep::testing::error_message<std::invalid_argument>(
                [&] { psnr(Rgb8Image(4, 2), Rgb8Image(2, 2)); }),
            "PSNR: the colour panorama is 4x2, the ground-truth colour 2x2");
}

}  // namespace
}  // namespace omnisweep::stitch
