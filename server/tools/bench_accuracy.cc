#include "server/tools/bench_accuracy.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "omnisweep/dataset/dataset.h"
#include "omnisweep/gpu/command_log.h"
#include "server/depth/depth_estimator.h"
#include "server/depth/depth_inputs.h"
#include "server/depth/photometric_model.h"
#include "server/pipeline/gpu_frame.h"
#include "server/stitch/panorama_metrics.h"
#include "server/stitch/stitcher.h"
#include "server/synthetic/synthetic_rig.h"
#include "server/tools/bench_model.h"

namespace omnisweep::tools {
namespace {

struct TruthFrame {
  std::vector<Rgb8Image> images;  // every camera, as calibrated
  Rgb8Image rgb;
  FloatImage inverse_distance;
};

struct AccuracySet {
  std::string name;
  Rig rig;
  std::vector<std::optional<Gray8Image>> masks;
  std::vector<int> references;
  std::optional<Eigen::Vector3d> viewpoint;
  std::vector<TruthFrame> frames;
};

struct Variant {
  const char* name;
  depth::MatchingCost cost;
  bool correct_photometry;
  int match_cameras = 1;
  double confident_sigma_s = 0;  // DepthOptions::confident_sigma_s
  double plane_fill = 0;         // StitchOptions::plane_fill
  double sigma_s = 0;            // DepthOptions::sigma_s; 0: the paper's
  bool region_planes = false;    // StitchOptions::region_planes
  bool edge_check = false;       // StitchOptions::edge_check
  double match_blur = 0;         // DepthOptions::match_blur
  double raw_agreement = 0;      // DepthOptions::raw_agreement
  bool membrane_fill = false;    // StitchOptions::membrane_fill
};

constexpr Variant kVariants[] = {
    {"paper (ad)", depth::MatchingCost::kAbsoluteDifference, false},
    {"ad + photometric correction", depth::MatchingCost::kAbsoluteDifference, true},
    {"ad, 2 cameras", depth::MatchingCost::kAbsoluteDifference, false, 2},
    {"ad + correction, 2 cameras", depth::MatchingCost::kAbsoluteDifference, true, 2},
    {"nad", depth::MatchingCost::kNormalised, false},
    {"nad + photometric correction", depth::MatchingCost::kNormalised, true},
    {"nad, 2 cameras", depth::MatchingCost::kNormalised, false, 2},
    {"census", depth::MatchingCost::kCensus, false},
    {"nad-census", depth::MatchingCost::kNormalisedCensus, false},
    {"ratio", depth::MatchingCost::kRatio, false},
    {"ratio, 2 cameras", depth::MatchingCost::kRatio, false, 2},
    {"ad, confident 5", depth::MatchingCost::kAbsoluteDifference, false, 1, 5},
    {"ad + correction, 2 cameras, confident 5", depth::MatchingCost::kAbsoluteDifference, true, 2,
     5},
    {"ad, plane fill 0.05", depth::MatchingCost::kAbsoluteDifference, false, 1, 0, 0.05},
    {"ad, confident 5, plane fill 0.05", depth::MatchingCost::kAbsoluteDifference, false, 1, 5,
     0.05},
    {"ad + correction, 2 cameras, confident 5, plane fill 0.05",
     depth::MatchingCost::kAbsoluteDifference, true, 2, 5, 0.05},
    // The filter's reach: better on every noisy synthetic set, worse on blender-hall's ceiling
    // (docs/accuracy.md, "Where the error sits with noise").
    {"ad + correction, 2 cameras, confident 5, plane fill 0.05, sigma_s 20",
     depth::MatchingCost::kAbsoluteDifference, true, 2, 5, 0.05, 20},
    // The unconfident regions' planes from their rims (docs/accuracy.md, "Region planes").
    {"ad + correction, 2 cameras, confident 5, plane fill 0.05, sigma_s 20, region planes",
     depth::MatchingCost::kAbsoluteDifference, true, 2, 5, 0.05, 20, true},
    // The default with the confidence lowered beside depth steps without a colour step
    // (docs/accuracy.md, "Confidence"); the distances are the default's.
    {"ad + correction, 2 cameras, confident 5, plane fill 0.05, sigma_s 20, region planes, edge "
     "check",
     depth::MatchingCost::kAbsoluteDifference, true, 2, 5, 0.05, 20, true, true},
    // The matching images blurred first, with and without the region planes (docs/accuracy.md,
    // "Matching blur").
    {"ad + correction, 2 cameras, confident 5, plane fill 0.05, sigma_s 20, region planes, match "
     "blur 1",
     depth::MatchingCost::kAbsoluteDifference, true, 2, 5, 0.05, 20, true, false, 1.0},
    {"ad + correction, 2 cameras, confident 5, plane fill 0.05, sigma_s 20, match blur 1",
     depth::MatchingCost::kAbsoluteDifference, true, 2, 5, 0.05, 20, false, false, 1.0},
    // The default whose confidence also hears the pixel's raw curve where that puts the surface
    // nearer, so the fills replace what the filter carried over (docs/accuracy.md, "Confidence";
    // not the default: the fills' near patches on kaist-rig).
    {"ad + correction, 2 cameras, confident 5, plane fill 0.05, sigma_s 20, region planes, raw "
     "agreement 0.3",
     depth::MatchingCost::kAbsoluteDifference, true, 2, 5, 0.05, 20, true, false, 0, 0.3},
    // The large unconfident regions solved from their rims (docs/accuracy.md, "Membrane fill"),
    // after the default's fills, and after the blur's without the region planes.
    {"ad + correction, 2 cameras, confident 5, plane fill 0.05, sigma_s 20, region planes, "
     "membrane fill",
     depth::MatchingCost::kAbsoluteDifference, true, 2, 5, 0.05, 20, true, false, 0, 0, true},
    {"ad + correction, 2 cameras, confident 5, plane fill 0.05, sigma_s 20, match blur 1, "
     "membrane fill",
     depth::MatchingCost::kAbsoluteDifference, true, 2, 5, 0.05, 20, false, false, 1.0, 0, true},
};

// The synthetic rig's frames, through realistic lenses or not, with Gaussian sensor noise of
// `noise` 8-bit levels (new every frame) or none. Its renders are otherwise noise-free to the
// last level, which no camera is: the sets with noise show what a variant's gain on the clean
// frames owes to texture below one level (docs/accuracy.md, "Sensor noise").
AccuracySet synthetic_set(const AccuracySectionOptions& options, bool lenses, double noise,
                          int width, int height) {
  synthetic::SyntheticRigOptions rig_options;
  // Small matching resolutions (a smoke run) render small images too.
  if (options.resolution > 0) rig_options.image_size = std::min(1216, 2 * options.resolution);
  if (lenses) rig_options.photometric = synthetic::PhotometricOptions::realistic();
  rig_options.photometric.noise_sigma = noise;
  const synthetic::SyntheticRig rig(rig_options);
  std::string name = "synthetic";
  if (lenses) name += noise > 0 ? ", lenses" : ", realistic lenses";
  if (noise > 0) {
    char level[32];
    std::snprintf(level, sizeof level, ", noise %g", noise);
    name += level;
  }
  AccuracySet set{name, rig.rig(), {}, {2, 3}, rig.viewpoint(), {}};
  for (auto& mask : rig.masks()) set.masks.emplace_back(std::move(mask));
  for (int i = 0; i < options.frames; ++i) {
    synthetic::SyntheticFrame frame = rig.render(i, width, height);
    TruthFrame truth;
    for (auto& cam : frame.cameras) truth.images.push_back(std::move(cam.rgb));
    truth.rgb = std::move(frame.panorama.rgb);
    truth.inverse_distance = std::move(frame.panorama.inverse_distance);
    set.frames.push_back(std::move(truth));
  }
  return set;
}

std::optional<AccuracySet> dataset_set(const std::string& dir, int width, int height) {
  const Dataset dataset = Dataset::open(dir);
  AccuracySet set{"development set (" + std::filesystem::path(dir).filename().string() + ")",
                  dataset.rig(),
                  {},
                  dataset.hints().references,
                  dataset.hints().viewpoint,
                  {}};
  if (set.references.empty()) set.references = depth::DepthOptions{}.references;
  for (const auto& mask : dataset.masks())
    set.masks.emplace_back(mask ? std::optional<Gray8Image>(mask->clone()) : std::nullopt);
  for (const std::string& name : dataset.frames()) {
    Frame frame = dataset.load_frame(name);
    if (!frame.ground_truth) continue;
    if (frame.ground_truth->rgb.width() != width || frame.ground_truth->rgb.height() != height) {
      std::fprintf(stderr, "accuracy: %s: ground truth is not %dx%d, development set left out\n",
                   dir.c_str(), width, height);
      return std::nullopt;
    }
    TruthFrame truth{depth::rgb8_images(frame), std::move(frame.ground_truth->rgb),
                     std::move(frame.ground_truth->inverse_distance)};
    set.frames.push_back(std::move(truth));
  }
  return set;
}

struct Row {
  stitch::PanoramaMetrics mean;
  double mae_at_80 = 0;  // the confidence's: MAE of the 80 % most confident pixels
  double ause = 0;
  double ms = 0;         // median per frame, host wall time (correction included)
  double xavier_ms = 0;  // predicted GPU time of the frame
};

Row run(gpu::Context& context, const AccuracySet& set, const Variant& variant,
        const AccuracySectionOptions& options, int width, int height) {
  depth::DepthOptions depth_options;
  depth_options.references = set.references;
  depth_options.cost = variant.cost;
  depth_options.correct_photometry = variant.correct_photometry;
  depth_options.match_cameras = variant.match_cameras;
  depth_options.confident_sigma_s = variant.confident_sigma_s;
  depth_options.match_blur = variant.match_blur;
  depth_options.raw_agreement = variant.raw_agreement;
  if (variant.sigma_s > 0) depth_options.sigma_s = variant.sigma_s;
  if (options.resolution > 0)
    depth_options.matching_width = depth_options.matching_height = options.resolution;
  const Rig matching_rig =
      set.rig.resized(depth_options.matching_width, depth_options.matching_height);
  std::vector<std::optional<Gray8Image>> masks;
  for (const auto& mask : set.masks)
    masks.emplace_back(mask ? std::optional<Gray8Image>(mask->clone()) : std::nullopt);
  masks = depth::matching_masks(masks, depth_options);
  depth::DepthEstimator estimator(context, matching_rig, masks, depth_options);
  stitch::Stitcher stitcher(context, matching_rig, set.rig, set.references, masks,
                            {.panorama_width = width,
                             .panorama_height = height,
                             .viewpoint = set.viewpoint,
                             .min_distance = depth_options.min_distance,
                             .max_distance = depth_options.max_distance,
                             .plane_fill = variant.plane_fill,
                             .region_planes = variant.region_planes,
                             .edge_check = variant.edge_check,
                             .membrane_fill = variant.membrane_fill,
                             .temporal = std::nullopt});
  pipeline::GpuFrame gpu_frame(context, estimator, stitcher);
  std::optional<depth::PhotometricCorrector> photometry;
  if (variant.correct_photometry) photometry.emplace(matching_rig, masks);
  Row row;
  std::vector<double> ms;
  gpu::CommandLog log;
  for (const TruthFrame& frame : set.frames) {
    std::vector<Rgb8Image> full;
    for (const auto& im : frame.images) full.push_back(im.clone());
    const auto start = std::chrono::steady_clock::now();
    std::vector<Rgb8Image> matching = depth::matching_images(full, depth_options);
    std::vector<Rgb8Image> color = depth::reference_color_images(full, set.rig, set.references);
    const depth::PhotometryFit* fit = photometry ? &photometry->fit(views(matching)) : nullptr;
    log.clear();
    context.set_command_log(&log);
    stitch::Panorama pano = gpu_frame.run(views(matching), views(color), fit);
    context.set_command_log(nullptr);
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                     .count());
    const auto m =
        stitch::evaluate_panorama(pano.rgb, pano.distance, frame.rgb, frame.inverse_distance);
    const double n = double(set.frames.size());
    row.mean.mae += m.mae / n;
    row.mean.rmse += m.rmse / n;
    row.mean.bad_0_1 += m.bad_0_1 / n;
    row.mean.bad_0_4 += m.bad_0_4 / n;
    row.mean.psnr += m.psnr / n;
    row.mean.ssim += m.ssim / n;
    const stitch::Sparsification curve =
        stitch::sparsification(pano.distance, pano.confidence, frame.inverse_distance);
    row.mae_at_80 += curve.mae_at_80 / n;
    row.ause += curve.ause / n;
  }
  std::sort(ms.begin(), ms.end());
  row.ms = ms.empty() ? 0 : ms[ms.size() / 2];
  row.xavier_ms = predicted_xavier_ms(log);
  return row;
}

}  // namespace

