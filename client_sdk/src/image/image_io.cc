#include "omnisweep/image/image_io.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <system_error>

namespace omnisweep {
namespace {

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& what) {
  throw ImageIoError(path.string() + ": " + what);
}

void require_readable_file(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) fail(path, "file does not exist");
  if (!std::filesystem::is_regular_file(path, ec)) fail(path, "is not a regular file");
}

bool is_exr(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext == ".exr";
}

template <typename T>
Image<T, 3> rgb_from_mat(const cv::Mat& mat) {
  cv::Mat rgb;
  switch (mat.channels()) {
    case 1:
      cv::cvtColor(mat, rgb, cv::COLOR_GRAY2RGB);
      break;
    case 3:
      cv::cvtColor(mat, rgb, cv::COLOR_BGR2RGB);
      break;
    case 4:
      cv::cvtColor(mat, rgb, cv::COLOR_BGRA2RGB);
      break;
    default:
      break;
  }
  Image<T, 3> out(mat.cols, mat.rows);
  for (int y = 0; y < mat.rows; ++y) {
    std::memcpy(out.view().row(y), rgb.ptr<T>(y), sizeof(T) * 3 * mat.cols);
  }
  return out;
}

// Reads the named channels of an EXR file as float, in order; missing channels are an error.
std::vector<FloatImage> read_exr_channels(const std::filesystem::path& path,
                                          const std::vector<std::string>& names) {
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i window = file.header().dataWindow();
    const int width = window.max.x - window.min.x + 1;
    const int height = window.max.y - window.min.y + 1;
    if (width <= 0 || height <= 0 || std::int64_t(width) * height > (std::int64_t(1) << 28)) {
      fail(path, "unsupported EXR size " + std::to_string(width) + "x" + std::to_string(height));
    }
    std::vector<FloatImage> out;
    Imf::FrameBuffer buffer;
    for (const std::string& name : names) {
      if (!file.header().channels().findChannel(name))
        fail(path, "EXR has no channel '" + name + "'");
      out.emplace_back(width, height);
      char* origin =
          reinterpret_cast<char*>(out.back().data()) -
          (std::ptrdiff_t(window.min.y) * width + window.min.x) * std::ptrdiff_t(sizeof(float));
      buffer.insert(name, Imf::Slice(Imf::FLOAT, origin, sizeof(float), sizeof(float) * width));
    }
    file.setFrameBuffer(buffer);
    file.readPixels(window.min.y, window.max.y);
    return out;
  } catch (const ImageIoError&) {
    throw;
  } catch (const std::exception& e) {
    fail(path, std::string("cannot read EXR: ") + e.what());
  }
}

std::vector<std::string> exr_channel_names(const std::filesystem::path& path) {
  try {
    Imf::InputFile file(path.c_str());
    std::vector<std::string> names;
    for (auto it = file.header().channels().begin(); it != file.header().channels().end(); ++it) {
      names.emplace_back(it.name());
    }
    return names;
  } catch (const std::exception& e) {
    fail(path, std::string("cannot read EXR: ") + e.what());
  }
}

}  // namespace

AnyImage read_color_image(const std::filesystem::path& path) {
  require_readable_file(path);
  if (is_exr(path)) {
    const auto names = exr_channel_names(path);
    const bool rgb = std::ranges::count_if(names, [](const std::string& n) {
                       return n == "R" || n == "G" || n == "B";
                     }) == 3;
    if (!rgb && names.size() != 1) fail(path, "EXR colour image needs R, G, B or a single channel");
    auto channels = read_exr_channels(path, rgb ? std::vector<std::string>{"R", "G", "B"} : names);
    RgbFloatImage out(channels[0].width(), channels[0].height());
    for (std::size_t i = 0; i < channels[0].size(); ++i) {
      for (int c = 0; c < 3; ++c) out.data()[i * 3 + c] = channels[rgb ? c : 0].data()[i];
    }
    return out;
  }
  const cv::Mat mat = cv::imread(path.string(), cv::IMREAD_UNCHANGED);
  if (mat.empty()) fail(path, "cannot decode image (unsupported or corrupt file)");
  if (mat.channels() != 1 && mat.channels() != 3 && mat.channels() != 4) {
    fail(path, "unsupported channel count " + std::to_string(mat.channels()));
  }
  switch (mat.depth()) {
    case CV_8U:
      return rgb_from_mat<std::uint8_t>(mat);
    case CV_16U:
      return rgb_from_mat<std::uint16_t>(mat);
    case CV_32F:
      return rgb_from_mat<float>(mat);
    default:
      fail(path, "unsupported sample type (expected 8-bit, 16-bit or float)");
  }
}

Gray8Image read_gray8_image(const std::filesystem::path& path) {
  require_readable_file(path);
  const cv::Mat mat = cv::imread(path.string(), cv::IMREAD_GRAYSCALE);
  if (mat.empty()) fail(path, "cannot decode image (unsupported or corrupt file)");
  Gray8Image out(mat.cols, mat.rows);
  for (int y = 0; y < mat.rows; ++y) std::memcpy(out.view().row(y), mat.ptr(y), mat.cols);
  return out;
}

