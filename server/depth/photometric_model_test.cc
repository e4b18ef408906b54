// The photometric model: on synthetic frames through lenses with known gains, casts and
// vignetting, the fit finds them, and the correction brings the images back to the scene's colours.
#include "server/depth/photometric_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <numbers>

#include "server/synthetic/synthetic_rig.h"

namespace omnisweep::depth {
namespace {

struct Case {
  synthetic::SyntheticRig rig;
  std::vector<Rgb8Image> images;
  std::vector<std::optional<Gray8Image>> masks;
};

Case render(const synthetic::PhotometricOptions& photometric, int size = 256) {
  synthetic::SyntheticRigOptions options;
  options.image_size = size;
  options.photometric = photometric;
  Case out{synthetic::SyntheticRig(options), {}, {}};
  synthetic::SyntheticFrame frame = out.rig.render(0, 16, 8);
  for (auto& cam : frame.cameras) out.images.push_back(std::move(cam.rgb));
  for (auto& mask : out.rig.masks()) out.masks.emplace_back(std::move(mask));
  return out;
}

TEST(PhotometricModel, FindsTheGainsCastsAndVignettingOfTheLenses) {
  const auto c = render(synthetic::PhotometricOptions::realistic());
  const PhotometryFit fit = estimate_photometry(c.rig.rig(), views(c.images), c.masks);
  ASSERT_EQ(fit.cameras.size(), 4u);
  // The truth, up to the fit's gauge: each channel's gains over their geometric mean.
  for (int k = 0; k < 3; ++k) {
    double log_mean = 0;
    for (int cam = 0; cam < 4; ++cam) log_mean += std::log(c.rig.response(cam).gain[k]) / 4;
    for (int cam = 0; cam < 4; ++cam) {
      const double truth = c.rig.response(cam).gain[k] / std::exp(log_mean);
      EXPECT_NEAR(fit.cameras[cam].gain[k] / truth, 1.0, 0.03)
          << "camera " << cam << " channel " << k;
    }
  }
  const double edge = 110.0 * std::numbers::pi / 180.0;
  for (int cam = 0; cam < 4; ++cam) {
    std::cout << "camera " << cam << ": V(110 deg) " << fit.cameras[cam].vignetting(edge)
              << " (truth " << c.rig.response(cam).vignetting << "), V(60 deg) "
              << fit.cameras[cam].vignetting(edge * 60 / 110) << "\n";
    EXPECT_NEAR(fit.cameras[cam].vignetting(edge), c.rig.response(cam).vignetting, 0.06);
  }
  std::cout << fit.pairs << " pairs, rms residual " << fit.rms_residual << "\n";
}

TEST(PhotometricModel, FindsNothingWhereThereIsNothing) {
  const auto c = render({});
  const PhotometryFit fit = estimate_photometry(c.rig.rig(), views(c.images), c.masks);
  for (int cam = 0; cam < 4; ++cam) {
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(fit.cameras[cam].gain[k], 1.0, 0.02);
    EXPECT_NEAR(fit.cameras[cam].vignetting(110.0 * std::numbers::pi / 180.0), 1.0, 0.05);
  }
}

TEST(PhotometricModel, CorrectionBringsBackTheScenesColors) {
  const auto clean = render({});
  auto changed = render(synthetic::PhotometricOptions::realistic());
  const PhotometryFit fit =
      estimate_photometry(changed.rig.rig(), views(changed.images), changed.masks);
  auto mean_error = [&](const std::vector<Rgb8Image>& images) {
    // Up to the gauge: compare after scaling each channel by the mean ratio over all cameras.
    double error = 0;
    long n = 0;
    for (int k = 0; k < 3; ++k) {
      double a = 0, b = 0;
      for (int cam = 0; cam < 4; ++cam)
        for (std::size_t p = k; p < images[cam].size(); p += 3) {
          a += images[cam].data()[p];
          b += clean.images[cam].data()[p];
        }
      for (int cam = 0; cam < 4; ++cam)
        for (std::size_t p = k; p < images[cam].size(); p += 3) {
          const double v = clean.images[cam].data()[p];
          if (v < 10 || v > 200) continue;
          error += std::abs(images[cam].data()[p] * b / a - v);
          ++n;
        }
    }
    return error / n;
  };
  const double before = mean_error(changed.images);
  PhotometricCorrection(changed.rig.rig()).apply(fit, changed.images);
  const double after = mean_error(changed.images);
  std::cout << "mean colour error against the scene's: " << before << " levels before, " << after
            << " after\n";
  EXPECT_LT(after, 2.5);
  EXPECT_LT(after, before / 4);
}

TEST(PhotometricCorrector, RefitsInTheBackgroundWhileTheFramesGoOn) {
  const auto clean = render({});
  const auto changed = render(synthetic::PhotometricOptions::realistic());
  const PhotometryFit truth =
      estimate_photometry(changed.rig.rig(), views(changed.images), changed.masks);
  auto same = [](const PhotometryFit& a, const PhotometryFit& b) {
    for (std::size_t cam = 0; cam < a.cameras.size(); ++cam) {
      for (int k = 0; k < 3; ++k)
        if (std::abs(a.cameras[cam].gain[k] - b.cameras[cam].gain[k]) > 1e-9) return false;
      if (std::abs(a.cameras[cam].b1 - b.cameras[cam].b1) > 1e-9) return false;
    }
    return a.cameras.size() == b.cameras.size();
  };
  // In the frame (omnisweep-process): each frame gets its own fit.
  PhotometricCorrector now(changed.rig.rig(), changed.masks);
  const PhotometryFit first = now.fit(views(clean.images));
  EXPECT_TRUE(same(now.fit(views(changed.images)), truth));

  // In the background (omnisweep-server): the first frame waits for its fit; the next frame,
  // whose refit is due, goes on with the last fit while its own is computed, and the frame after
  // the refit has finished gets it.
  PhotometricCorrector background(changed.rig.rig(), changed.masks, /*refresh_every=*/2,
                                  /*refit_in_background=*/true);
  EXPECT_TRUE(same(background.fit(views(clean.images)), first));
  EXPECT_TRUE(same(background.fit(views(changed.images)), first));  // not due
  EXPECT_TRUE(same(background.fit(views(changed.images)), first));  // due: starts the refit
  background.finish_refit();
  EXPECT_TRUE(same(background.fit(views(clean.images)), truth));
  EXPECT_FALSE(same(first, truth));  // the check can fail
}

TEST(PhotometricModel, RejectsMismatchedInputs) {
  const auto c = render({}, 64);
  auto images = views(c.images);
  images.pop_back();
  EXPECT_THROW(estimate_photometry(c.rig.rig(), images, c.masks), std::invalid_argument);
  std::vector<Rgb8Image> wrong;
  wrong.emplace_back(10, 10);
  EXPECT_THROW(PhotometricCorrection(c.rig.rig()).apply(PhotometryFit{{{}, {}, {}, {}}}, wrong),
               std::invalid_argument);
}

}  // namespace
}  // namespace omnisweep::depth
