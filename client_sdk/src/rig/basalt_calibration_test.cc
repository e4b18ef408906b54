#include "omnisweep/rig/basalt_calibration.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "tests/support/test_support.h"

namespace omnisweep {
namespace {

using nlohmann::json;
using testing::ScratchDir;

TEST(BasaltCalibration, ReadsTheKaistRig) {
  const Rig rig = read_basalt_calibration(testing::kaist_rig_dir() / "calibration.json");
  ASSERT_EQ(rig.num_cameras(), 4);
  const RigCamera& cam2 = rig.cameras[2];
  EXPECT_EQ(cam2.model.name(), "ds");
  EXPECT_EQ(cam2.width, 1216);
  EXPECT_EQ(cam2.height, 1216);
  EXPECT_DOUBLE_EQ(cam2.model.fx(), 451.02815256076249);
  EXPECT_DOUBLE_EQ(cam2.model.params()[5], 0.766170708696419);
  EXPECT_NEAR(cam2.rig_from_cam.translation.y(), -0.06905850417529966, 1e-15);
  EXPECT_NEAR(cam2.rig_from_cam.rotation.norm(), 1.0, 1e-12);
  // Camera 0 is the rig frame; cameras 2 and 3 look in roughly opposite directions.
  EXPECT_LT(rig.cameras[0].rig_from_cam.translation.norm(), 1e-12);
  const Eigen::Vector3d z2 = rig.cameras[2].rig_from_cam.rotation * Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d z3 = rig.cameras[3].rig_from_cam.rotation * Eigen::Vector3d::UnitZ();
  EXPECT_LT(z2.dot(z3), -0.95);
}

TEST(BasaltCalibration, WriteThenReadIsExact) {
  ScratchDir dir;
  Rig rig = read_basalt_calibration(testing::kaist_rig_dir() / "calibration.json");
  rig.cameras[1].model = KannalaBrandtCamera<double>(
      (KannalaBrandtCamera<double>::Params() << 300, 301, 600, 601, 0.01, -0.002, 0.0005, -1e-5)
          .finished());
  rig.cameras[3].model = ExtendedUnifiedCamera<double>({350, 351, 610, 612, 0.6, 1.1});
  write_basalt_calibration(rig, dir.path() / "calib.json");
  const Rig back = read_basalt_calibration(dir.path() / "calib.json");
  ASSERT_EQ(back.num_cameras(), rig.num_cameras());
  for (int c = 0; c < rig.num_cameras(); ++c) {
    EXPECT_EQ(back.cameras[c].model.name(), rig.cameras[c].model.name());
    EXPECT_EQ(back.cameras[c].model.params(), rig.cameras[c].model.params());
    EXPECT_EQ(back.cameras[c].width, rig.cameras[c].width);
    EXPECT_TRUE(back.cameras[c].rig_from_cam.translation ==
                rig.cameras[c].rig_from_cam.translation);
    EXPECT_TRUE(back.cameras[c].rig_from_cam.rotation.coeffs() ==
                rig.cameras[c].rig_from_cam.rotation.coeffs());
  }
}

// A valid calibration as JSON, for the error tests to break one field at a time.
json valid_json(int cameras) {
  Rig rig;
  for (int c = 0; c < cameras; ++c) {
    RigCamera cam;
    cam.model = DoubleSphereCamera<double>({300, 300, 511.5, 511.5, -0.2, 0.57});
    cam.width = cam.height = 1024;
    cam.rig_from_cam.translation = Eigen::Vector3d(0.05 * c, 0, 0);
    rig.cameras.push_back(cam);
  }
  return json::parse(to_basalt_json(rig));
}

TEST(BasaltCalibration, AnyNumberOfCamerasFromTwo) {
  for (int n : {2, 3, 6}) {
    EXPECT_EQ(parse_basalt_calibration(valid_json(n).dump(), "rig.json").num_cameras(), n);
  }
}

// Expects parsing `text` to throw a CalibrationError whose message holds every `parts`.
void expect_error(const std::string& text, std::vector<std::string> parts) {
  try {
    parse_basalt_calibration(text, "rig.json");
    FAIL() << "no error for " << text.substr(0, 200);
  } catch (const CalibrationError& e) {
    parts.insert(parts.begin(), "rig.json: ");
    for (const std::string& part : parts) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos)
          << "message '" << e.what() << "' lacks '" << part << "'";
    }
  }
}

TEST(BasaltCalibrationErrors, MissingFileNamesTheFile) {
  try {
    read_basalt_calibration("/nonexistent/calib.json");
    FAIL();
  } catch (const CalibrationError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/calib.json"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("does not exist"), std::string::npos);
  }
}

