// omnisweep-bench's codec section: the distance codec against 16-bit PNG on estimated panoramas.
#include "server/tools/bench_codecs.h"

#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <optional>
#include <utility>
#include <vector>

#include "omnisweep/codec/codec.h"
#include "omnisweep/dataset/dataset.h"
#include "server/depth/depth_estimator.h"
#include "server/depth/depth_inputs.h"
#include "server/stitch/stitcher.h"
#include "server/synthetic/synthetic_rig.h"
#include "server/tools/bench_stats.h"

namespace omnisweep::tools {
namespace {

// Runs per measurement; the median is reported.
constexpr int kRuns = 15;

// Medians of kRuns calls of each of a and b, alternated so both see the same machine load.
template <typename A, typename B>
std::pair<Cost, Cost> interleaved(A&& a, B&& b) {
  std::vector<Cost> ca, cb;
  for (int i = 0; i < kRuns; ++i) {
    ca.push_back(cost_of(a));
    cb.push_back(cost_of(b));
  }
  return {median(ca), median(cb)};
}

struct Error {
  double mean = 0, max = 0;
};
// Inverse-distance error of `back` against `truth` over the pixels that have a distance.
Error inverse_error(const FloatImage& truth, const FloatImage& back) {
  Error e;
  std::size_t count = 0;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const float d = truth.data()[i];
    if (d <= 0) continue;
    const double error = std::abs(1.0 / back.data()[i] - 1.0 / d);
    e.max = std::max(e.max, error);
    e.mean += error;
    ++count;
  }
  e.mean /= double(std::max<std::size_t>(count, 1));
  return e;
}

// The levels the distance codec quantises to, as a 16-bit image.
cv::Mat quantised_levels(const FloatImage& distance, const codec::DistanceParams& params) {
  const int w = distance.width(), h = distance.height();
  cv::Mat levels(h, w, CV_16UC1);
  const double lo = 1.0 / params.max_distance, hi = 1.0 / params.min_distance;
  for (int p = 0; p < w * h; ++p) {
    const float d = distance.data()[p];
    levels.at<std::uint16_t>(p) =
        d > 0 ? std::uint16_t(1 + std::lround((std::clamp(1.0 / d, lo, hi) - lo) / (hi - lo) *
                                              (params.levels - 1)))
              : 0;
  }
  return levels;
}

class Table {
 public:
  explicit Table(bool json) : json_(json) {
    if (json_) return;
    std::printf(
        "\nCodecs on estimated 2048x1024 panoramas (median of %d; KB; wall and CPU ms, CPU of all "
        "threads)\n",
        kRuns);
    std::printf("%-10s %-38s %8s %9s %9s %9s %9s %9s %9s\n", "panorama", "codec", "KB", "enc ms",
                "enc cpu", "dec ms", "dec cpu", "mean err", "max err");
  }
  void row(const std::string& pano, const std::string& name, std::size_t bytes, Cost enc, Cost dec,
           Error error) const {
    if (json_) {
      std::printf(
          "{\"kind\": \"codec\", \"panorama\": \"%s\", \"codec\": \"%s\", \"bytes\": %zu, "
          "\"encode_ms\": %.3f, \"encode_cpu_ms\": %.3f, \"decode_ms\": %.3f, "
          "\"decode_cpu_ms\": %.3f, \"mean_error\": %.6g, \"max_error\": %.6g}\n",
          pano.c_str(), name.c_str(), bytes, enc.wall_ms, enc.cpu_ms, dec.wall_ms, dec.cpu_ms,
          error.mean, error.max);
    } else {
      std::printf("%-10s %-38s %8.1f %9.2f %9.2f %9.2f %9.2f %9.3g %9.3g\n", pano.c_str(),
                  name.c_str(), bytes / 1024.0, enc.wall_ms, enc.cpu_ms, dec.wall_ms, dec.cpu_ms,
                  error.mean, error.max);
    }
  }
  // The distance codec against PNG, measured side by side.
  void ratio(const std::string& pano, std::size_t ours, std::size_t png, Cost ours_enc,
             Cost png_enc, Cost ours_dec, Cost png_dec) const {
    const double size = double(ours) / double(png);
    const double enc = png_enc.wall_ms / ours_enc.wall_ms,
                 enc_cpu = png_enc.cpu_ms / ours_enc.cpu_ms;
    const double dec = png_dec.wall_ms / ours_dec.wall_ms,
                 dec_cpu = png_dec.cpu_ms / ours_dec.cpu_ms;
    if (json_) {
      std::printf(
          "{\"kind\": \"codec_ratio\", \"panorama\": \"%s\", \"size_ratio\": %.4f, "
          "\"encode_speedup\": %.2f, \"encode_cpu_ratio\": %.2f, \"decode_speedup\": %.2f, "
          "\"decode_cpu_ratio\": %.2f}\n",
          pano.c_str(), size, enc, enc_cpu, dec, dec_cpu);
    } else {
      std::printf(
          "%-10s qinv16-zstd vs png16 level 1: %.0f %% of the size; encode %.1fx faster (%.1fx "
          "less CPU), decode %.1fx faster (%.1fx less CPU)\n",
          pano.c_str(), 100 * size, enc, enc_cpu, dec, dec_cpu);
    }
  }

