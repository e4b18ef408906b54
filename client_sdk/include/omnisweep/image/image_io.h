// Reading and writing images at the file edge (OpenCV codecs; OpenEXR for .exr files).
// Every error is an ImageIoError whose message starts with the file name.
#pragma once

#include <filesystem>
#include <stdexcept>

#include "omnisweep/image/image.h"

namespace omnisweep {

class ImageIoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A colour image in RGB order at its stored depth: 8-bit (jpg, png, bmp, tif...), 16-bit
// (png, tif) or float (tif, exr; 1.0 = full scale). Gray images become RGB; alpha is dropped.
AnyImage read_color_image(const std::filesystem::path& path);
// An 8-bit single-channel image (masks). Colour files are converted to gray.
Gray8Image read_gray8_image(const std::filesystem::path& path);
// A single-channel float32 EXR (channel "Y", as OpenCV writes it, else the only channel).
FloatImage read_exr(const std::filesystem::path& path);

// Writes 1-channel (gray) or 3-channel (RGB) 8-bit PNGs; compression 0 (fast) to 9 (small).
void write_png(const std::filesystem::path& path, Rgb8View image, int compression = 3);
void write_png(const std::filesystem::path& path, Gray8View image, int compression = 3);
// Writes a 1-channel float32 EXR with channel "Y" (what OpenCV's imwrite produces).
void write_exr(const std::filesystem::path& path, FloatView image);

// Area-averaging resize (OpenCV INTER_AREA), rounded to 8 bits.
Rgb8Image resize_area(Rgb8View image, int width, int height);
Gray8Image resize_area(Gray8View image, int width, int height);
// ALGORITHM.md §2: a mask resized (area) to width x height and read as [0, 1] is usable where
// >= 0.9; returns 255 there, else 0.
Gray8Image usable_mask(Gray8View mask, int width, int height);

// Maps inverse distance in [0, max_inverse_distance] m^-1 to the turbo colour map (far = dark
// blue, near = red) for people to look at; non-finite or negative values become black.
Rgb8Image colorize_inverse_distance(FloatView inverse_distance, float max_inverse_distance);

}  // namespace omnisweep
