// The frame cost model. Its inputs are counted, not typed in: the dispatches, barriers, host
// round trips and bound bytes that DepthEstimator and Stitcher record for one frame
// (gpu::CommandLog). Its assumptions, stated once here and in docs/performance.md:
//   - a dispatch moves the bytes of what it binds once through global memory (an upper bound for
//     kernels that touch part of a binding, a lower bound for ones that read a texel repeatedly
//     past the caches), at kBandwidthEfficiency of the device's peak bandwidth;
//   - every dispatch costs kDispatchUs of launch, every barrier kBarrierUs of drain, every host
//     round trip kRoundTripUs (submit, fence wait, wake-up);
//   - arithmetic is not yet modelled (the kernels' FLOPs per invocation are not counted), so the
//     prediction is the memory-bound time: a lower bound where a kernel is compute-bound.
#include "server/tools/bench_model.h"

#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "omnisweep/gpu/command_log.h"
#include "omnisweep/reproject/reprojector.h"
#include "server/depth/depth_estimator.h"
#include "server/depth/depth_inputs.h"
#include "server/depth/photometric_model.h"
#include "server/pipeline/gpu_frame.h"
#include "server/stitch/stitcher.h"
#include "server/synthetic/synthetic_rig.h"
#include "server/tools/depth_flags.h"

