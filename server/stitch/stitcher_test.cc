// Stitching end to end on synthetic frames: depth on the GPU, then the panorama, compared with
// the exact ground-truth panorama at the same viewpoint.
#include "server/stitch/stitcher.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "omnisweep/gpu/command_log.h"
#include "omnisweep/image/image_io.h"
#include "server/depth/depth_estimator.h"
#include "server/depth/photometric_model.h"
#include "server/pipeline/gpu_frame.h"
#include "server/stitch/blend_weights.h"
#include "server/stitch/membrane_fill.h"
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
  o = {};
  o.panorama_width = 1020;  // cells of 4 pixels: 510 rows are not a whole number of them
  o.panorama_height = 510;
  EXPECT_NO_THROW(o.check());
  o.membrane_fill = true;
  EXPECT_NE(message(o).find("StitchOptions.membrane_fill: the panorama 1020x510"),
            std::string::npos)
      << message(o);
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

// Frame 0 of a synthetic rig, with its four camera images and usable masks resized to the
// matching resolution and depth options for it.
struct TestFrame {
  synthetic::SyntheticRig rig;
  synthetic::SyntheticFrame frame;
  Rig matching_rig;
  std::vector<Rgb8Image> images;
  std::vector<std::optional<Gray8Image>> usable;
  depth::DepthOptions options;
};
TestFrame render(const synthetic::SyntheticRigOptions& rig_options, int matching, int pano_w,
                 int pano_h) {
  TestFrame out{synthetic::SyntheticRig(rig_options), {}, {}, {}, {}, {}};
  out.frame = out.rig.render(0, pano_w, pano_h);
  out.matching_rig = out.rig.rig().resized(matching, matching);
  const std::vector<Gray8Image> masks = out.rig.masks();
  for (int c = 0; c < 4; ++c) {
    out.images.push_back(resize_area(out.frame.cameras[c].rgb, matching, matching));
    out.usable.emplace_back(usable_mask(masks[c], matching, matching));
  }
  out.options.matching_width = out.options.matching_height = matching;
  return out;
}

// (The z-buffer and disocclusion filling are tested on an analytic near-object scene in
// client_sdk/src/reproject/forward_warp_test.cc.)
TEST_F(StitcherTest, PanoramaMatchesTheGroundTruth) {
  synthetic::SyntheticRigOptions rig_options;
  rig_options.image_size = 608;
  const int pano_w = 1024, pano_h = 512;
  const TestFrame test = render(rig_options, 512, pano_w, pano_h);
  const auto& [rig, frame, matching_rig, images, usable, options] = test;
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

  // With the membrane fill (on the GPU, in the same submission): the C++ reference's fill of the
  // panorama, to float's rounding; the colour and the confidence are unchanged. This clean
  // frame has no large unconfident region, so one is made: no confidence within a disc about each
  // reference's axis (a cone of about 40 degrees).
  std::vector<FloatImage> unsure;
  for (const FloatImage& c : depth.confidence) {
    unsure.push_back(c.clone());
    const double cx = c.width() / 2.0, cy = c.height() / 2.0, r = 0.2 * c.width();
    for (int y = 0; y < c.height(); ++y) {
      for (int x = 0; x < c.width(); ++x)
        if (std::hypot(x + 0.5 - cx, y + 0.5 - cy) < r) unsure.back()(x, y) = 0;
    }
  }
  const std::vector<Rgb8View> colors{frame.cameras[2].rgb, frame.cameras[3].rgb};
  const Panorama before = stitcher.stitch(views(depth.distance), colors, views(unsure));
  Stitcher membrane(context(), matching_rig, rig.rig(), options.references, usable,
                    {.panorama_width = pano_w, .panorama_height = pano_h, .membrane_fill = true});
  const Panorama filled = membrane.stitch(views(depth.distance), colors, views(unsure));
  const FloatImage expected =
      membrane_fill_cpu(before.distance, before.confidence, MembraneFillParams::for_width(pano_w),
                        StitchOptions{}.min_distance, StitchOptions{}.max_distance);
  long changed = 0;
  double worst = 0;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    const bool filled_here = expected.data()[i] != before.distance.data()[i];
    ASSERT_EQ(filled_here, filled.distance.data()[i] != before.distance.data()[i]) << "pixel " << i;
    changed += filled_here;
    if (filled_here)
      worst = std::max(worst, std::abs(1.0 / filled.distance.data()[i] - 1.0 / expected.data()[i]));
  }
  EXPECT_TRUE(std::equal(filled.confidence.pixels().begin(), filled.confidence.pixels().end(),
                         before.confidence.pixels().begin()));
  EXPECT_TRUE(std::equal(filled.rgb.pixels().begin(), filled.rgb.pixels().end(),
                         before.rgb.pixels().begin()));
  EXPECT_EQ(filled.stage_ms.back().first, "membrane fill");
  const PanoramaMetrics mb = evaluate_panorama(before.rgb, before.distance, frame.panorama.rgb,
                                               frame.panorama.inverse_distance);
  const PanoramaMetrics mf = evaluate_panorama(filled.rgb, filled.distance, frame.panorama.rgb,
                                               frame.panorama.inverse_distance);
  std::cout << "membrane fill: " << changed << " pixels filled, MAE " << mb.mae << " -> " << mf.mae
            << " m^-1, GPU - CPU at most " << worst << ", " << filled.stage_ms.back().second
            << " ms\n";
  EXPECT_GT(changed, long(expected.size() / 50));  // more than 2 % of the panorama
  EXPECT_LT(worst, 1e-3);
}