 private:
  bool json_;
};

}  // namespace

// An estimated 2048x1024 panorama (defaults) of a frame: what the server compresses.
stitch::Panorama estimate_panorama(gpu::Context& context, const Rig& rig,
                                   const std::vector<Rgb8Image>& images,
                                   const std::vector<std::optional<Gray8Image>>& masks_full) {
  depth::DepthOptions options;
  const Rig matching_rig = rig.resized(options.matching_width, options.matching_height);
  const auto usable = depth::matching_masks(masks_full, options);
  const std::vector<Rgb8Image> matching = depth::matching_images(images, options);
  depth::DepthEstimator estimator(context, matching_rig, usable, options);
  const depth::DepthResult result = estimator.estimate(views(matching));
  stitch::Stitcher stitcher(context, matching_rig, rig, options.references, usable, {});
  return stitcher.stitch(views(result.distance), std::vector<Rgb8View>{images[2], images[3]});
}

stitch::Panorama synthetic_panorama(gpu::Context& context) {
  const synthetic::SyntheticRig rig;
  synthetic::SyntheticFrame frame = rig.render(0, 64, 32);
  std::vector<Rgb8Image> images;
  std::vector<std::optional<Gray8Image>> masks;
  for (auto& c : frame.cameras) images.push_back(std::move(c.rgb));
  for (auto& m : rig.masks()) masks.emplace_back(std::move(m));
  return estimate_panorama(context, rig.rig(), images, masks);
}

void codec_section(gpu::Context& context, const std::string& kaist_dir, bool json) {
  std::vector<std::pair<std::string, stitch::Panorama>> panoramas;
  panoramas.emplace_back("synthetic", synthetic_panorama(context));
  if (!kaist_dir.empty() &&
      std::filesystem::exists(std::filesystem::path(kaist_dir) / "calibration.json")) {
    const Dataset kaist = Dataset::open(kaist_dir);
    const Frame frame = kaist.load_frame(kaist.frames().at(0));
    panoramas.emplace_back(
        "kaist-rig",
        estimate_panorama(context, kaist.rig(), depth::rgb8_images(frame), kaist.masks()));
  }
  const auto distance_codec = codec::make_distance_codec(codec::kQinv16Zstd);
  const codec::DistanceParams full, light = codec::kLightDistance;
  const Table table(json);
  for (const auto& entry : panoramas) {
    // Named, not a structured binding: clang 14 (the sanitizer build) cannot capture one.
    const std::string& label = entry.first;
    const FloatImage& distance = entry.second.distance;
    const int w = distance.width(), h = distance.height();

    // Defaults, side by side with 16-bit PNG of the same levels at zlib level 1.
    codec::Bytes bytes;
    std::vector<std::uint8_t> png;
    const cv::Mat levels = quantised_levels(distance, full);
    distance_codec->encode(distance, full);  // first call: allocates its buffers
    const auto [enc, png_enc] =
        interleaved([&] { bytes = distance_codec->encode(distance, full); },
                    [&] {
                      cv::imencode(".png", levels, png, {cv::IMWRITE_PNG_COMPRESSION, 1});
                    });
    FloatImage back;
    const auto [dec, png_dec] =
        interleaved([&] { back = distance_codec->decode(bytes, w, h, full); },
                    [&] { cv::imdecode(png, cv::IMREAD_UNCHANGED); });
    const std::size_t default_bytes = bytes.size();
    table.row(label, "qinv16-zstd (default)", default_bytes, enc, dec,
              inverse_error(distance, back));
    table.row(label, "png16 level 1 (same levels)", png.size(), png_enc, png_dec,
              {full.max_quantisation_error() / 2, full.max_quantisation_error()});

    std::vector<Cost> light_enc, light_dec;
    for (int i = 0; i < kRuns; ++i) {
      light_enc.push_back(cost_of([&] { bytes = distance_codec->encode(distance, light); }));
      light_dec.push_back(cost_of([&] { back = distance_codec->decode(bytes, w, h, light); }));
    }
    table.row(label,
              "qinv16-zstd light (" + std::to_string(light.levels) + " levels, 1/" +
                  std::to_string(light.downsample) + " res)",
              bytes.size(), median(light_enc), median(light_dec), inverse_error(distance, back));

    for (int quality : {codec::ColorOptions{}.quality, codec::kLightJpegQuality}) {
      const auto jpeg = codec::make_color_codec(codec::kJpeg, {.quality = quality});
      std::vector<Cost> jpeg_enc, jpeg_dec;
      for (int i = 0; i < kRuns; ++i) {
        jpeg_enc.push_back(cost_of([&] { bytes = jpeg->encode(entry.second.rgb); }));
        jpeg_dec.push_back(cost_of([&] { jpeg->decode(bytes, w, h); }));
      }
      table.row(label, "jpeg q" + std::to_string(quality) + " (colour)", bytes.size(),
                median(jpeg_enc), median(jpeg_dec), {});
    }
    table.ratio(label, default_bytes, png.size(), enc, png_enc, dec, png_dec);
  }
}

}  // namespace omnisweep::tools