void accuracy_section(gpu::Context& context, const AccuracySectionOptions& options, bool json) {
  const int width = options.resolution > 0 ? 2 * options.resolution : 2048;
  const int height = options.resolution > 0 ? options.resolution : 1024;
  std::vector<AccuracySet> sets;
  for (const double noise : {0.0, 1.0}) {
    sets.push_back(synthetic_set(options, false, noise, width, height));
    sets.push_back(synthetic_set(options, true, noise, width, height));
  }
  if (!options.dev_set.empty()) {
    if (auto set = dataset_set(options.dev_set, width, height)) sets.push_back(std::move(*set));
  }
  // The variant column is as wide as the longest name, so a longer name does not shift a row.
  int name_width = 0;
  for (const Variant& variant : kVariants)
    name_width = std::max(name_width, static_cast<int>(std::string_view(variant.name).size()));
  if (!json) {
    std::printf(
        "\nAccuracy of the variants (inverse distance in m^-1, means over the frames; ms: median "
        "wall time per frame here; Xavier: the cost model's GPU time, without host work; "
        "MAE@80: the MAE of the 80 %% most confident pixels; AUSE: the area between the "
        "confidence's sparsification curve and the oracle's)\n");
    std::printf("%-*s %-32s %8s %8s %7s %7s %8s %7s %8s %8s %8s %8s\n", name_width, "variant",
                "data", "MAE", "RMSE", ">0.1 %", ">0.4 %", "PSNR dB", "SSIM", "MAE@80", "AUSE",
                "ms", "Xavier");
  }
  for (const AccuracySet& set : sets) {
    for (const Variant& variant : kVariants) {
      const Row r = run(context, set, variant, options, width, height);
      if (json) {
        std::printf(
            "{\"kind\": \"accuracy\", \"variant\": \"%s\", \"data\": \"%s\", \"frames\": %zu, "
            "\"mae\": %.6f, \"rmse\": %.6f, \"bad_0_1\": %.6f, \"bad_0_4\": %.6f, \"psnr\": %.4f, "
            "\"ssim\": %.6f, \"mae_at_80\": %.6f, \"ause\": %.6f, \"ms\": %.1f, "
            "\"xavier_ms\": %.3f}\n",
            variant.name, set.name.c_str(), set.frames.size(), r.mean.mae, r.mean.rmse,
            r.mean.bad_0_1, r.mean.bad_0_4, r.mean.psnr, r.mean.ssim, r.mae_at_80, r.ause, r.ms,
            r.xavier_ms);
      } else {
        std::printf("%-*s %-32s %8.4f %8.4f %7.2f %7.2f %8.2f %7.3f %8.4f %8.4f %8.0f %8.2f\n",
                    name_width, variant.name, set.name.c_str(), r.mean.mae, r.mean.rmse,
                    100 * r.mean.bad_0_1, 100 * r.mean.bad_0_4, r.mean.psnr, r.mean.ssim,
                    r.mae_at_80, r.ause, r.ms, r.xavier_ms);
      }
      std::fflush(stdout);
    }
  }
}

}  // namespace omnisweep::tools
