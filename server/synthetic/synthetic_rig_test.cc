// The synthetic rig's images and ground truth must agree with each other, be deterministic,
// and cover what the depth tests need: 0.6-20 m, plain and textured areas, thin structures.
#include "server/synthetic/synthetic_rig.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <numeric>

#include "omnisweep/dataset/dataset.h"
#include "omnisweep/geometry/equirectangular.h"
#include "server/synthetic/synthetic_dataset.h"
#include "tests/support/test_support.h"

namespace omnisweep::synthetic {
namespace {

// Half the default resolution keeps the suite fast; the geometry is the same.
SyntheticRig small_rig(std::uint64_t seed = 1) {
  SyntheticRigOptions options;
  options.seed = seed;
  options.image_size = 608;
  return SyntheticRig(options);
}

float bilinear(const Rgb8Image& im, double u, double v, int c) {
  const int x0 = int(std::floor(u)), y0 = int(std::floor(v));
  const double fx = u - x0, fy = v - y0;
  auto at = [&](int x, int y) {
    return double(im(std::clamp(x, 0, im.width() - 1), std::clamp(y, 0, im.height() - 1), c));
  };
  return float((1 - fy) * ((1 - fx) * at(x0, y0) + fx * at(x0 + 1, y0)) +
               fy * ((1 - fx) * at(x0, y0 + 1) + fx * at(x0 + 1, y0 + 1)));
}

double percentile(std::vector<float> v, double q) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[std::size_t(q * (v.size() - 1))];
}

TEST(SyntheticRig, GroundTruthPanoramaAgreesWithEveryCamera) {
  const SyntheticRig rig = small_rig();
  const SyntheticFrame frame = rig.render(0, 1024, 512);
  const std::vector<Gray8Image> masks = rig.masks();
  const Eigen::Vector3d viewpoint = rig.viewpoint();
  const int w = frame.panorama.rgb.width(), h = frame.panorama.rgb.height();
  for (int c = 0; c < rig.rig().num_cameras(); ++c) {
    const RigCamera& cam = rig.rig().cameras[c];
    const Rigid3d cam_from_rig = cam.rig_from_cam.inverse();
    long inside = 0, same_surface = 0;
    std::vector<float> color_error;
    for (int y = 0; y < h; y += 2) {
      for (int x = 0; x < w; x += 2) {
        const float inv = frame.panorama.inverse_distance(x, y);
        ASSERT_GT(inv, 0.0f);
        // Back-project the panorama pixel and project it into camera c.
        const Eigen::Vector3d x_in_rig = viewpoint + equirect_direction<double>(x, y, w, h) / inv;
        const Eigen::Vector3d x_in_cam = cam_from_rig * x_in_rig;
        Eigen::Vector2d uv;
        if (!cam.model.project(x_in_cam, &uv)) continue;
        const int u = int(std::lround(uv.x())), v = int(std::lround(uv.y()));
        if (!masks[c].contains(u, v) || masks[c](u, v) == 0) continue;
        ++inside;
        // Visible from c: the camera's own ground truth sees the same surface there.
        const float cam_inv = frame.cameras[c].inverse_distance(u, v);
        if (std::abs(1.0 / cam_inv - x_in_cam.norm()) > 0.02 * x_in_cam.norm()) continue;
        ++same_surface;
        float err = 0;
        for (int k = 0; k < 3; ++k)
          err += std::abs(bilinear(frame.cameras[c].rgb, uv.x(), uv.y(), k) -
                          frame.panorama.rgb(x, y, k));
        color_error.push_back(err / 3);
      }
    }
    const double visible = double(same_surface) / double(inside);
    const double median = percentile(color_error, 0.5), p90 = percentile(color_error, 0.9);
    std::cout << "camera " << c << ": " << inside << " panorama points inside the lens, "
              << 100 * visible << " % on the same surface; colour error median " << median
              << ", 90th percentile " << p90 << " levels\n";
    // Occlusion between the viewpoint and a camera a few cm away hides only a few percent.
    EXPECT_GT(visible, 0.95);
    EXPECT_LT(median, 2.0);
    EXPECT_LT(p90, 6.0);
  }
}

TEST(SyntheticRig, DistancesSpanTheRequiredRange) {
  const SyntheticRig rig = small_rig();
  for (int index : {0, 75, 150, 225}) {
    const RenderedImage pano = rig.render_panorama_at(index, rig.viewpoint(), 512, 256);
    const auto [lo, hi] = std::minmax_element(pano.inverse_distance.pixels().begin(),
                                              pano.inverse_distance.pixels().end());
    const double nearest = 1.0 / *hi, farthest = 1.0 / *lo;
    std::cout << "frame " << index << ": distances " << nearest << " .. " << farthest << " m\n";
    EXPECT_GE(nearest, 0.6);
    EXPECT_LE(farthest, 20.0);
    if (index == 0) {
      EXPECT_LT(nearest, 0.8);  // the deliberate near sphere
      EXPECT_GT(farthest, 8.0);
    }
  }
}

TEST(SyntheticRig, SceneHasPlainAndTexturedAreasAndThinPoles) {
  const SyntheticRig rig = small_rig();
  EXPECT_GE(rig.scene().boxes().size(), 4u);
  EXPECT_GE(rig.scene().spheres().size(), 3u);
  EXPECT_GE(rig.scene().poles().size(), 3u);
  for (const Pole& p : rig.scene().poles()) EXPECT_LE(p.radius, 0.06f);
  const RenderedImage pano = rig.render_panorama_at(0, rig.viewpoint(), 1024, 512);
  // Local contrast in 5x5 windows of the green channel.
  long plain = 0, textured = 0, total = 0;
  for (int y = 2; y < 510; y += 3) {
    for (int x = 2; x < 1022; x += 3) {
      int lo = 255, hi = 0;
      for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx) {
          lo = std::min<int>(lo, pano.rgb(x + dx, y + dy, 1));
          hi = std::max<int>(hi, pano.rgb(x + dx, y + dy, 1));
        }
      plain += hi - lo <= 2;
      textured += hi - lo >= 12;
      ++total;
    }
  }
  std::cout << "plain " << 100.0 * plain / total << " %, textured " << 100.0 * textured / total
            << " %\n";
  EXPECT_GT(double(plain) / total, 0.10);
  EXPECT_GT(double(textured) / total, 0.25);
}

