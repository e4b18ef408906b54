// The synthetic rig's photometric conditions: gains, casts and vignetting as drawn, noise new
// every frame and repeatable with the seed, ground truth untouched, bad options named.
#include "server/synthetic/photometric.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "server/synthetic/synthetic_rig.h"

namespace omnisweep::synthetic {
namespace {

SyntheticRig rig_with(const PhotometricOptions& photometric) {
  SyntheticRigOptions options;
  options.image_size = 128;
  options.photometric = photometric;
  return SyntheticRig(options);
}

template <typename T, int C>
bool same(const Image<T, C>& a, const Image<T, C>& b) {
  return std::ranges::equal(a.pixels(), b.pixels());
}

// Mean of channel k over pixels where both images are lit, and the ratio b / a there.
double mean_ratio(const Rgb8Image& a, const Rgb8Image& b, int k, int x0, int y0, int size) {
  double sa = 0, sb = 0;
  for (int y = y0; y < y0 + size; ++y) {
    for (int x = x0; x < x0 + size; ++x) {
      if (a(x, y, k) < 20 || a(x, y, k) > 200) continue;
      sa += a(x, y, k);
      sb += b(x, y, k);
    }
  }
  return sb / sa;
}

TEST(Photometric, RealisticRangesAreDrawnPerCameraAndRepeatWithTheSeed) {
  const PhotometricOptions o = PhotometricOptions::realistic();
  double lo = 9, hi = 0;
  for (int c = 0; c < 4; ++c) {
    const CameraResponse r = draw_camera_response(o, 7, c);
    const CameraResponse again = draw_camera_response(o, 7, c);
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(r.gain[k], again.gain[k]);
      EXPECT_GE(r.gain[k], 0.75 * 0.94 - 1e-12);
      EXPECT_LE(r.gain[k], 1.25 * 1.06 + 1e-12);
      lo = std::min(lo, r.gain[k]);
      hi = std::max(hi, r.gain[k]);
    }
    EXPECT_GE(r.vignetting, 0.45);
    EXPECT_LE(r.vignetting, 0.65);
    EXPECT_NE(r.gain[0], draw_camera_response(o, 8, c).gain[0]);
  }
  EXPECT_GT(hi / lo, 1.05);  // the cameras differ
}

TEST(Photometric, ImagesCarryGainAndVignettingAndTheGroundTruthDoesNot) {
  PhotometricOptions o = PhotometricOptions::realistic();
  const SyntheticRig plain = rig_with({}), changed = rig_with(o);
  const SyntheticFrame a = plain.render(3, 64, 32), b = changed.render(3, 64, 32);
  EXPECT_TRUE(same(a.panorama.rgb, b.panorama.rgb));
  for (int c = 0; c < 4; ++c) {
    EXPECT_TRUE(same(a.cameras[c].inverse_distance, b.cameras[c].inverse_distance));
    const CameraResponse& r = changed.response(c);
    // At the centre the image is the scene times the gain (vignetting is ~1 there) ...
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(mean_ratio(a.cameras[c].rgb, b.cameras[c].rgb, k, 54, 54, 20), r.gain[k], 0.03);
    // ... and near the lens' edge it is darker by the vignetting on top.
    const double centre = mean_ratio(a.cameras[c].rgb, b.cameras[c].rgb, 1, 54, 54, 20);
    const double edge = mean_ratio(a.cameras[c].rgb, b.cameras[c].rgb, 1, 4, 54, 8);
    EXPECT_LT(edge / centre, 0.5 * (1 + r.vignetting)) << "camera " << c;
  }
}

TEST(Photometric, NoiseIsNewEveryFrameAndRepeatsWithTheSeed) {
  PhotometricOptions o;
  o.noise_sigma = 3;
  const SyntheticRig noisy = rig_with(o), plain = rig_with({});
  // The rig stands still between frames 0 and frames_per_loop: same scene, new noise.
  const int lap = noisy.options().frames_per_loop;
  const Rgb8Image f0 = std::move(noisy.render(0, 16, 8).cameras[0].rgb);
  const Rgb8Image f1 = std::move(noisy.render(lap, 16, 8).cameras[0].rgb);
  const Rgb8Image clean = std::move(plain.render(0, 16, 8).cameras[0].rgb);
  EXPECT_TRUE(same(f0, noisy.render(0, 16, 8).cameras[0].rgb));
  double sum = 0, sum2 = 0;
  long n = 0, differ = 0;
  for (int y = 32; y < 96; ++y) {
    for (int x = 32; x < 96; ++x) {
      const double d = double(f0(x, y, 1)) - clean(x, y, 1);
      sum += d;
      sum2 += d * d;
      ++n;
      differ += f0(x, y, 1) != f1(x, y, 1);
    }
  }
  EXPECT_NEAR(sum / n, 0.0, 0.3);
  EXPECT_NEAR(std::sqrt(sum2 / n), 3.0, 0.4);
  EXPECT_GT(differ, n / 2);
}

// A sensor rounds once, after its gain and noise: the 8-bit steps of a smooth ramp lie where the
// camera's own brightness crosses them, and noise dithers a level's fraction into the mean. (Gain
// on the rendered 8-bit values would keep the render's steps, the same in every camera.)
TEST(Photometric, TheSensorRoundsOnceAfterItsResponse) {
  PhotometricOptions o;
  o.gain_spread = 0.2;  // any(); the response is given below
  const SyntheticRig rig = rig_with(o);
  const RigCamera& camera = rig.rig().cameras[0];
  CameraResponse response;
  response.gain[0] = response.gain[1] = response.gain[2] = 0.8;
  RgbFloatImage ramp(camera.width, camera.height);
  for (int y = 0; y < camera.height; ++y)
    for (int x = 0; x < camera.width; ++x)
      for (int k = 0; k < 3; ++k) ramp(x, y, k) = float((40.0 + 0.37 * x) / 255.0);
  Rgb8Image image(camera.width, camera.height);
  apply_camera_response(o, response, camera, 1, ramp, &image);
  for (int x = 0; x < camera.width; ++x)
    ASSERT_EQ(image(x, 64, 1), std::lround(255.0 * ramp(x, 64, 1) * 0.8)) << "x " << x;

  o.noise_sigma = 1;
  const RgbFloatImage flat = RgbFloatImage::filled(camera.width, camera.height, 0.3f);
  apply_camera_response(o, response, camera, 1, flat, &image);
  double sum = 0;
  for (const std::uint8_t v : image.pixels()) sum += v;
  // 255 x 0.3 x 0.8 = 61.2; rounding the render first would give 77 x 0.8 = 61.6.
  EXPECT_NEAR(sum / double(image.pixels().size()), 61.2, 0.05);

  EXPECT_THROW(apply_camera_response(o, response, camera, 1, RgbFloatImage(4, 4), &image),
               std::invalid_argument);
}

TEST(Photometric, BadOptionsNameTheField) {
  PhotometricOptions o;
  o.vignetting_min = 0.8;
  o.vignetting_max = 0.5;
  try {
    o.check();
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("vignetting_max"), std::string::npos) << e.what();
  }
  o = {};
  o.gain_spread = -0.1;
  EXPECT_THROW(o.check(), std::invalid_argument);
  o = {};
  o.noise_sigma = std::nan("");
  EXPECT_THROW(o.check(), std::invalid_argument);
}

}  // namespace
}  // namespace omnisweep::synthetic
