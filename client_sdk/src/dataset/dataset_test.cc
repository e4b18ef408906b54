#include "omnisweep/dataset/dataset.h"

#include <gtest/gtest.h>

#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "omnisweep/image/image_io.h"
#include "omnisweep/rig/basalt_calibration.h"
#include "tests/support/test_support.h"

namespace omnisweep {
namespace {

namespace fs = std::filesystem;
using testing::ScratchDir;

Rig small_rig() {
  Rig rig;
  for (int c = 0; c < 2; ++c) {
    RigCamera cam;
    cam.model = DoubleSphereCamera<double>({20, 20, 31.5, 23.5, -0.2, 0.57});
    cam.width = 64;
    cam.height = 48;
    rig.cameras.push_back(cam);
  }
  return rig;
}

std::vector<Rgb8Image> images(std::uint8_t value) {
  std::vector<Rgb8Image> out;
  out.push_back(Rgb8Image::filled(64, 48, value));
  out.push_back(Rgb8Image::filled(64, 48, value));
  return out;
}

TEST(Dataset, ListsFramesInNaturalOrderAndSkipsBrokenOnes) {
  ScratchDir dir;
  DatasetWriter writer(dir.path(), small_rig());
  for (const char* name : {"0", "1", "2", "10", "x"}) writer.write_images(name, images(10));
  fs::remove(dir.path() / "cam1" / "1.png");                                  // missing
  write_png(dir.path() / "cam0" / "2.png", Rgb8Image(32, 48));                // wrong size
  std::ofstream(dir.path() / "cam1" / "x.png", std::ios::trunc) << "broken";  // unreadable
  std::ofstream(dir.path() / "cam0" / "notes.txt") << "not an image";

  const Dataset ds = Dataset::open(dir.path());
  EXPECT_EQ(ds.frames(), (std::vector<std::string>{"0", "1", "2", "10", "x"}));
  std::vector<std::string> loaded;
  const auto skipped = ds.for_each_frame({}, [&](Frame&& f) {
    EXPECT_EQ(f.images.size(), 2u);
    EXPECT_EQ(std::get<Rgb8Image>(f.images[1])(5, 5, 2), 10);
    loaded.push_back(f.name);
  });
  EXPECT_EQ(loaded, (std::vector<std::string>{"0", "10"}));
  ASSERT_EQ(skipped.size(), 3u);
  EXPECT_EQ(skipped[0].name, "1");
  EXPECT_NE(skipped[0].reason.find("cam1/1.*: image is missing"), std::string::npos)
      << skipped[0].reason;
  EXPECT_EQ(skipped[1].name, "2");
  EXPECT_NE(skipped[1].reason.find("cam0/2.png: image is 32x48, calibration says 64x48"),
            std::string::npos)
      << skipped[1].reason;
  EXPECT_EQ(skipped[2].name, "x");
  EXPECT_NE(skipped[2].reason.find("cam1/x.png: cannot decode"), std::string::npos)
      << skipped[2].reason;
  EXPECT_THROW(ds.load_frame("1"), DatasetError);
}

TEST(Dataset, LoadsDeepImagesMasksAndGroundTruth) {
  ScratchDir dir;
  DatasetWriter writer(dir.path(), small_rig());
  Gray8Image mask = Gray8Image::filled(64, 48, 255);
  mask(0, 0) = 0;
  writer.write_mask(1, mask);
  writer.write_images("a", images(3));
  cv::imwrite((dir.path() / "cam0" / "b.png").string(),
              cv::Mat(48, 64, CV_16UC3, cv::Scalar(1, 2, 3)));
  cv::imwrite((dir.path() / "cam1" / "b.tiff").string(),
              cv::Mat(48, 64, CV_32FC3, cv::Scalar(0.1f, 0.2f, 0.3f)),
              {cv::IMWRITE_TIFF_COMPRESSION, 1});  // uncompressed: exact floats
  FloatImage inv = FloatImage::filled(32, 16, 0.25f);
  writer.write_ground_truth("a", Rgb8Image::filled(32, 16, 80), inv);
  writer.write_camera_ground_truth("a", 1, FloatImage::filled(64, 48, 0.5f));

  const Dataset ds = Dataset::open(dir.path());
  ASSERT_EQ(ds.masks().size(), 2u);
  EXPECT_FALSE(ds.masks()[0].has_value());
  ASSERT_TRUE(ds.masks()[1].has_value());
  EXPECT_EQ((*ds.masks()[1])(0, 0), 0);
  EXPECT_TRUE(ds.has_ground_truth());

  const Frame a = ds.load_frame("a");
  ASSERT_TRUE(a.ground_truth.has_value());
  EXPECT_EQ(a.ground_truth->inverse_distance(3, 3), 0.25f);
  EXPECT_EQ(a.ground_truth->rgb(3, 3, 1), 80);
  EXPECT_FALSE(a.ground_truth->camera_inverse_distance[0].has_value());
  EXPECT_EQ((*a.ground_truth->camera_inverse_distance[1])(1, 1), 0.5f);

  const Frame b = ds.load_frame("b");
  EXPECT_FALSE(b.ground_truth.has_value());
  EXPECT_EQ(std::get<Rgb16Image>(b.images[0])(0, 0, 0), 3);  // R from BGR (1, 2, 3)
  EXPECT_FLOAT_EQ(std::get<RgbFloatImage>(b.images[1])(0, 0, 0), 0.3f);
}

TEST(Dataset, BadFolderCalibrationOrMaskIsAnError) {
  EXPECT_THROW(Dataset::open("/nonexistent/dataset"), DatasetError);
  ScratchDir dir;
  EXPECT_THROW(Dataset::open(dir.path()), CalibrationError);
  DatasetWriter writer(dir.path(), small_rig());
  write_png(dir.path() / "cam0" / "mask.png", Gray8Image(10, 10));
  try {
    Dataset::open(dir.path());
    FAIL();
  } catch (const DatasetError& e) {
    EXPECT_NE(std::string(e.what()).find("cam0/mask.png: mask is 10x10"), std::string::npos)
        << e.what();
  }
  fs::remove(dir.path() / "cam0" / "mask.png");
  fs::remove_all(dir.path() / "cam1");
  EXPECT_THROW(Dataset::open(dir.path()), DatasetError);
}

TEST(Dataset, DatasetJsonGivesTheHintsAndBadFieldsAreNamed) {
  ScratchDir dir;
  DatasetWriter writer(dir.path(), small_rig());
  EXPECT_TRUE(Dataset::open(dir.path()).hints().references.empty());  // no dataset.json
  writer.write_hints({.references = {1, 0},
                      .viewpoint = Eigen::Vector3d(0.1, -0.2, 0.3),
                      .min_distance = 0.5,
                      .max_distance = 50.0});
  const DatasetHints hints = Dataset::open(dir.path()).hints();
  EXPECT_EQ(hints.references, (std::vector<int>{1, 0}));
  ASSERT_TRUE(hints.viewpoint.has_value());
  EXPECT_DOUBLE_EQ(hints.viewpoint->y(), -0.2);
  EXPECT_EQ(hints.min_distance, 0.5);
  EXPECT_EQ(hints.max_distance, 50.0);
  auto error_for = [&](const std::string& text) {
    std::ofstream(dir.path() / "dataset.json") << text;
    return omnisweep::testing::error_message<DatasetError>([&] { Dataset::open(dir.path()); });
  };
  EXPECT_NE(error_for("{\"references\": [0, 9]}").find("\"references\""), std::string::npos);
  EXPECT_NE(error_for("{\"viewpoint\": [0, 1]}").find("\"viewpoint\""), std::string::npos);
  EXPECT_NE(error_for("{\"min_dist\": -1}").find("\"min_dist\""), std::string::npos);
  EXPECT_NE(error_for("{\"min_dist\": 2, \"max_dist\": 1}").find("\"max_dist\""),
            std::string::npos);
  EXPECT_NE(error_for("[1,").find("dataset.json: not JSON"), std::string::npos);
}

TEST(Dataset, KaistRigLoads) {
  const Dataset ds = Dataset::open(testing::kaist_rig_dir());
  EXPECT_EQ(ds.rig().num_cameras(), 4);
  EXPECT_EQ(ds.frames(), std::vector<std::string>{"0"});
  EXPECT_FALSE(ds.has_ground_truth());
  for (const auto& mask : ds.masks()) {
    ASSERT_TRUE(mask.has_value());
    EXPECT_EQ(mask->width(), 1216);
  }
  const Frame frame = ds.load_frame("0");
  ASSERT_EQ(frame.images.size(), 4u);
  for (const AnyImage& im : frame.images) {
    EXPECT_STREQ(depth_name(im), "8-bit");
    EXPECT_EQ(width_of(im), 1216);
    EXPECT_EQ(height_of(im), 1216);
  }
  EXPECT_FALSE(frame.ground_truth.has_value());
}

TEST(Dataset, NaturalOrder) {
  EXPECT_TRUE(natural_less("2", "10"));
  EXPECT_TRUE(natural_less("frame_9", "frame_10"));
  EXPECT_FALSE(natural_less("10", "10"));
  EXPECT_TRUE(natural_less("007", "8"));
  EXPECT_TRUE(natural_less("a", "b"));
}

}  // namespace
}  // namespace omnisweep
