// Property tests of the camera models: round trips over every valid pixel of the real rig and
// over random valid parameters, validity reporting without NaN, FOV and rescaling.
#include "omnisweep/camera/camera_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <numbers>
#include <random>

#include "omnisweep/rig/basalt_calibration.h"
#include "tests/support/test_support.h"

namespace omnisweep {
namespace {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;

struct RoundTripStats {
  long valid = 0;
  long invalid = 0;
  double max_error = 0;
};

// Unprojects every pixel centre (u, v) of a width x height grid (step `step`), projects the
// ray back and records the largest pixel error. Invalid pixels must leave the ray untouched.
template <typename Scalar>
RoundTripStats round_trip(const CameraModel<Scalar>& cam, int width, int height, int step = 1) {
  using V2 = Eigen::Matrix<Scalar, 2, 1>;
  using V3 = Eigen::Matrix<Scalar, 3, 1>;
  RoundTripStats stats;
  for (int v = 0; v < height; v += step) {
    for (int u = 0; u < width; u += step) {
      const V2 uv(u, v);
      V3 ray(7, 7, 7);
      if (!cam.unproject(uv, &ray)) {
        EXPECT_EQ(ray, V3(7, 7, 7)) << "invalid pixel wrote its ray";
        ++stats.invalid;
        continue;
      }
      EXPECT_TRUE(ray.allFinite());
      EXPECT_NEAR(double(ray.norm()), 1.0, 1e-5);
      V2 back;
      const bool ok = cam.project(ray, &back);
      EXPECT_TRUE(ok) << "pixel (" << u << ", " << v << ") unprojects but does not project";
      if (!ok) continue;
      stats.max_error = std::max(stats.max_error, double((back - uv).norm()));
      ++stats.valid;
    }
  }
  return stats;
}

TEST(CameraModel, KaistRigRoundTripEveryPixelDouble) {
  const Rig rig = read_basalt_calibration(testing::kaist_rig_dir() / "calibration.json");
  ASSERT_EQ(rig.num_cameras(), 4);
  for (int c = 0; c < 4; ++c) {
    const RigCamera& cam = rig.cameras[c];
    const RoundTripStats stats = round_trip(cam.model, cam.width, cam.height);
    std::cout << "camera " << c << ": " << stats.valid << " valid pixels, " << stats.invalid
              << " invalid, max round-trip error " << stats.max_error << " px\n";
    EXPECT_LT(stats.max_error, 1e-4) << "camera " << c;
    // A 220-degree lens fills most of its square image.
    EXPECT_GT(stats.valid, long(cam.width) * cam.height / 2) << "camera " << c;
  }
}

TEST(CameraModel, KaistRigRoundTripFloat) {
  const Rig rig = read_basalt_calibration(testing::kaist_rig_dir() / "calibration.json");
  for (const RigCamera& cam : rig.cameras) {
    const RoundTripStats stats = round_trip(cam.model.cast<float>(), cam.width, cam.height, 3);
    std::cout << "float: max round-trip error " << stats.max_error << " px\n";
    EXPECT_LT(stats.max_error, 5e-3);
    EXPECT_GT(stats.valid, 0);
  }
}

TEST(CameraModel, KaistRigFieldOfView) {
  const Rig rig = read_basalt_calibration(testing::kaist_rig_dir() / "calibration.json");
  for (const RigCamera& cam : rig.cameras) {
    const double fov_deg = cam.model.field_of_view() * 180.0 / std::numbers::pi;
    EXPECT_GT(fov_deg, 200.0);
    EXPECT_LT(fov_deg, 360.0);
    // Rays just inside the limit project, rays just outside do not.
    const double t = cam.model.max_angle();
    Vec2 uv;
    EXPECT_TRUE(cam.model.project(Vec3(std::sin(t - 1e-6), 0, std::cos(t - 1e-6)), &uv));
    EXPECT_FALSE(cam.model.project(Vec3(std::sin(t + 1e-6), 0, std::cos(t + 1e-6)), &uv));
    EXPECT_TRUE(uv.allFinite());
  }
}

// Random valid parameters per model (seeded), with the first four in a 1024 x 1024 image.
CameraModel<double> random_camera(std::string_view name, std::mt19937_64& rng) {
  auto uni = [&](double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
  };
  std::vector<double> p = {uni(150, 600), uni(150, 600), uni(400, 624), uni(400, 624)};
  if (name == "ds") {
    p.insert(p.end(), {uni(-0.6, 0.9), uni(0.05, 0.95)});
  } else if (name == "kb4") {
    p.insert(p.end(), {uni(-0.05, 0.05), uni(-0.01, 0.01), uni(-0.005, 0.005), uni(-0.001, 0.001)});
  } else if (name == "eucm") {
    p.insert(p.end(), {uni(0.05, 0.95), uni(0.5, 2.0)});
  }
  return CameraModel<double>::from_params(name, p);
}

class RandomCameraTest : public ::testing::TestWithParam<std::string> {};

TEST_P(RandomCameraTest, RoundTripOverValidPixels) {
  std::mt19937_64 rng(1234);
  double worst = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const CameraModel<double> cam = random_camera(GetParam(), rng);
    ASSERT_FALSE(cam.check().has_value());
    const RoundTripStats stats = round_trip(cam, 1024, 1024, 9);
    EXPECT_GT(stats.valid, 0);
    worst = std::max(worst, stats.max_error);
  }
  std::cout << GetParam() << ": max round-trip error over random cameras " << worst << " px\n";
  EXPECT_LT(worst, 1e-4);
}

TEST_P(RandomCameraTest, PointsRoundTripAndInvalidPointsStayFinite) {
  std::mt19937_64 rng(99);
  std::normal_distribution<double> normal(0, 1);
  for (int trial = 0; trial < 20; ++trial) {
    const CameraModel<double> cam = random_camera(GetParam(), rng);
    int valid = 0;
    for (int i = 0; i < 2000; ++i) {
      const Vec3 p = Vec3(normal(rng), normal(rng), normal(rng)) * 3.0;
      Vec2 uv;
      const bool ok = cam.project(p, &uv);
      ASSERT_TRUE(uv.allFinite()) << "project wrote NaN for " << p.transpose();
      const double angle = std::acos(std::clamp(p.normalized().z(), -1.0, 1.0));
      if (angle < cam.max_angle() - 1e-9) {
        EXPECT_TRUE(ok) << p.transpose();
      }
      if (angle > cam.max_angle() + 1e-9) {
        EXPECT_FALSE(ok) << p.transpose();
      }
      if (!ok) continue;
      Vec3 ray;
      if (!cam.unproject(uv, &ray)) continue;  // beyond the lens' unprojection domain
      ++valid;
      EXPECT_LT((ray - p.normalized()).norm(), 1e-7) << p.transpose();
    }
    EXPECT_GT(valid, 500);
    // The origin and non-finite points are invalid and never produce NaN.
    for (const Vec3& bad : {Vec3(0, 0, 0), Vec3(NAN, 0, 1), Vec3(INFINITY, 0, 1)}) {
      Vec2 uv;
      EXPECT_FALSE(cam.project(bad, &uv));
      EXPECT_TRUE(uv.allFinite());
    }
    Vec3 ray(7, 7, 7);
    EXPECT_FALSE(cam.unproject(Vec2(NAN, 3), &ray));
    EXPECT_EQ(ray, Vec3(7, 7, 7));
  }
}

TEST_P(RandomCameraTest, RescalingFollowsThePixelCentreConvention) {
  std::mt19937_64 rng(7);
  const CameraModel<double> cam = random_camera(GetParam(), rng);
  const double sx = 1024.0 / 1216.0, sy = 0.5;
  const CameraModel<double> small = cam.scaled(sx, sy);
  for (const Vec3& p : {Vec3(0.3, -0.2, 1), Vec3(-0.6, 0.5, 0.7), Vec3(0.1, 0.1, 3)}) {
    Vec2 a, b;
    ASSERT_TRUE(cam.project(p, &a));
    ASSERT_TRUE(small.project(p, &b));
    EXPECT_NEAR(b.x(), (a.x() + 0.5) * sx - 0.5, 1e-9);
    EXPECT_NEAR(b.y(), (a.y() + 0.5) * sy - 0.5, 1e-9);
  }
}

INSTANTIATE_TEST_SUITE_P(Models, RandomCameraTest,
                         ::testing::Values("ds", "kb4", "eucm", "pinhole"));

TEST(CameraModel, DoubleSphereDefinitionFromAlgorithmMd) {
  // Project by the formula written out in ALGORITHM.md §2 and compare.
  const double fx = 300, fy = 310, cx = 500, cy = 520, xi = -0.2, alpha = 0.6;
  const CameraModel<double> cam = DoubleSphereCamera<double>({fx, fy, cx, cy, xi, alpha});
  const Vec3 p(0.4, -0.7, 0.9);
  const double d1 = p.norm(), c = xi * d1 + p.z();
  const double d2 = std::sqrt(p.x() * p.x() + p.y() * p.y() + c * c);
  const double den = alpha * d2 + (1 - alpha) * c;
  Vec2 uv;
  ASSERT_TRUE(cam.project(p, &uv));
  EXPECT_NEAR(uv.x(), fx * p.x() / den + cx, 1e-12);
  EXPECT_NEAR(uv.y(), fy * p.y() / den + cy, 1e-12);
  EXPECT_EQ(cam.name(), "ds");
}

TEST(CameraModel, FactoryRejectsUnknownNamesAndWrongCounts) {
  const std::vector<double> six = {1, 1, 0, 0, 0, 0.5};
  EXPECT_THROW(CameraModel<double>::from_params("fisheye99", six), std::invalid_argument);
  EXPECT_THROW(CameraModel<double>::from_params("kb4", six), std::invalid_argument);
  EXPECT_EQ(CameraModel<double>::from_params("eucm", six).name(), "eucm");
  EXPECT_EQ(CameraModel<double>::known_names(), "ds, kb4, eucm, pinhole");
}

}  // namespace
}  // namespace omnisweep