TEST(SyntheticRig, DeterministicForASeed) {
  auto checksum = [](const Rgb8Image& im) {
    return std::accumulate(
        im.pixels().begin(), im.pixels().end(), std::uint64_t(0),
        [](std::uint64_t h, std::uint8_t v) { return h * 1099511628211ull ^ v; });
  };
  const SyntheticRig a = small_rig(5), b = small_rig(5), c = small_rig(6);
  const Rgb8Image ia = render_camera(a.scene(), a.rig().cameras[2], a.world_from_rig(3), 1.9).rgb;
  const Rgb8Image ib = render_camera(b.scene(), b.rig().cameras[2], b.world_from_rig(3), 1.9).rgb;
  const Rgb8Image ic = render_camera(c.scene(), c.rig().cameras[2], c.world_from_rig(3), 1.9).rgb;
  EXPECT_EQ(checksum(ia), checksum(ib));
  EXPECT_NE(checksum(ia), checksum(ic));
}

TEST(SyntheticRig, RigMovesAlongAClosedLoop) {
  const SyntheticRig rig = small_rig();
  EXPECT_LT(rig.world_from_rig(0).translation.norm(), 1e-12);
  EXPECT_GT((rig.world_from_rig(75).translation - rig.world_from_rig(0).translation).norm(), 0.5);
  EXPECT_LT((rig.world_from_rig(300).translation - rig.world_from_rig(0).translation).norm(), 1e-9);
  // The default rig: 4 cameras, references 2 and 3 face opposite ways.
  const Rig& r = rig.rig();
  ASSERT_EQ(r.num_cameras(), 4);
  const Eigen::Vector3d z2 = r.cameras[2].rig_from_cam.rotation * Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d z3 = r.cameras[3].rig_from_cam.rotation * Eigen::Vector3d::UnitZ();
  EXPECT_LT(z2.dot(z3), -0.99);
  EXPECT_NEAR(r.cameras[0].model.field_of_view() * 180 / M_PI, 2 * 121.0, 3.0);
}

TEST(SyntheticRig, WritesADatasetInTheReferenceLayout) {
  testing::ScratchDir dir;
  SyntheticRigOptions options;
  options.image_size = 96;
  const SyntheticRig rig(options);
  write_synthetic_dataset(
      rig, dir.path(),
      {.first_frame = 4, .num_frames = 2, .panorama_width = 64, .panorama_height = 32});
  const Dataset ds = Dataset::open(dir.path());
  EXPECT_EQ(ds.frames(), (std::vector<std::string>{"4", "5"}));
  ASSERT_EQ(ds.masks().size(), 4u);
  EXPECT_EQ((*ds.masks()[0])(48, 48), 255);
  EXPECT_EQ((*ds.masks()[0])(0, 0), 0);  // outside the lens circle
  const Frame frame = ds.load_frame("5");
  ASSERT_TRUE(frame.ground_truth.has_value());
  EXPECT_EQ(frame.ground_truth->inverse_distance.width(), 64);
  ASSERT_TRUE(frame.ground_truth->camera_inverse_distance[3].has_value());
  EXPECT_GT((*frame.ground_truth->camera_inverse_distance[3])(48, 48), 0.05f);
  EXPECT_EQ(width_of(frame.images[1]), 96);
}

TEST(SyntheticRig, RejectsBadOptions) {
  SyntheticRigOptions options;
  options.references = {2, 7};
  EXPECT_THROW(SyntheticRig{options}, std::invalid_argument);
  options.references = {2, 3};
  options.image_size = 4;
  EXPECT_THROW(SyntheticRig{options}, std::invalid_argument);
}

}  // namespace
}  // namespace omnisweep::synthetic
