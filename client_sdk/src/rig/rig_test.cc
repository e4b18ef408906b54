#include "omnisweep/rig/rig.h"

#include <gtest/gtest.h>

namespace omnisweep {
namespace {

Rig two_camera_rig() {
  Rig rig;
  for (int c = 0; c < 2; ++c) {
    RigCamera cam;
    cam.model = DoubleSphereCamera<double>({400, 400, 607.5, 607.5, -0.25, 0.57});
    cam.width = cam.height = 1216;
    rig.cameras.push_back(cam);
  }
  // Camera 1 looks backwards (180 degrees about y), 6 cm behind camera 0.
  rig.cameras[1].rig_from_cam =
      Rigid3d(Eigen::Quaterniond(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitY())),
              Eigen::Vector3d(0, 0, -0.06));
  return rig;
}

TEST(Rig, CamFromCamFollowsAlgorithmMd) {
  const Rig rig = two_camera_rig();
  // A point 1 m in front of camera 0 is 1.06 m behind camera 1.
  const Eigen::Vector3d x_in_1 = rig.cam_from_cam(1, 0) * Eigen::Vector3d(0, 0, 1);
  EXPECT_TRUE(x_in_1.isApprox(Eigen::Vector3d(0, 0, -1.06), 1e-12)) << x_in_1.transpose();
  const Rigid3d identity = rig.cam_from_cam(1, 1);
  EXPECT_LT(identity.translation.norm(), 1e-15);
  EXPECT_NEAR(std::abs(identity.rotation.w()), 1.0, 1e-15);
}

TEST(Rig, ResizedScalesIntrinsicsWithPixelCentres) {
  const Rig small = two_camera_rig().resized(1024, 1024);
  const double s = 1024.0 / 1216.0;
  EXPECT_EQ(small.cameras[0].width, 1024);
  EXPECT_DOUBLE_EQ(small.cameras[0].model.fx(), 400 * s);
  EXPECT_DOUBLE_EQ(small.cameras[0].model.cx(), (607.5 + 0.5) * s - 0.5);
  EXPECT_DOUBLE_EQ(small.cameras[0].model.params()[4], -0.25);
}

TEST(Rig, CheckNamesTheProblem) {
  Rig rig = two_camera_rig();
  EXPECT_NO_THROW(rig.check());
  rig.cameras[1].model = DoubleSphereCamera<double>({400, 400, 607.5, 607.5, -0.25, 1.5});
  try {
    rig.check();
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "camera 1: alpha must be within [0, 1]");
  }
  rig.cameras.pop_back();
  EXPECT_THROW(rig.check(), std::invalid_argument);
}

}  // namespace
}  // namespace omnisweep
