// Stitching end to end on synthetic frames: depth on the GPU, then the panorama, compared with
// the exact ground-truth panorama at the same viewpoint.
#include "server/stitch/stitcher.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "omnisweep/gpu/command_log.h"
#include "omnisweep/image/image_io.h"
#include "server/depth/depth_estimator.h"
#include "server/pipeline/gpu_frame.h"
#include "server/stitch/blend_weights.h"
#include "server/stitch/panorama_metrics.h"
#include "server/synthetic/synthetic_rig.h"
#include "tests/support/gpu_test_support.h"
#include "tests/support/test_support.h"

namespace omnisweep::stitch {
namespace {

using omnisweep::testing::ValidatedGpuTest;
using StitcherTest = ValidatedGpuTest;

TEST(StitchOptions, CheckNamesTheFieldAndItsValue) {
  EXPECT_NO_THROW(StitchOptions{}.check());
  auto message = [](const StitchOptions& o) {
    return omnisweep::testing::error_message<std::invalid_argument>([&] { o.check(); });
  };
  StitchOptions o;
  o.panorama_width = 300;
  EXPECT_NE(message(o).find("300x1024"), std::string::npos) << message(o);
  EXPECT_NE(message(o).find("twice the height"), std::string::npos);
  o = {};
  o.max_distance = 0.1;
  EXPECT_NE(message(o).find("StitchOptions.max_distance = 0.1"), std::string::npos) << message(o);
  o = {};
  o.inpaint_passes = -1;
  EXPECT_NE(message(o).find("StitchOptions.inpaint_passes = -1"), std::string::npos) << message(o);
  o = {};
  o.viewpoint = Eigen::Vector3d(0, std::nan(""), 0);
  EXPECT_NE(message(o).find("StitchOptions.viewpoint"), std::string::npos) << message(o);
}

TEST(BoxFilter, WrapsHorizontallyAndPadsVertically) {
  FloatImage im(8, 4);
  im(0, 1) = 9.0f;
  const FloatImage out = box_filter(im, 3, true, 0.0f);
  EXPECT_FLOAT_EQ(out(7, 1), 1.0f);  // the left edge's neighbour across the seam
  EXPECT_FLOAT_EQ(out(1, 0), 1.0f);
  const FloatImage padded = box_filter(FloatImage(5, 5), 3, false, 1.0f);
  EXPECT_FLOAT_EQ(padded(0, 0), 5.0f / 9.0f);  // five of nine taps outside
  EXPECT_FLOAT_EQ(padded(2, 2), 0.0f);
}

TEST(PanoramaMetrics, IdenticalImagesAndKnownErrors) {
  Rgb8Image a = Rgb8Image::filled(16, 12, 100);
  for (std::size_t i = 0; i < a.size(); ++i) a.data()[i] = std::uint8_t(i * 7 % 256);
  EXPECT_NEAR(ssim(a, a), 1.0, 1e-12);
  Rgb8Image b = a.clone();
  b.data()[5] ^= 16;
  EXPECT_LT(ssim(a, b), 1.0);
  EXPECT_NEAR(psnr(a, b), 10 * std::log10(255.0 * 255.0 / (256.0 / double(a.size()))), 1e-9);
  FloatImage distance = FloatImage::filled(16, 12, 2.0f);
  FloatImage inverse = FloatImage::filled(16, 12, 0.5f);
  inverse(3, 3) = 1.0f;  // one pixel off by 0.5
  const PanoramaMetrics m = evaluate_panorama(a, distance, a, inverse);
  EXPECT_NEAR(m.mae, 0.5 / 192, 1e-12);
  EXPECT_NEAR(m.bad_0_4, 1.0 / 192, 1e-12);
  EXPECT_THROW(evaluate_panorama(a, FloatImage(8, 4), a, inverse), std::invalid_argument);
}

// (The z-buffer and disocclusion filling are tested on an analytic near-object scene in
// client_sdk/src/reproject/forward_warp_test.cc.)
TEST_F(StitcherTest, PanoramaMatchesTheGroundTruth) {
  synthetic::SyntheticRigOptions rig_options;
  rig_options.image_size = 608;
  const synthetic::SyntheticRig rig(rig_options);
  const int matching = 512, pano_w = 1024, pano_h = 512;
  const synthetic::SyntheticFrame frame = rig.render(0, pano_w, pano_h);
  const Rig matching_rig = rig.rig().resized(matching, matching);
  std::vector<Rgb8Image> images;
  std::vector<std::optional<Gray8Image>> usable;
  const std::vector<Gray8Image> masks = rig.masks();
  for (int c = 0; c < 4; ++c) {
    images.push_back(resize_area(frame.cameras[c].rgb, matching, matching));
    usable.emplace_back(usable_mask(masks[c], matching, matching));
  }
  depth::DepthOptions options;
  options.matching_width = options.matching_height = matching;
  depth::DepthEstimator estimator(context(), matching_rig, usable, options);
  std::vector<Rgb8View> image_views;
  for (const auto& im : images) image_views.push_back(im);
  const depth::DepthResult depth = estimator.estimate(image_views);

  Stitcher stitcher(context(), matching_rig, rig.rig(), options.references, usable,
                    {.panorama_width = pano_w, .panorama_height = pano_h});
  EXPECT_TRUE(stitcher.viewpoint().isApprox(rig.viewpoint(), 1e-12));
  {  // The GPU's blending weights against the plain C++ version.
    BlendSetup setup{&matching_rig, options.references, rig.viewpoint(), {}, 0.55, 100.0, pano_w,
                     pano_h};
    for (const auto& u : usable) setup.usable.emplace_back(u->clone());
    const std::vector<FloatImage> cpu = blend_weights(setup), gpu = stitcher.weights();
    double worst = 0;
    long close = 0;
    for (std::size_t k = 0; k < cpu.size(); ++k) {
      for (std::size_t i = 0; i < cpu[k].size(); ++i) {
        const double d = std::abs(double(cpu[k].data()[i]) - gpu[k].data()[i]);
        worst = std::max(worst, d);
        close += d < 1e-3;
      }
    }
    const double share = double(close) / double(2 * cpu[0].size());
    std::cout << "blending weights GPU vs C++: " << 100 * share
              << " % within 1e-3, largest difference " << worst << "\n";
    EXPECT_GT(share, 0.999);
    EXPECT_LT(worst, 0.02);
  }
  const Panorama pano = stitcher.stitch(
      views(depth.distance), std::vector<Rgb8View>{frame.cameras[2].rgb, frame.cameras[3].rgb},
      views(depth.confidence));
  const PanoramaMetrics m = evaluate_panorama(pano.rgb, pano.distance, frame.panorama.rgb,
                                              frame.panorama.inverse_distance);
  std::cout << "panorama: MAE " << m.mae << " m^-1, RMSE " << m.rmse << ", >0.1 " << 100 * m.bad_0_1
            << " %, >0.4 " << 100 * m.bad_0_4 << " %, PSNR " << m.psnr << " dB, SSIM " << m.ssim
            << "\n";
  for (const auto& [stage, ms] : pano.stage_ms) std::cout << "  " << stage << ": " << ms << " ms\n";
  long empty = 0;
  for (float d : pano.distance.pixels()) empty += !(d > 0);
  // Measured on lavapipe (frame 0, 512 px matching, 608 px colour, 1024x512 panorama): MAE 0.0303
  // m^-1, > 0.1 4.97 %, > 0.4 0.66 %, PSNR 33.2 dB, SSIM 0.970.
  EXPECT_EQ(empty, 0);
  EXPECT_LT(m.mae, 0.04);
  EXPECT_LT(m.bad_0_4, 0.01);
  EXPECT_GT(m.psnr, 31.5);
  EXPECT_GT(m.ssim, 0.96);

  // The confidence ranks the errors: dropping the least confident pixels lowers the MAE of the
  // rest, step after step. Measured here: MAE 0.0303, 80 % most confident 0.0202, AUSE 0.0081.
  const Sparsification curve =
      sparsification(pano.distance, pano.confidence, frame.panorama.inverse_distance);
  std::cout << "confidence: MAE of the 80 % most confident " << curve.mae_at_80 << ", AUSE "
            << curve.ause << (curve.monotonic ? "" : ", curve not monotonic") << "\n";
  for (const float c : pano.confidence.pixels()) ASSERT_TRUE(c >= 0 && c <= 1) << c;
  EXPECT_TRUE(curve.monotonic);
  EXPECT_LT(curve.mae_at_80, 0.75 * m.mae);
  EXPECT_LT(curve.ause, 0.5 * m.mae);

  // The same frame as one submission, depth never leaving the GPU: the same panorama, bit for bit.
  gpu::CommandLog log;
  context().set_command_log(&log);
  pipeline::GpuFrame gpu_frame(context(), estimator, stitcher);
  const Panorama resident =
      gpu_frame.run(image_views, std::vector<Rgb8View>{frame.cameras[2].rgb, frame.cameras[3].rgb});
  context().set_command_log(nullptr);
  // One submission from the images to the panorama (staged transfers before and after it wait
  // for the GPU too, where memory is not mapped).
  EXPECT_EQ(log.totals().round_trips - log.totals(gpu::CommandLog::kTransferStage).round_trips, 1u);
  EXPECT_EQ(log.totals().download_bytes, pano.distance.size() * 12)
      << "only the panorama (colour, distance, confidence) comes back";
  EXPECT_TRUE(std::equal(resident.rgb.pixels().begin(), resident.rgb.pixels().end(),
                         pano.rgb.pixels().begin()));
  EXPECT_TRUE(std::equal(resident.distance.pixels().begin(), resident.distance.pixels().end(),
                         pano.distance.pixels().begin()));
  EXPECT_TRUE(std::equal(resident.confidence.pixels().begin(), resident.confidence.pixels().end(),
                         pano.confidence.pixels().begin()));
}

}  // namespace
}  // namespace omnisweep::stitch
