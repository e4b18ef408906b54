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
