#include "omnisweep/image/image.h"

#include <gtest/gtest.h>

#include <cmath>

namespace omnisweep {
namespace {

TEST(Image, LayoutIsInterleavedRowMajor) {
  Image<float> im(3, 2, 3, 0.0f);
  im(2, 1, 1) = 5.0f;
  EXPECT_EQ(im.data()[(1 * 3 + 2) * 3 + 1], 5.0f);
  EXPECT_EQ(im.view().row(1)[2 * 3 + 1], 5.0f);
  EXPECT_TRUE(im.contains(2, 1));
  EXPECT_FALSE(im.contains(3, 0));
}

TEST(Image, CloneIsDeep) {
  Image<std::uint8_t> a(4, 4, 1, 9);
  Image<std::uint8_t> b = a.clone();
  b(0, 0) = 1;
  EXPECT_EQ(a(0, 0), 9);
  Image<std::uint8_t> moved = std::move(b);
  EXPECT_EQ(moved(0, 0), 1);
}

TEST(Image, DepthConversionsKeepFullScale) {
  Image<std::uint16_t> sixteen(1, 1, 3);
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

  Image<float> f(1, 1, 3);
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

}  // namespace
}  // namespace omnisweep
