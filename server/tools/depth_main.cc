// omnisweep-depth: fisheye distance maps of a dataset's reference cameras (ALGORITHM.md §3-4),
// written as inverse distance (float32 EXR) and as colourised PNGs, with GPU time per stage;
// with --evaluate, compared with per-camera ground truth (gt/cam<i>/inv_distance_<frame>.exr).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "client_sdk/tools/tool_main.h"
#include "omnisweep/dataset/dataset.h"
#include "omnisweep/gpu/context.h"
#include "omnisweep/image/image_io.h"
#include "server/depth/depth_estimator.h"
#include "server/depth/depth_inputs.h"
#include "server/tools/depth_flags.h"

namespace {

using namespace omnisweep;
namespace fs = std::filesystem;

int run(int argc, char** argv) {
  CLI::App app{"Estimate fisheye distance maps of the reference cameras of a dataset on the GPU."};
  std::string dataset_dir, output_dir, frames, device;
  depth::DepthOptions options;
  bool evaluate = false;
  app.add_option("--dataset", dataset_dir, "Dataset in the reference layout")->required();
  app.add_option("--output", output_dir, "Folder for the distance maps (created if missing)")
      ->required();
  app.add_option("--frames", frames, "Comma-separated frame names (default: all)");
  app.add_flag("--evaluate", evaluate, "Compare with gt/cam<i>/inv_distance_<frame>.exr");
  tools::add_depth_flags(app, options, device);
  CLI11_PARSE(app, argc, argv);

  const Dataset dataset = Dataset::open(dataset_dir);
  options.check(dataset.rig().num_cameras());
  gpu::Context context(tools::context_options(device));
  depth::DepthEstimator estimator(
      context, dataset.rig().resized(options.matching_width, options.matching_height),
      depth::matching_masks(dataset.masks(), options), options);
  fs::create_directories(output_dir);
  std::fprintf(stderr, "device: %s; GPU memory for depth: %.1f MiB\n", context.info().name.c_str(),
               double(estimator.gpu_bytes()) / (1 << 20));

  int done = 0, failed = 0;
  const auto skipped = dataset.for_each_frame(
      tools::split_list(frames),
      [&](Frame&& frame) {
        const auto images = depth::matching_images(depth::rgb8_images(frame), options);
        const depth::DepthResult result = estimator.estimate(views(images));
        std::printf("frame %s:", frame.name.c_str());
        for (const auto& [stage, ms] : result.stage_ms)
          std::printf(" %s %.1f ms", stage.c_str(), ms);
        std::printf("\n");
        for (std::size_t slot = 0; slot < options.references.size(); ++slot) {
          const int ref = options.references[slot];
          FloatImage inverse(options.matching_width, options.matching_height);
          for (std::size_t p = 0; p < inverse.size(); ++p)
            inverse.data()[p] = 1.0f / result.distance[slot].data()[p];
          const std::string stem = "inv_distance_cam" + std::to_string(ref) + "_" + frame.name;
          write_exr(fs::path(output_dir) / (stem + ".exr"), inverse);
          write_png(fs::path(output_dir) / (stem + ".png"),
                    colorize_inverse_distance(inverse, float(1.0 / options.min_distance)));
          if (!evaluate) continue;
          static const std::optional<FloatImage> kNone;
          const auto& gt =
              frame.ground_truth ? frame.ground_truth->camera_inverse_distance[ref] : kNone;
          if (!gt) {
            std::fprintf(stderr, "frame %s: no gt/cam%d/inv_distance_%s.exr to evaluate against\n",
                         frame.name.c_str(), ref, frame.name.c_str());
            ++failed;
            continue;
          }
          const FloatImage truth =
              gt->width() == options.matching_width ? gt->clone() : FloatImage();
          if (truth.empty()) {
            std::fprintf(stderr,
                         "frame %s: camera ground truth is %dx%d, not the matching resolution\n",
                         frame.name.c_str(), gt->width(), gt->height());
            ++failed;
            continue;
          }
          double mae = 0, bad1 = 0, bad4 = 0;
          long n = 0;
          for (std::size_t p = 0; p < truth.size(); ++p) {
            if (truth.data()[p] <= 0) continue;
            const double e = std::abs(double(inverse.data()[p]) - truth.data()[p]);
            mae += e;
            bad1 += e > 0.1;
            bad4 += e > 0.4;
            ++n;
          }
          std::printf("  camera %d: MAE %.4f m^-1, >0.1 %.2f %%, >0.4 %.2f %% over %ld pixels\n",
                      ref, mae / n, 100 * bad1 / n, 100 * bad4 / n, n);
        }
        ++done;
      },
      [](const SkippedFrame& s) {
        std::fprintf(stderr, "skipped frame %s: %s\n", s.name.c_str(), s.reason.c_str());
      });
  std::printf("%d frame(s) written to %s\n", done, fs::absolute(output_dir).c_str());
  return skipped.empty() && failed == 0 && done > 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  return omnisweep::tools::run_tool("omnisweep-depth", argc, argv, run);
}
