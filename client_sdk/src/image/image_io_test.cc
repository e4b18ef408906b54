#include "omnisweep/image/image_io.h"

#include <gtest/gtest.h>

#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "tests/support/test_support.h"

namespace omnisweep {
namespace {

using testing::ScratchDir;

TEST(ImageIo, PngKeepsRgbOrder) {
  ScratchDir dir;
  Rgb8Image im(5, 4);
  im(1, 2, 0) = 200;  // red
  im(3, 0, 2) = 77;   // blue
  write_png(dir.path() / "a.png", im);
  // OpenCV sees BGR: red lands in its third channel.
  const cv::Mat raw = cv::imread((dir.path() / "a.png").string(), cv::IMREAD_UNCHANGED);
  EXPECT_EQ(raw.at<cv::Vec3b>(2, 1)[2], 200);
  const AnyImage back = read_color_image(dir.path() / "a.png");
  ASSERT_EQ(back.index(), 0u);
  const auto& u8 = std::get<Rgb8Image>(back);
  EXPECT_EQ(u8(1, 2, 0), 200);
  EXPECT_EQ(u8(3, 0, 2), 77);
  EXPECT_EQ(u8(3, 0, 0), 0);
}

TEST(ImageIo, ReadsSixteenBitAndFloatAndGray) {
  ScratchDir dir;
  cv::Mat bgr16(3, 4, CV_16UC3, cv::Scalar(0, 0, 0));
  bgr16.at<cv::Vec3w>(1, 2) = cv::Vec3w(10, 20, 65535);  // B, G, R
  cv::imwrite((dir.path() / "deep.png").string(), bgr16);
  const AnyImage deep = read_color_image(dir.path() / "deep.png");
  ASSERT_EQ(deep.index(), 1u);
  EXPECT_EQ(std::get<Rgb16Image>(deep)(2, 1, 0), 65535);
  EXPECT_EQ(std::get<Rgb16Image>(deep)(2, 1, 2), 10);

  cv::Mat f32(2, 2, CV_32FC3, cv::Scalar(0.25f, 0.5f, 0.75f));
  cv::imwrite((dir.path() / "f.tiff").string(), f32, {cv::IMWRITE_TIFF_COMPRESSION, 1});
  const AnyImage fl = read_color_image(dir.path() / "f.tiff");
  ASSERT_EQ(fl.index(), 2u);
  EXPECT_FLOAT_EQ(std::get<RgbFloatImage>(fl)(0, 0, 0), 0.75f);

  cv::Mat gray(2, 3, CV_8UC1, cv::Scalar(42));
  cv::imwrite((dir.path() / "g.png").string(), gray);
  const AnyImage gray_any = read_color_image(dir.path() / "g.png");
  const auto& g = std::get<Rgb8Image>(gray_any);
  EXPECT_EQ(g.channels(), 3);
  EXPECT_EQ(g(2, 1, 1), 42);
}

TEST(ImageIo, ExrRoundTripIsExact) {
  ScratchDir dir;
  FloatImage im(7, 3);
  for (int i = 0; i < 21; ++i) im.data()[i] = 0.01f * float(i) + 1e-7f;
  write_exr(dir.path() / "d.exr", im);
  const FloatImage back = read_exr(dir.path() / "d.exr");
  ASSERT_EQ(back.width(), 7);
  ASSERT_EQ(back.height(), 3);
  for (int i = 0; i < 21; ++i) EXPECT_EQ(back.data()[i], im.data()[i]);
}

TEST(ImageIo, ErrorsNameTheFile) {
  ScratchDir dir;
  const auto missing = dir.path() / "missing.png";
  const auto corrupt = dir.path() / "corrupt.png";
  std::ofstream(corrupt) << "not a png at all";
  for (const auto& path : {missing, corrupt}) {
    try {
      read_color_image(path);
      FAIL() << path;
    } catch (const ImageIoError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(path.string(), 0), 0u) << e.what();
    }
  }
  std::ofstream(dir.path() / "bad.exr") << "garbage";
  EXPECT_THROW(read_exr(dir.path() / "bad.exr"), ImageIoError);
  EXPECT_THROW(write_png(dir.path() / "no" / "such" / "dir.png", Rgb8Image(2, 2)), ImageIoError);
}

TEST(ImageIo, ColorizedInverseDistanceMarksInvalidPixels) {
  FloatImage inv(3, 1);
  inv(0, 0) = 0.0f;
  inv(1, 0) = 1.8f;
  inv(2, 0) = NAN;
  const Rgb8Image rgb = colorize_inverse_distance(inv, 1.8f);
  EXPECT_EQ(rgb(2, 0, 0) + rgb(2, 0, 1) + rgb(2, 0, 2), 0);
  EXPECT_GT(rgb(1, 0, 0), rgb(1, 0, 2));  // near is red
  EXPECT_GT(rgb(0, 0, 2), rgb(0, 0, 0));  // far is blue
}

}  // namespace
}  // namespace omnisweep
