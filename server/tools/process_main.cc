// omnisweep-process: a dataset in the reference layout to 360-degree colour + distance panoramas
// (ALGORITHM.md §3-6), like the reference implementation: rgb_<frame>.png and
// inv_distance_<frame>.exr (float32, m^-1), plus a colourised inv_distance_<frame>.png. With
// --evaluate, compares with gt/ and prints MAE, RMSE, > 0.1, > 0.4, PSNR, SSIM and ms per frame.
// confidence_<frame>.png holds the distance's confidence as 8-bit levels (255 = 1); with
// --evaluate, its sparsification curve (AUSE, the MAE of the 80 % most confident pixels) is
// printed and drawn in sparsification_<frame>.png. --temporal filters the distance over the
// frames in order (a stream's filter); with --evaluate, the flicker between consecutive frames
// (the mean |change of inverse distance| where the truth did not change) is printed too.
// --region-planes refits the unconfident regions' distances (stitch/region_planes.h);
// --edge-check lowers the confidence of distances carried across plain surfaces
// (stitch/edge_check.h); --membrane-fill solves the large unconfident regions' distances from
// their rims (stitch/membrane_fill.h).
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <numbers>
#include <span>
#include <string>
#include <vector>

#include "client_sdk/tools/tool_main.h"
#include "omnisweep/codec/codec.h"
#include "omnisweep/dataset/dataset.h"
#include "omnisweep/image/image_io.h"
#include "server/depth/depth_estimator.h"
#include "server/depth/depth_inputs.h"
#include "server/depth/photometric_model.h"
#include "server/pipeline/gpu_frame.h"
#include "server/stitch/panorama_metrics.h"
#include "server/stitch/stitcher.h"
#include "server/tools/depth_flags.h"
#include "server/tools/sparsification_plot.h"
#include "server/tools/stitch_flags.h"

