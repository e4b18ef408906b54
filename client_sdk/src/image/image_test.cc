#include "omnisweep/image/image.h"

#include <gtest/gtest.h>

#include <cmath>
#include <type_traits>
#include <vector>

namespace omnisweep {
namespace {

TEST(Image, LayoutIsInterleavedRowMajor) {
  RgbFloatImage im(3, 2);
  im(2, 1, 1) = 5.0f;
  EXPECT_EQ(im.data()[(1 * 3 + 2) * 3 + 1], 5.0f);
  EXPECT_EQ(im.view().row(1)[2 * 3 + 1], 5.0f);
  EXPECT_TRUE(im.contains(2, 1));
  EXPECT_FALSE(im.contains(3, 0));
}

TEST(Image, CloneIsDeep) {
  Gray8Image a = Gray8Image::filled(4, 4, 9);
  Gray8Image b = a.clone();
  b(0, 0) = 1;
  EXPECT_EQ(a(0, 0), 9);
  Gray8Image moved = std::move(b);
  EXPECT_EQ(moved(0, 0), 1);
}

TEST(Image, DepthConversionsKeepFullScale) {
  Rgb16Image sixteen(1, 1);
  sixteen(0, 0, 0) = 65535;
  sixteen(0, 0, 1) = 257 * 100;
  sixteen(0, 0, 2) = 0;
  const AnyImage any16 = std::move(sixteen);
  EXPECT_STREQ(depth_name(any16), "16-bit");
  const Rgb8Image u8 = to_rgb8(any16);
  EXPECT_EQ(u8(0, 0, 0), 255);
  EXPECT_EQ(u8(0, 0, 1), 100);
  EXPECT_EQ(u8(0, 0, 2), 0);
  // Float keeps sub-level precision on the 0..255 scale.
  EXPECT_NEAR(to_rgb_float255(any16)(0, 0, 1), 100.0f, 1e-4);

  RgbFloatImage f(1, 1);
  f(0, 0, 0) = 0.5f;
  f(0, 0, 1) = NAN;
  f(0, 0, 2) = 3.0f;
  const AnyImage anyf = std::move(f);
  EXPECT_EQ(width_of(anyf), 1);
  const Rgb8Image fu8 = to_rgb8(anyf);
  EXPECT_EQ(fu8(0, 0, 0), 128);  // 127.5 rounds up
  EXPECT_EQ(fu8(0, 0, 1), 0);    // NaN reads as 0
  EXPECT_EQ(fu8(0, 0, 2), 255);  // clamped
}

// The pixel format is the type: colour, grey and float images do not stand in for one another,
// and the channel count of 0.1's constructor no longer compiles (it would now read as a fill).
static_assert(!std::is_same_v<Rgb8Image, Gray8Image>);
static_assert(!std::is_convertible_v<const Rgb8Image&, Gray8View>);
static_assert(!std::is_convertible_v<const Gray8Image&, Rgb8View>);
static_assert(!std::is_convertible_v<const RgbFloatImage&, FloatView>);
static_assert(std::is_convertible_v<const Rgb8Image&, Rgb8View>);
static_assert(std::is_convertible_v<ImageView<float, 1>, FloatView>);
static_assert(!std::is_convertible_v<FloatView, ImageView<float, 1>>);
static_assert(!std::is_constructible_v<Rgb8Image, int, int, int>);
static_assert(!std::is_constructible_v<FloatImage, int, int, int, float>);
static_assert(Rgb8Image::channels() == 3 && Gray8Image::channels() == 1);

TEST(Image, ViewsSeeTheOwnersPixels) {
  std::vector<Rgb8Image> images;
  images.push_back(Rgb8Image::filled(4, 3, 7));
  images.push_back(Rgb8Image(2, 2));
  const std::vector<Rgb8View> seen = views(images);
  ASSERT_EQ(seen.size(), 2u);
  EXPECT_EQ(seen[0].data(), images[0].data());
  EXPECT_EQ(seen[0].width(), 4);
  EXPECT_EQ(seen[0].height(), 3);
  EXPECT_EQ(seen[0](3, 2, 2), 7);
  images[0](3, 2, 2) = 9;  // a view, not a copy
  EXPECT_EQ(seen[0](3, 2, 2), 9);
  EXPECT_EQ(seen[1](1, 1, 0), 0);  // zero-filled

  const Rgb8Image copy = Rgb8Image::copy_of(seen[0]);
  images[0](0, 0, 0) = 1;
  EXPECT_EQ(copy(0, 0, 0), 7);  // a copy, not a view
  EXPECT_EQ(copy(3, 2, 2), 9);

  FloatImage distance = FloatImage::filled(3, 2, 2.5f);
  const ImageView<float> writable = distance.view();
  writable(1, 1) = 4.0f;
  const FloatView readable = writable;
  EXPECT_EQ(readable(1, 1), 4.0f);
  EXPECT_EQ(readable(0, 0), 2.5f);
  EXPECT_EQ(readable.size(), 6u);
}

}  // namespace
}  // namespace omnisweep