FloatImage read_exr(const std::filesystem::path& path) {
  require_readable_file(path);
  const auto names = exr_channel_names(path);
  const bool has_y = std::ranges::find(names, "Y") != names.end();
  if (!has_y && names.size() != 1) {
    fail(path, "expected a single-channel EXR (channel 'Y'), found " +
                   std::to_string(names.size()) + " channels");
  }
  return std::move(read_exr_channels(path, {has_y ? std::string("Y") : names[0]})[0]);
}

namespace {

template <int Channels>
void write_png_of(const std::filesystem::path& path, ImageView<const std::uint8_t, Channels> image,
                  int compression) {
  cv::Mat wrapped(image.height(), image.width(), CV_8UC(Channels),
                  const_cast<std::uint8_t*>(image.data()));
  cv::Mat bgr;
  if constexpr (Channels == 3) {
    cv::cvtColor(wrapped, bgr, cv::COLOR_RGB2BGR);
  } else {
    bgr = wrapped;
  }
  bool ok = false;
  try {
    ok = cv::imwrite(path.string(), bgr, {cv::IMWRITE_PNG_COMPRESSION, compression});
  } catch (const cv::Exception& e) {
    fail(path, std::string("cannot write PNG: ") + e.what());
  }
  if (!ok) fail(path, "cannot write PNG");
}

template <int Channels>
Image<std::uint8_t, Channels> resize_area_of(ImageView<const std::uint8_t, Channels> image,
                                             int width, int height) {
  if (width <= 0 || height <= 0) throw ImageIoError("resize_area: target size must be positive");
  const cv::Mat src(image.height(), image.width(), CV_8UC(Channels),
                    const_cast<std::uint8_t*>(image.data()));
  Image<std::uint8_t, Channels> out(width, height);
  cv::Mat dst(height, width, CV_8UC(Channels), out.data());
  cv::resize(src, dst, dst.size(), 0, 0, cv::INTER_AREA);
  return out;
}

}  // namespace

void write_png(const std::filesystem::path& path, Rgb8View image, int compression) {
  write_png_of(path, image, compression);
}

void write_png(const std::filesystem::path& path, Gray8View image, int compression) {
  write_png_of(path, image, compression);
}

Rgb8Image resize_area(Rgb8View image, int width, int height) {
  return resize_area_of(image, width, height);
}

Gray8Image resize_area(Gray8View image, int width, int height) {
  return resize_area_of(image, width, height);
}

void write_exr(const std::filesystem::path& path, FloatView image) {
  try {
    Imf::Header header(image.width(), image.height());
    header.channels().insert("Y", Imf::Channel(Imf::FLOAT));
    header.compression() = Imf::ZIP_COMPRESSION;
    Imf::OutputFile file(path.c_str(), header);
    Imf::FrameBuffer buffer;
    buffer.insert(
        "Y", Imf::Slice(Imf::FLOAT, const_cast<char*>(reinterpret_cast<const char*>(image.data())),
                        sizeof(float), sizeof(float) * image.width()));
    file.setFrameBuffer(buffer);
    file.writePixels(image.height());
  } catch (const std::exception& e) {
    fail(path, std::string("cannot write EXR: ") + e.what());
  }
}

Gray8Image usable_mask(Gray8View mask, int width, int height) {
  const cv::Mat src(mask.height(), mask.width(), CV_8UC1, const_cast<std::uint8_t*>(mask.data()));
  cv::Mat as_float, resized;
  src.convertTo(as_float, CV_32F, 1.0 / 255.0);
  cv::resize(as_float, resized, cv::Size(width, height), 0, 0, cv::INTER_AREA);
  Gray8Image out(width, height);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) out(x, y) = resized.at<float>(y, x) >= 0.9f ? 255 : 0;
  }
  return out;
}

Rgb8Image colorize_inverse_distance(FloatView inverse_distance, float max_inverse_distance) {
  cv::Mat levels(inverse_distance.height(), inverse_distance.width(), CV_8UC1);
  cv::Mat valid(levels.size(), CV_8UC1);
  for (int y = 0; y < levels.rows; ++y) {
    for (int x = 0; x < levels.cols; ++x) {
      const float v = inverse_distance(x, y);
      const bool ok = std::isfinite(v) && v >= 0.0f;
      valid.at<std::uint8_t>(y, x) = ok ? 255 : 0;
      levels.at<std::uint8_t>(y, x) =
          ok ? std::uint8_t(std::lround(255.0f * std::min(v / max_inverse_distance, 1.0f))) : 0;
    }
  }
  cv::Mat bgr;
  cv::applyColorMap(levels, bgr, cv::COLORMAP_TURBO);
  bgr.setTo(cv::Scalar::all(0), valid == 0);
  return rgb_from_mat<std::uint8_t>(bgr);
}

}  // namespace omnisweep