namespace omnisweep::tools {
namespace {

constexpr double kBandwidthEfficiency = 0.75;
constexpr double kDispatchUs = 4.0, kBarrierUs = 2.0, kRoundTripUs = 50.0;

struct DeviceProfile {
  const char* name;
  double bandwidth_gb_s;  // peak DRAM bandwidth
  double tflops;          // peak fp32 (reported; not yet part of the prediction)
};

constexpr DeviceProfile kProfiles[] = {
    {"Jetson AGX Xavier", 137.0, 1.4},
    {"Jetson AGX Orin 64GB", 204.8, 5.3},
    {"RTX 4090", 1008.0, 82.0},
    {"H100 SXM", 3350.0, 67.0},
    {"H200", 4800.0, 67.0},
};

double predicted_ms(const gpu::CommandTotals& t, const DeviceProfile& device) {
  const double memory_s = double(t.bound_bytes + t.upload_bytes + t.download_bytes) /
                          (kBandwidthEfficiency * device.bandwidth_gb_s * 1e9);
  const double overhead_us = kDispatchUs * double(t.dispatches) + kBarrierUs * double(t.barriers) +
                             kRoundTripUs * double(t.round_trips);
  return memory_s * 1e3 + overhead_us * 1e-3;
}

// Prints the log's stages and its total as a table (or JSON rows of `kind`).
void print_log(const gpu::CommandLog& log, const char* kind, const std::string& title,
               const std::string& frame_name, bool json) {
  std::vector<std::string> stages = log.stages();
  stages.push_back("");  // the frame
  if (!json) {
    std::printf("\n%s (%s)\n", title.c_str(), frame_name.c_str());
    std::printf("%-14s %10s %9s %11s %12s %12s", "stage", "dispatches", "barriers", "round trips",
                "bound MB", "host MB");
    for (const auto& d : kProfiles) std::printf(" %12.12s", d.name);
    std::printf("   (predicted ms)\n");
  }
  for (const std::string& stage : stages) {
    const gpu::CommandTotals t = log.totals(stage);
    const std::string name = stage.empty() ? "frame" : stage;
    if (json) {
      std::printf(
          "{\"kind\": \"%s\", \"frame\": \"%s\", \"stage\": \"%s\", \"dispatches\": %llu, "
          "\"barriers\": %llu, \"round_trips\": %llu, \"bound_bytes\": %llu, \"upload_bytes\": "
          "%llu, \"download_bytes\": %llu, \"invocations\": %llu",
          kind, frame_name.c_str(), name.c_str(), static_cast<unsigned long long>(t.dispatches),
          static_cast<unsigned long long>(t.barriers),
          static_cast<unsigned long long>(t.round_trips),
          static_cast<unsigned long long>(t.bound_bytes),
          static_cast<unsigned long long>(t.upload_bytes),
          static_cast<unsigned long long>(t.download_bytes),
          static_cast<unsigned long long>(t.invocations));
      std::printf(", \"predicted_ms\": {");
      for (const auto& d : kProfiles)
        std::printf("%s\"%s\": %.3f", &d == kProfiles ? "" : ", ", d.name, predicted_ms(t, d));
      std::printf("}}\n");
      continue;
    }
    std::printf("%-14s %10llu %9llu %11llu %12.1f %12.1f", name.c_str(),
                static_cast<unsigned long long>(t.dispatches),
                static_cast<unsigned long long>(t.barriers),
                static_cast<unsigned long long>(t.round_trips), double(t.bound_bytes) * 1e-6,
                double(t.upload_bytes + t.download_bytes) * 1e-6);
    for (const auto& d : kProfiles) std::printf(" %12.2f", predicted_ms(t, d));
    std::printf("\n");
  }
}

// One VR frame on the client: a stereo pair of 1440x1600 pinhole views (90 degrees across), the
// eyes 6.4 cm apart and their midpoint 5 cm from the panorama's centre, rendered by the SDK's
// Reprojector from a 2048x1024 RGB-D panorama (the second such frame; the first builds the
// warpers), views downloaded.
void vr_frame(gpu::Context& context, bool json) {
  const synthetic::SyntheticRig rig(synthetic::SyntheticRigOptions{.image_size = 64});
  const synthetic::RenderedImage pano = rig.render_panorama_at(0, rig.viewpoint(), 2048, 1024);
  reproject::Reprojector reprojector(context);
  reprojector.set_panorama(pano.rgb, reciprocal_or_zero(pano.inverse_distance), rig.viewpoint());
  const PinholeCamera<double> eye = reproject::pinhole_for_fov(1440, 1600, 90);
  gpu::CommandLog log;
  for (int run = 0; run < 2; ++run) {
    log.clear();
    context.set_command_log(&log);
    for (const double side : {-0.032, 0.032}) {
      const Rigid3d pose(Eigen::Quaterniond::Identity(),
                         rig.viewpoint() + Eigen::Vector3d(0.05 + side, 0, 0));
      reprojector.render_pinhole(pose, eye, 1440, 1600);
    }
    context.set_command_log(nullptr);
  }
  print_log(log, "model_vr", "Client cost model: one stereo VR frame as the Reprojector records it",
            "2 x 1440x1600 pinhole, 6.4 cm apart, 5 cm from the centre", json);
}

// Records into `log` the second of two frames of `options` and `stitch_options` as
// omnisweep-process submits them (one submission, depth staying on the GPU); the first also
// computes what is kept for a calibration and pose (the inpainting directions), which a stream
// does once.
void record_frame(gpu::Context& context, const synthetic::SyntheticRig& rig,
                  const std::vector<Rgb8Image>& images, const depth::DepthOptions& options,
                  const stitch::StitchOptions& stitch_options, gpu::CommandLog& log) {
  const Rig& full_rig = rig.rig();
  const Rig matching_rig = full_rig.resized(options.matching_width, options.matching_height);
  std::vector<std::optional<Gray8Image>> masks;
  for (auto& m : rig.masks()) masks.emplace_back(std::move(m));
  masks = depth::matching_masks(masks, options);
  depth::DepthEstimator estimator(context, matching_rig, masks, options);
  stitch::Stitcher stitcher(context, matching_rig, full_rig, options.references, masks,
                            stitch_options);
  const auto matching = depth::matching_images(images, options);
  std::vector<Rgb8Image> own;  // reference_color_images takes the references' images
  for (const Rgb8Image& image : images) own.push_back(image.clone());
  const auto color = depth::reference_color_images(own, full_rig, options.references);
  pipeline::GpuFrame gpu_frame(context, estimator, stitcher);
  // With the photometric correction, its fit (on the host, not recorded) and its dispatch (the
  // frame's first, recorded), as omnisweep-process runs it.
  std::optional<depth::PhotometricCorrector> photometry;
  if (options.correct_photometry) photometry.emplace(matching_rig, masks);
  const depth::PhotometryFit* fit = photometry ? &photometry->fit(views(matching)) : nullptr;
  for (int run = 0; run < 2; ++run) {
    log.clear();
    context.set_command_log(&log);
    gpu_frame.run(views(matching), views(color), fit);
    context.set_command_log(nullptr);
  }
}

// Whether two settings agree in every variant that a method sets (depth::Method), and in the
// edge check, the membrane fill and the matching images' blur.
bool same_variants(const depth::DepthOptions& a, const stitch::StitchOptions& a_stitch,
                   const depth::DepthOptions& b, const stitch::StitchOptions& b_stitch) {
  return a.cost == b.cost && a.correct_photometry == b.correct_photometry &&
         a.match_cameras == b.match_cameras && a.confident_sigma_s == b.confident_sigma_s &&
         a.sigma_s == b.sigma_s && a.match_blur == b.match_blur &&
         a_stitch.plane_fill == b_stitch.plane_fill &&
         a_stitch.region_planes == b_stitch.region_planes &&
         a_stitch.edge_check == b_stitch.edge_check &&
         a_stitch.membrane_fill == b_stitch.membrane_fill;
}

// The frame's predicted time over the paper's frame's, per device, side by side: the time
// condition of a new default (docs/accuracy.md, "Defaults": at most 1.20 on the Xavier).
void print_against_paper(const gpu::CommandLog& log, const gpu::CommandLog& paper, bool json) {
  const gpu::CommandTotals frame = log.totals(""), paper_frame = paper.totals("");
  if (json) {
    std::printf("{\"kind\": \"model_against_paper\", \"ratio\": {");
    for (const auto& d : kProfiles)
      std::printf("%s\"%s\": %.4f", &d == kProfiles ? "" : ", ", d.name,
                  predicted_ms(frame, d) / predicted_ms(paper_frame, d));
    std::printf("}, \"paper_ms\": {");
    for (const auto& d : kProfiles)
      std::printf("%s\"%s\": %.3f", &d == kProfiles ? "" : ", ", d.name,
                  predicted_ms(paper_frame, d));
    std::printf("}}\n");
    return;
  }
  std::printf("\nAgainst the paper's frame (--method paper), recorded in the same run\n");
  std::printf("%-14s %10s %9s %11s %12s %12s", "", "", "", "", "", "");
  for (const auto& d : kProfiles) std::printf(" %12.12s", d.name);
  std::printf("\n%-14s %10llu %9llu %11llu %12.1f %12.1f", "paper frame",
              static_cast<unsigned long long>(paper_frame.dispatches),
              static_cast<unsigned long long>(paper_frame.barriers),
              static_cast<unsigned long long>(paper_frame.round_trips),
              double(paper_frame.bound_bytes) * 1e-6,
              double(paper_frame.upload_bytes + paper_frame.download_bytes) * 1e-6);
  for (const auto& d : kProfiles) std::printf(" %12.2f", predicted_ms(paper_frame, d));
  std::printf("   (predicted ms)\n%-14s %59s", "ratio", "");
  for (const auto& d : kProfiles)
    std::printf(" %11.3fx", predicted_ms(frame, d) / predicted_ms(paper_frame, d));
  std::printf("   (a new default: at most 1.20x on the Xavier)\n");
}

}  // namespace

double predicted_xavier_ms(const gpu::CommandLog& log) {
  return predicted_ms(log.totals(""), kProfiles[0]);
}

void model_section(gpu::Context& context, depth::DepthOptions options, double plane_fill,
                   bool region_planes, bool edge_check, bool membrane_fill, int resolution,
                   bool json) {
  stitch::StitchOptions stitch_options;
  stitch_options.plane_fill = plane_fill;
  stitch_options.region_planes = region_planes;
  stitch_options.edge_check = edge_check;
  stitch_options.membrane_fill = membrane_fill;
  if (resolution > 0) {
    options.matching_width = options.matching_height = resolution;
    stitch_options.panorama_width = 2 * resolution;
    stitch_options.panorama_height = resolution;
  }
  // One rendered frame of the synthetic rig for both recordings (rendering it is most of the
  // section's host time, under the sanitizers most of all).
  const synthetic::SyntheticRig rig;
  synthetic::SyntheticFrame frame = rig.render(0, 8, 4);
  std::vector<Rgb8Image> images;
  for (auto& camera : frame.cameras) images.push_back(std::move(camera.rgb));
  gpu::CommandLog log;
  record_frame(context, rig, images, options, stitch_options, log);

  const std::string frame_name = std::to_string(options.matching_width) + "^2 matching, " +
                                 std::to_string(options.num_candidates) + " candidates, " +
                                 std::to_string(stitch_options.panorama_width) + "x" +
                                 std::to_string(stitch_options.panorama_height) + " panorama";
  if (!json) {
    std::printf(
        "\nassumed: bound bytes once at %.0f %% of peak bandwidth; %.0f us per dispatch, "
        "%.0f us per barrier, %.0f us per host round trip; arithmetic not modelled\n",
        100 * kBandwidthEfficiency, kDispatchUs, kBarrierUs, kRoundTripUs);
  }
  print_log(log, "model", "Frame cost model: a frame as the estimator and stitcher record it",
            frame_name, json);
  // The paper's method on the same frame (the method table's settings, as --method paper sets
  // them; no edge check and no blur of the matching images, which no method sets).
  depth::DepthOptions paper_options = options;
  stitch::StitchOptions paper_stitch = stitch_options;
  paper_stitch.edge_check = false;
  paper_stitch.membrane_fill = false;
  paper_options.match_blur = 0;
  apply_method(*depth::method_named("paper"), paper_options,
               {&paper_stitch.plane_fill, &paper_stitch.region_planes});
  if (!same_variants(options, stitch_options, paper_options, paper_stitch)) {
    gpu::CommandLog paper_log;
    record_frame(context, rig, images, paper_options, paper_stitch, paper_log);
    print_against_paper(log, paper_log, json);
  }
  vr_frame(context, json);
}

}  // namespace omnisweep::tools