TEST(BasaltCalibrationErrors, MalformedJsonNamesLineAndField) {
  std::string text = valid_json(2).dump(2);
  text.insert(text.find("\"fx\"") + 6, "@");
  expect_error(text, {"value0.intrinsics[0].intrinsics.fx", "malformed JSON at line", "column"});
  expect_error("{\"value0\": ", {"malformed JSON"});
  expect_error("", {"malformed JSON at line 1"});
}

TEST(BasaltCalibrationErrors, UnknownCameraType) {
  json j = valid_json(2);
  j["value0"]["intrinsics"][1]["camera_type"] = "omni";
  expect_error(j.dump(),
               {"value0.intrinsics[1].camera_type", "unknown camera_type 'omni'", "ds, kb4"});
}

TEST(BasaltCalibrationErrors, ArrayLengthsDiffer) {
  json j = valid_json(3);
  j["value0"]["resolution"].erase(2);
  expect_error(j.dump(), {"value0", "T_imu_cam has 3", "resolution 2"});
  j = valid_json(3);
  j["value0"]["intrinsics"].erase(0);
  expect_error(j.dump(), {"intrinsics 2"});
}

TEST(BasaltCalibrationErrors, NonFiniteNumbers) {
  std::string text = valid_json(2).dump();
  const auto pos = text.find("\"xi\":") + 5;
  const auto end = text.find_first_of(",}", pos);
  expect_error(text.substr(0, pos) + "1e999" + text.substr(end),
               {"value0.intrinsics[0].intrinsics.xi", "number overflow"});
  expect_error(text.substr(0, pos) + "NaN" + text.substr(end),
               {"value0.intrinsics[0].intrinsics.xi", "malformed JSON"});
  text = valid_json(2).dump();
  const auto ppos = text.find("\"px\":") + 5;
  expect_error(text.substr(0, ppos) + "-Infinity" + text.substr(text.find_first_of(",}", ppos)),
               {"value0.T_imu_cam[0].px"});
}

TEST(BasaltCalibrationErrors, FocalLengthsMustBePositive) {
  json j = valid_json(2);
  j["value0"]["intrinsics"][1]["intrinsics"]["fx"] = 0.0;
  expect_error(j.dump(), {"value0.intrinsics[1].intrinsics.fx", "= 0 must be > 0"});
  j = valid_json(2);
  j["value0"]["intrinsics"][0]["intrinsics"]["fy"] = -12.5;
  expect_error(j.dump(), {"value0.intrinsics[0].intrinsics.fy", "= -12.5 must be > 0"});
}

TEST(BasaltCalibrationErrors, AlphaOutsideUnitInterval) {
  for (double alpha : {-0.01, 1.2}) {
    json j = valid_json(2);
    j["value0"]["intrinsics"][1]["intrinsics"]["alpha"] = alpha;
    expect_error(j.dump(), {"value0.intrinsics[1].intrinsics.alpha", "must be within [0, 1]"});
  }
}

TEST(BasaltCalibrationErrors, QuaternionNormFarFromOne) {
  json j = valid_json(2);
  j["value0"]["T_imu_cam"][1]["qw"] = 0.5;
  expect_error(j.dump(), {"value0.T_imu_cam[1]", "quaternion", "norm 0.5"});
  // Within the tolerance the quaternion is accepted and normalised.
  j["value0"]["T_imu_cam"][1]["qw"] = 1.0004;
  const Rig rig = parse_basalt_calibration(j.dump(), "rig.json");
  EXPECT_NEAR(rig.cameras[1].rig_from_cam.rotation.norm(), 1.0, 1e-15);
}

TEST(BasaltCalibrationErrors, MissingFieldsWrongTypesAndTooFewCameras) {
  json j = valid_json(2);
  j["value0"]["intrinsics"][0]["intrinsics"].erase("cy");
  expect_error(j.dump(), {"value0.intrinsics[0].intrinsics.cy", "missing"});
  j = valid_json(2);
  j["value0"]["T_imu_cam"][0]["pz"] = "zero";
  expect_error(j.dump(), {"value0.T_imu_cam[0].pz", "expected a number, got string"});
  j = valid_json(2);
  j["value0"]["resolution"][1] = {1024, -3};
  expect_error(j.dump(), {"value0.resolution[1][1]", "positive integer"});
  expect_error(valid_json(1).dump(), {"value0.T_imu_cam", "at least 2 cameras, found 1"});
  expect_error("[1, 2]", {"expected an object"});
  expect_error("{}", {"value0: missing"});
}

}  // namespace
}  // namespace omnisweep