namespace {

using namespace omnisweep;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

// `values` as a JSON array of numbers, "[a, b, ...]", to stdout.
void print_json_numbers(std::span<const double> values) {
  std::printf("[");
  for (std::size_t i = 0; i < values.size(); ++i) std::printf("%s%.6f", i ? ", " : "", values[i]);
  std::printf("]");
}

int run(int argc, char** argv) {
  CLI::App app{
      "Turn the frames of a dataset into 360-degree colour + distance panoramas (sphere sweeping "
      "on the GPU)."};
  std::string dataset_dir, output_dir, frames, device;
  depth::DepthOptions options;
  tools::PanoramaFlags panorama_flags{.panorama = {2048, 1024}};
  const std::vector<int>& rgb_resolution = panorama_flags.rgb_resolution;
  const std::vector<int>& panorama = panorama_flags.panorama;
  bool evaluate = false, json = false;
  std::optional<stitch::TemporalOptions> temporal;
  double plane_fill = 0.0;
  bool region_planes = false, edge_check = false, membrane_fill = false;
  app.add_option("--dataset", dataset_dir, "Dataset in the reference layout")->required();
  app.add_option("--output", output_dir, "Folder for the panoramas (created if missing)")
      ->required();
  app.add_option("--frames", frames, "Comma-separated frame names (default: all)");
  app.add_flag("--evaluate", evaluate,
               "Compare with gt/rgb_<frame>.png and gt/inv_distance_<frame>.exr");
  app.add_flag("--json", json, "One JSON object per frame, then one with \"summary\": true");
  tools::add_panorama_flags(app, panorama_flags);
  tools::add_depth_flags(app, options, device, {&plane_fill, &region_planes});
  tools::add_plane_fill_flag(app, plane_fill);
  tools::add_region_planes_flag(app, region_planes);
  tools::add_edge_check_flag(app, edge_check);
  tools::add_membrane_fill_flag(app, membrane_fill);
  tools::add_temporal_flags(app, temporal);
  CLI11_PARSE(app, argc, argv);

  const Dataset dataset = Dataset::open(dataset_dir);
  // dataset.json's references, viewpoint and distance range, where no flag gives them.
  const DatasetHints& hints = dataset.hints();
  if (!hints.references.empty() && app.count("--references") == 0)
    options.references = hints.references;
  if (hints.min_distance && app.count("--min-dist") == 0)
    options.min_distance = *hints.min_distance;
  if (hints.max_distance && app.count("--max-dist") == 0)
    options.max_distance = *hints.max_distance;
  std::optional<Eigen::Vector3d> viewpoint = panorama_flags.centre();
  if (hints.viewpoint && !viewpoint) viewpoint = *hints.viewpoint;
  options.check(dataset.rig().num_cameras());
  if (evaluate && !dataset.has_ground_truth()) {
    throw std::runtime_error((fs::path(dataset_dir) / "gt").string() +
                             ": --evaluate needs ground truth, and there is none");
  }
  const Rig matching_rig = dataset.rig().resized(options.matching_width, options.matching_height);
  const RigCamera& first = dataset.rig().cameras[options.references[0]];
  const Rig color_rig = rgb_resolution.empty()
                            ? dataset.rig()
                            : dataset.rig().resized(rgb_resolution[0], rgb_resolution[1]);
  for (int r : options.references) {
    const RigCamera& cam = dataset.rig().cameras[r];
    if (rgb_resolution.empty() && (cam.width != first.width || cam.height != first.height)) {
      throw std::runtime_error("reference cameras differ in size; give --rgb-resolution");
    }
  }
  gpu::Context context(tools::context_options(device));
  const auto masks = depth::matching_masks(dataset.masks(), options);
  depth::DepthEstimator estimator(context, matching_rig, masks, options);
  stitch::StitchOptions stitch_options{.panorama_width = panorama[0],
                                       .panorama_height = panorama[1],
                                       .viewpoint = {},
                                       .min_distance = options.min_distance,
                                       .max_distance = options.max_distance};
  stitch_options.viewpoint = viewpoint;
  stitch_options.temporal = temporal;
  stitch_options.plane_fill = plane_fill;
  stitch_options.region_planes = region_planes;
  stitch_options.edge_check = edge_check;
  stitch_options.membrane_fill = membrane_fill;
  stitch::Stitcher stitcher(context, matching_rig, color_rig, options.references, masks,
                            stitch_options);
  pipeline::GpuFrame gpu_frame(context, estimator, stitcher);
  std::optional<depth::PhotometricCorrector> photometry;
  if (options.correct_photometry) photometry.emplace(matching_rig, masks);
  fs::create_directories(output_dir);
  if (!json) {
    std::fprintf(stderr, "device: %s; GPU memory: depth %.1f MiB, stitching %.1f MiB\n",
                 context.info().name.c_str(), estimator.gpu_bytes() / 1048576.0,
                 stitcher.gpu_bytes() / 1048576.0);
  }

  const std::vector<std::string> names =
      frames.empty() ? dataset.frames() : tools::split_list(frames);
  int done = 0, failed = 0;
  std::map<std::string, double> totals;
  // The previous frame's estimate and truth (inverse distance), for the flicker.
  std::optional<std::pair<FloatImage, FloatImage>> previous;
  int flicker_frames = 0;
  const auto skipped = dataset.for_each_frame(
      names,
      [&](Frame&& frame) {
        if (names.size() > 1)
          std::fprintf(stderr, "frame %d/%zu (%s)\n", done + failed + 1, names.size(),
                       frame.name.c_str());
        const auto start = Clock::now();
        std::vector<Rgb8Image> full = depth::rgb8_images(frame);
        std::vector<Rgb8Image> images = depth::matching_images(full, options);
        std::vector<Rgb8Image> color =
            depth::reference_color_images(full, color_rig, options.references);
        double fit_ms = 0;
        const depth::PhotometryFit* fit = nullptr;
        if (photometry) {
          const auto t = Clock::now();
          fit = &photometry->fit(views(images));
          fit_ms = std::chrono::duration<double, std::milli>(Clock::now() - t).count();
        }
        // One submission from the images to the panorama: depth stays on the GPU (the fit's
        // correction too, as the GPU stage "photometry").
        stitch::Panorama pano = gpu_frame.run(views(images), views(color), fit);
        // The fit's host time joins the GPU stages, as the stage "photometry_fit".
        if (photometry) pano.stage_ms.insert(pano.stage_ms.begin(), {"photometry_fit", fit_ms});
        const double ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();

        const FloatImage inverse = reciprocal_or_zero(pano.distance);
        write_png(fs::path(output_dir) / ("rgb_" + frame.name + ".png"), pano.rgb);
        write_exr(fs::path(output_dir) / ("inv_distance_" + frame.name + ".exr"), inverse);
        write_png(fs::path(output_dir) / ("inv_distance_" + frame.name + ".png"),
                  colorize_inverse_distance(inverse, float(1.0 / options.min_distance)));
        write_png(fs::path(output_dir) / ("confidence_" + frame.name + ".png"),
                  codec::confidence_levels(pano.confidence));

        const std::vector<std::pair<std::string, double>>& stages = pano.stage_ms;
        std::optional<stitch::PanoramaMetrics> metrics;
        std::optional<stitch::Sparsification> sparsification;
        std::optional<double> flicker;  // against the previous frame
        if (evaluate) {
          if (!frame.ground_truth) {
            std::fprintf(
                stderr, "frame %s: %s missing, not evaluated\n", frame.name.c_str(),
                (fs::path(dataset_dir) / "gt" / ("inv_distance_" + frame.name + ".exr")).c_str());
            ++failed;
            return;
          }
          metrics = stitch::evaluate_panorama(pano.rgb, pano.distance, frame.ground_truth->rgb,
                                              frame.ground_truth->inverse_distance);
          totals["mae"] += metrics->mae;
          totals["rmse"] += metrics->rmse;
          totals["bad_0_1"] += metrics->bad_0_1;
          totals["bad_0_4"] += metrics->bad_0_4;
          totals["psnr"] += metrics->psnr;
          totals["ssim"] += metrics->ssim;
          sparsification = stitch::sparsification(pano.distance, pano.confidence,
                                                  frame.ground_truth->inverse_distance);
          totals["ause"] += sparsification->ause;
          totals["mae_at_80"] += sparsification->mae_at_80;
          totals["oracle_at_80"] += sparsification->oracle_at_80;
          write_png(
              fs::path(output_dir) / ("sparsification_" + frame.name + ".png"),
              tools::plot_sparsification(
                  *sparsification, fs::path(dataset_dir).lexically_normal().filename().string() +
                                       ", frame " + frame.name));
          if (previous) {
            flicker = stitch::flicker(previous->first, inverse, previous->second,
                                      frame.ground_truth->inverse_distance);
            totals["flicker"] += *flicker;
            ++flicker_frames;
          }
          previous.emplace(inverse.clone(), frame.ground_truth->inverse_distance.clone());
        }
        totals["ms"] += ms;
        for (const auto& [stage, t] : stages) totals["stage:" + stage] += t;
        ++done;
        if (json) {
          std::printf("{\"frame\": %s", json_string(frame.name).c_str());
          if (metrics) {
            std::printf(
                ", \"mae\": %.6f, \"rmse\": %.6f, \"bad_0_1\": %.6f, \"bad_0_4\": %.6f, \"psnr\": "
                "%.4f, \"ssim\": %.6f",
                metrics->mae, metrics->rmse, metrics->bad_0_1, metrics->bad_0_4, metrics->psnr,
                metrics->ssim);
            std::printf(", \"mae_by_eighth\": ");
            print_json_numbers(metrics->mae_by_eighth);
            std::printf(
                ", \"ause\": %.6f, \"mae_at_80\": %.6f, \"oracle_at_80\": %.6f, "
                "\"sparsification_monotonic\": %s, \"sparsification\": ",
                sparsification->ause, sparsification->mae_at_80, sparsification->oracle_at_80,
                sparsification->monotonic ? "true" : "false");
            print_json_numbers(sparsification->mae);
            std::printf(", \"oracle\": ");
            print_json_numbers(sparsification->oracle);
            if (flicker) std::printf(", \"flicker\": %.6f", *flicker);
          }
          if (photometry) {
            // Each camera's estimated gains and the brightness its vignetting leaves at 110 deg.
            std::printf(", \"photometry\": [");
            const auto& cameras = photometry->last().cameras;
            for (std::size_t c = 0; c < cameras.size(); ++c) {
              std::printf("%s{\"gain\": [%.4f, %.4f, %.4f], \"vignetting_110\": %.4f}",
                          c ? ", " : "", cameras[c].gain[0], cameras[c].gain[1], cameras[c].gain[2],
                          cameras[c].vignetting(110.0 * std::numbers::pi / 180.0));
            }
            std::printf("]");
          }
          std::printf(", \"ms\": %.2f, \"stages\": {", ms);
          for (std::size_t i = 0; i < stages.size(); ++i) {
            std::printf("%s%s: %.2f", i ? ", " : "", json_string(stages[i].first).c_str(),
                        stages[i].second);
          }
          std::printf("}}\n");
        } else {
          std::printf("frame %s:", frame.name.c_str());
          if (metrics) {
            std::printf(
                " MAE %.4f, RMSE %.4f, >0.1 %.2f %%, >0.4 %.2f %%, PSNR %.2f dB, SSIM %.4f,",
                metrics->mae, metrics->rmse, 100 * metrics->bad_0_1, 100 * metrics->bad_0_4,
                metrics->psnr, metrics->ssim);
            std::printf(" AUSE %.4f, MAE of the 80 %% most confident %.4f (oracle %.4f)%s,",
                        sparsification->ause, sparsification->mae_at_80,
                        sparsification->oracle_at_80,
                        sparsification->monotonic ? "" : " (curve not monotonic)");
            if (flicker) std::printf(" flicker %.4f,", *flicker);
          }
          std::printf(" %.1f ms (", ms);
          for (std::size_t i = 0; i < stages.size(); ++i) {
            std::printf("%s%s %.1f", i ? ", " : "", stages[i].first.c_str(), stages[i].second);
          }
          std::printf(")\n");
        }
        std::fflush(stdout);
      },
      [&](const SkippedFrame& s) {
        std::fprintf(stderr, "skipped frame %s: %s\n", s.name.c_str(), s.reason.c_str());
      });

  const double n = std::max(done, 1);
  if (json) {
    std::printf("{\"summary\": true, \"frames\": %d, \"failed\": %zu", done,
                skipped.size() + failed);
    for (const char* key : {"mae", "rmse", "bad_0_1", "bad_0_4", "psnr", "ssim", "ause",
                            "mae_at_80", "oracle_at_80"}) {
      if (evaluate) std::printf(", \"%s\": %.6f", key, totals[key] / n);
    }
    if (flicker_frames > 0) std::printf(", \"flicker\": %.6f", totals["flicker"] / flicker_frames);
    std::printf(", \"ms\": %.2f}\n", totals["ms"] / n);
  } else {
    std::printf("%d frame(s) written to %s", done, fs::absolute(output_dir).c_str());
    if (evaluate && done) {
      std::printf(
          "; overall MAE %.4f, RMSE %.4f, >0.1 %.2f %%, >0.4 %.2f %%, PSNR %.2f dB, SSIM %.4f, "
          "AUSE %.4f, MAE of the 80 %% most confident %.4f (oracle %.4f)",
          totals["mae"] / n, totals["rmse"] / n, 100 * totals["bad_0_1"] / n,
          100 * totals["bad_0_4"] / n, totals["psnr"] / n, totals["ssim"] / n, totals["ause"] / n,
          totals["mae_at_80"] / n, totals["oracle_at_80"] / n);
      if (flicker_frames > 0) std::printf(", flicker %.4f", totals["flicker"] / flicker_frames);
    }
    std::printf("; %.1f ms per frame\n", totals["ms"] / n);
  }
  return skipped.empty() && failed == 0 && done > 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  return omnisweep::tools::run_tool("omnisweep-process", argc, argv, run);
}