// --correct-photometry's path: GpuFrame undoes the host's fit on the GPU, in the matching and the
// colour images, and gives the panorama that the host's own correction (the CPU check) gives.
TEST_F(StitcherTest, GpuFrameUndoesThePhotometricFitAsTheHostWould) {
  synthetic::SyntheticRigOptions rig_options;
  rig_options.image_size = 192;
  rig_options.photometric = synthetic::PhotometricOptions::realistic();
  const int pano_w = 256, pano_h = 128;
  const TestFrame test = render(rig_options, 160, pano_w, pano_h);
  const auto& [rig, frame, matching_rig, images, usable, options] = test;
  const std::vector<Rgb8View> color{frame.cameras[2].rgb, frame.cameras[3].rgb};
  const depth::PhotometryFit fit = depth::estimate_photometry(matching_rig, views(images), usable);
  std::vector<Rgb8Image> host_images;
  for (const auto& im : images) host_images.push_back(im.clone());
  std::vector<Rgb8Image> host_color;
  for (const int c : options.references) host_color.push_back(frame.cameras[c].rgb.clone());
  depth::PhotometricCorrection(matching_rig).apply(fit, host_images);
  depth::PhotometricCorrection(rig.rig()).apply(fit, host_color, options.references);

  depth::DepthEstimator estimator(context(), matching_rig, usable, options);
  StitchOptions stitch_options;
  stitch_options.panorama_width = pano_w;
  stitch_options.panorama_height = pano_h;
  Stitcher stitcher(context(), matching_rig, rig.rig(), options.references, usable, stitch_options);
  pipeline::GpuFrame gpu_frame(context(), estimator, stitcher);
  const Panorama host = gpu_frame.run(views(host_images), views(host_color));
  const Panorama gpu = gpu_frame.run(views(images), color, &fit);
  const Panorama raw = gpu_frame.run(views(images), color);
  auto color_difference = [&](const Panorama& a) {
    double sum = 0;
    for (std::size_t i = 0; i < a.rgb.size(); ++i)
      sum += std::abs(int(a.rgb.data()[i]) - int(host.rgb.data()[i]));
    return sum / double(a.rgb.size());
  };
  auto same_distance = [&](const Panorama& a) {
    long same = 0;
    for (std::size_t i = 0; i < a.distance.size(); ++i)
      same += std::abs(a.distance.data()[i] - host.distance.data()[i]) <=
              0.01f * host.distance.data()[i];
    return double(same) / double(a.distance.size());
  };
  std::cout << "against the host's correction: colour " << color_difference(gpu)
            << " levels apart, distance within 1 % on " << 100 * same_distance(gpu)
            << " % of the pixels; uncorrected: " << color_difference(raw) << " levels, "
            << 100 * same_distance(raw) << " %\n";
  EXPECT_LT(color_difference(gpu), 0.5);  // each channel a rounding apart at most
  EXPECT_GT(same_distance(gpu), 0.98);
  EXPECT_GT(color_difference(raw), 2.0);  // the fit changes the frame: the check can fail
  EXPECT_LT(same_distance(raw), same_distance(gpu));
}

}  // namespace
}  // namespace omnisweep::stitch
