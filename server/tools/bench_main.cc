// omnisweep-bench: GPU time per depth stage at several matching resolutions, and the ISB filter
// side by side with OpenCV's guided filter, fast bilateral solver and box filter on one
// synthetic cost volume (the paper's Table 2 on this machine), the codecs against 16-bit PNG
// (bench_codecs.cc), novel-view reprojection (bench_reproject.cc), MCAP recording
// (bench_record.cc) and streaming with and without DDS Security (bench_security.cc). A
// benchmark, not a test: it prints what it measured.
#include <fcntl.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/ximgproc/edge_filter.hpp>
#include <string>
#include <vector>

#include "client_sdk/tools/tool_main.h"
#include "omnisweep/gpu/context.h"
#include "omnisweep/image/image_io.h"
#include "server/depth/depth_estimator.h"
#include "server/depth/depth_fixtures.h"
#include "server/depth/depth_inputs.h"
#include "server/depth/depth_reference.h"
#include "server/tools/bench_accuracy.h"
#include "server/tools/bench_codecs.h"
#include "server/tools/bench_model.h"
#include "server/tools/bench_record.h"
#include "server/tools/bench_reproject.h"
#include "server/tools/bench_ros2.h"
#include "server/tools/bench_security.h"
#include "server/tools/bench_stats.h"
#include "server/tools/depth_flags.h"
#include "server/tools/stitch_flags.h"

namespace {

using namespace omnisweep;
using Clock = std::chrono::steady_clock;
using tools::median;

struct Accuracy {
  double mae = 0, bad_0_1 = 0, bad_0_4 = 0;
};

// Winner-takes-all (no post-filter) on a filtered volume, scored against the ground truth over
// the pixels inside the lens: the same scoring for every filter.
Accuracy score(const std::vector<float>& volume, const depth::DepthOptions& options,
               const FloatImage& inverse_gt, const Gray8Image& usable) {
  Accuracy a;
  long n = 0;
  for (int p = 0; p < inverse_gt.width() * inverse_gt.height(); ++p) {
    if (!usable.data()[p] || inverse_gt.data()[p] <= 0) continue;
    const float d =
        depth::winner_take_all_cpu(&volume[std::size_t(p) * options.num_candidates], options);
    const double e = std::abs(1.0 / d - inverse_gt.data()[p]);
    a.mae += e;
    a.bad_0_1 += e > 0.1;
    a.bad_0_4 += e > 0.4;
    ++n;
  }
  a.mae /= n;
  a.bad_0_1 /= n;
  a.bad_0_4 /= n;
  return a;
}

// OpenCV's fast bilateral solver prints its progress on stdout; this keeps the tables (and the
// --json rows) clean while it runs.
class SilenceStdout {
 public:
  SilenceStdout() : saved_(::dup(STDOUT_FILENO)) {
    std::fflush(stdout);
    const int null = ::open("/dev/null", O_WRONLY);
    ::dup2(null, STDOUT_FILENO);
    ::close(null);
  }
  ~SilenceStdout() {
    std::fflush(stdout);
    ::dup2(saved_, STDOUT_FILENO);
    ::close(saved_);
  }
  SilenceStdout(const SilenceStdout&) = delete;
  SilenceStdout& operator=(const SilenceStdout&) = delete;

 private:
  int saved_;
};

// Applies `filter_slice` to every candidate slice of a pixel-major volume.
template <typename F>
std::vector<float> per_slice(const std::vector<float>& volume, int width, int height, int n,
                             F&& filter_slice) {
  std::vector<float> out(volume.size());
  cv::Mat slice(height, width, CV_32F), filtered;
  for (int i = 0; i < n; ++i) {
    for (int p = 0; p < width * height; ++p) slice.at<float>(p) = volume[std::size_t(p) * n + i];
    filter_slice(slice, filtered);
    for (int p = 0; p < width * height; ++p) out[std::size_t(p) * n + i] = filtered.at<float>(p);
  }
  return out;
}

// 1. GPU time per stage, both references, at each resolution.
void stage_section(gpu::Context& context, const std::vector<int>& resolutions, int iterations,
                   bool json) {
  // Winner-takes-all runs inside the filter's last pass (isb_upsample.comp), so "filter" has it.
  const std::vector<std::string> stages = {"sweep_cost", "filter", "post_filter"};
  std::map<int, std::map<std::string, double>> ms;
  std::map<int, double> memory_mib;
  for (int size : resolutions) {
    const auto scene = depth::fixtures::render_depth_case(size);
    depth::DepthOptions options;
    options.matching_width = options.matching_height = size;
    depth::DepthEstimator estimator(context, scene.rig.rig(), scene.usable, options);
    memory_mib[size] = double(estimator.gpu_bytes()) / (1 << 20);
    std::map<std::string, std::vector<double>> runs;
    for (int it = 0; it < iterations + 1; ++it) {
      const auto result = estimator.estimate(scene.image_views());
      if (it == 0) continue;  // warm-up
      for (const auto& [stage, t] : result.stage_ms) runs[stage].push_back(t);
    }
    for (const auto& [stage, t] : runs) ms[size][stage] = median(t);
    for (const auto& stage : stages) {
      if (json)
        std::printf("{\"kind\": \"stage\", \"stage\": \"%s\", \"resolution\": %d, \"ms\": %.3f}\n",
                    stage.c_str(), size, ms[size][stage]);
    }
  }
  if (!json) {
    std::printf("GPU time per stage (ms, both references, median of %d)\n%-12s", iterations,
                "stage");
    for (int size : resolutions) std::printf(" %8d^2", size);
    for (std::size_t i = 1; i < resolutions.size(); ++i)
      std::printf("  x(%d/%d)", resolutions[i], resolutions[i - 1]);
    std::printf("\n");
    auto row = [&](const std::string& name, auto value) {
      std::printf("%-12s", name.c_str());
      for (int size : resolutions) std::printf(" %10.1f", value(size));
      for (std::size_t i = 1; i < resolutions.size(); ++i) {
        std::printf("  %9.2f", value(resolutions[i]) / value(resolutions[i - 1]));
      }
      std::printf("\n");
    };
    for (const auto& stage : stages) row(stage, [&](int s) { return ms[s][stage]; });
    row("total", [&](int s) {
      double t = 0;
      for (const auto& stage : stages) t += ms[s][stage];
      return t;
    });
    row("memory MiB", [&](int s) { return memory_mib[s]; });
    std::printf("(pixels grow 4x per step: linear time means a ratio near 4)\n\n");
  }
}

// 2. The filters side by side on one raw cost volume (reference 2, synthetic frame 0).
void filter_section(gpu::Context& context, int filter_resolution, int iterations, bool skip_fbs,
                    bool json) {
  const int size = filter_resolution;
  const auto scene = depth::fixtures::render_depth_case(size);
  depth::DepthOptions options;
  options.matching_width = options.matching_height = size;
  depth::DepthEstimator estimator(context, scene.rig.rig(), scene.usable, options);
  const int n = options.num_candidates, ref = options.references[0];
  const std::vector<float> raw = estimator.cost_volume(scene.image_views(), 0, false);
  const std::vector<std::uint32_t> guide = depth::ycbcr_guide_cpu(scene.images[ref]);
  cv::Mat guide_mat(size, size, CV_8UC3);
  for (int p = 0; p < size * size; ++p) {
    guide_mat.at<cv::Vec3b>(p) =
        cv::Vec3b(guide[p] & 255, (guide[p] >> 8) & 255, (guide[p] >> 16) & 255);
  }
  const FloatImage& gt = scene.inverse_gt[ref];
  const Gray8Image& usable = *scene.usable[ref];

  struct Row {
    std::string method, parameters;
    double ms;
    Accuracy accuracy;
  };
  std::vector<Row> rows;
  {  // ISB on the GPU, filter dispatches only (GPU timestamps).
    const depth::VolumeLayout layout = depth::plan_volume(context, size, size, n);
    depth::CostVolume volume(context, size, size, layout);
    gpu::Buffer guide_buffer(context, guide.size() * 4);
    depth::IsbFilter filter(context, size, size, layout);
    gpu::Sequence seq(context);
    std::vector<double> times;
    std::vector<float> filtered;
    for (int it = 0; it < iterations + 1; ++it) {
      volume.upload(raw, n);
      guide_buffer.upload(std::span<const std::uint32_t>(guide));
      seq.begin();
      seq.begin_stage("isb");
      filter.record(seq, guide_buffer, volume, {options.sigma_i, options.scaled_sigma_s()});
      seq.submit_and_wait();
      if (it > 0) times.push_back(seq.stage_ms().empty() ? 0.0 : seq.stage_ms()[0].second);
    }
    filtered = volume.download(n);
    rows.push_back({"isb", "sigma_I 10, sigma_s 25 (x res/1024), GPU", median(times),
                    score(filtered, options, gt, usable)});
  }
  auto time_cpu = [&](auto&& make_filtered) {
    std::vector<double> times;
    std::vector<float> out;
    for (int it = 0; it < iterations; ++it) {
      const auto start = Clock::now();
      out = make_filtered();
      times.push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
    }
    return std::make_pair(median(times), std::move(out));
  };
  {
    const int radius = std::max(1, 8 * size / 1024);
    auto [t, out] = time_cpu([&] {
      const auto gf = cv::ximgproc::createGuidedFilter(guide_mat, radius, 100.0);
      return per_slice(raw, size, size, n, [&](const cv::Mat& s, cv::Mat& d) { gf->filter(s, d); });
    });
    rows.push_back({"guided",
                    "OpenCV ximgproc, radius " + std::to_string(radius) + ", eps 100, CPU", t,
                    score(out, options, gt, usable)});
  }
  if (!skip_fbs) {
    const SilenceStdout quiet;
    auto [t, out] = time_cpu([&] {
      const auto fbs =
          cv::ximgproc::createFastBilateralSolverFilter(guide_mat, 8.0 * size / 1024, 8, 8);
      const cv::Mat confidence(size, size, CV_32F, cv::Scalar(1.0f));
      return per_slice(raw, size, size, n,
                       [&](const cv::Mat& s, cv::Mat& d) { fbs->filter(s, confidence, d); });
    });
    rows.push_back({"fbs", "OpenCV ximgproc fast bilateral solver, defaults, CPU", t,
                    score(out, options, gt, usable)});
  }
  {
    const int k = std::max(3, 2 * (8 * size / 1024) + 1);
    auto [t, out] = time_cpu([&] {
      return per_slice(raw, size, size, n, [&](const cv::Mat& s, cv::Mat& d) {
        cv::boxFilter(s, d, -1, cv::Size(k, k));
      });
    });
    rows.push_back({"box",
                    "OpenCV boxFilter " + std::to_string(k) + "x" + std::to_string(k) + ", CPU", t,
                    score(out, options, gt, usable)});
  }
  rows.push_back({"none", "raw cost", 0.0, score(raw, options, gt, usable)});

  if (json) {
    for (const Row& r : rows) {
      if (r.method == "none") continue;
      std::printf(
          "{\"kind\": \"filter\", \"method\": \"%s\", \"ms\": %.3f, \"mae\": %.5f, \"bad_0_1\": "
          "%.5f, \"bad_0_4\": %.5f}\n",
          r.method.c_str(), r.ms, r.accuracy.mae, r.accuracy.bad_0_1, r.accuracy.bad_0_4);
    }
    return;
  }
  std::printf(
      "Filters on the same cost volume (%dx%d x %d candidates, reference %d), scored by "
      "winner-takes-all\n"
      "without post-filter against the ground truth (inverse distance, m^-1)\n",
      size, size, n, ref);
  std::printf("%-8s %10s %8s %8s %8s  %s\n", "method", "ms", "MAE", ">0.1 %", ">0.4 %",
              "parameters");
  for (const Row& r : rows) {
    std::printf("%-8s %10.1f %8.4f %8.2f %8.2f  %s\n", r.method.c_str(), r.ms, r.accuracy.mae,
                100 * r.accuracy.bad_0_1, 100 * r.accuracy.bad_0_4, r.parameters.c_str());
  }
  const double isb_ms = rows[0].ms, guided_ms = rows[1].ms;
  std::printf("ISB is %.1fx faster than the guided filter here\n", guided_ms / isb_ms);
}

int run(int argc, char** argv) {
  CLI::App app{
      "Benchmark the GPU depth stages and the ISB filter against OpenCV's edge-aware filters."};
  std::vector<int> resolutions = {256, 512, 1024};
  int filter_resolution = 1024, iterations = 3;
  bool json = false, skip_fbs = false;
  std::vector<std::string> sections = {"model",     "accuracy", "stages",   "filters", "codecs",
                                       "reproject", "record",   "security", "ros2"};
  int model_resolution = 0;
  std::string kaist_dir;
  if (const char* shared = std::getenv("OMNISWEEP_SHARED_DIR"))
    kaist_dir = std::string(shared) + "/data/kaist-rig";
  if (kaist_dir.empty() && std::filesystem::exists("../shared/data/kaist-rig"))
    kaist_dir = "../shared/data/kaist-rig";
  std::string device;
  app.add_option("--resolutions", resolutions, "Matching resolutions (square) for the stage table")
      ->check(CLI::Range(16, 4096));
  app.add_option("--filter-resolution", filter_resolution, "Resolution of the filter comparison")
      ->check(CLI::Range(16, 4096));
  app.add_option("--iterations", iterations, "Runs per measurement (the median is reported)")
      ->check(CLI::Range(1, 100));
  app.add_option(
      "--vk-device", device,
      "Vulkan device: index or name substring (default: OMNISWEEP_VK_DEVICE, else the best)");
  app.add_flag("--json", json, "One JSON object per row instead of tables");
  app.add_flag("--skip-fbs", skip_fbs, "Leave out the (slow) fast bilateral solver");
  app.add_option("--sections", sections,
                 "What to measure: model, accuracy, stages, filters, codecs, reproject, record, "
                 "security, ros2 "
                 "(default: all)")
      ->check(CLI::IsMember({"model", "accuracy", "stages", "filters", "codecs", "reproject",
                             "record", "security", "ros2"}))
      ->delimiter(',');
  app.add_option("--model-resolution", model_resolution,
                 "Matching resolution of the cost model's frame (panorama 2R x R; default: the "
                 "defaults, 1024^2 and 2048x1024)")
      ->check(CLI::Range(16, 4096));
  app.add_option("--kaist", kaist_dir,
                 "kaist-rig dataset for the codec comparison (default ../shared/data/kaist-rig)");
  tools::AccuracySectionOptions accuracy;
  if (const char* shared = std::getenv("OMNISWEEP_SHARED_DIR"))
    accuracy.dev_set = std::string(shared) + "/data/blender-hall";
  if (accuracy.dev_set.empty() && std::filesystem::exists("../shared/data/blender-hall"))
    accuracy.dev_set = "../shared/data/blender-hall";
  app.add_option("--accuracy-frames", accuracy.frames,
                 "Synthetic frames per set in the accuracy section")
      ->check(CLI::Range(1, 100));
  app.add_option("--accuracy-resolution", accuracy.resolution,
                 "Matching resolution of the accuracy section (panorama 2R x R; default: the "
                 "defaults); the development set needs the default")
      ->check(CLI::Range(16, 4096));
  app.add_option("--dev-set", accuracy.dev_set,
                 "Development dataset with ground truth for the accuracy section (default "
                 "../shared/data/blender-hall; empty: none)");
  depth::DepthOptions model_options;
  double model_plane_fill = 0.0;
  bool model_region_planes = false, model_edge_check = false, model_membrane_fill = false;
  tools::add_matching_cost_flags(app, model_options, {&model_plane_fill, &model_region_planes});
  tools::add_plane_fill_flag(app, model_plane_fill);
  tools::add_region_planes_flag(app, model_region_planes);
  tools::add_edge_check_flag(app, model_edge_check);
  tools::add_membrane_fill_flag(app, model_membrane_fill);
  CLI11_PARSE(app, argc, argv);

  gpu::Context context(tools::context_options(device));
  const auto& info = context.info();
  if (!json) {
    std::printf("device: %s (%s, Vulkan %s), maxStorageBufferRange %llu MiB\n\n", info.name.c_str(),
                info.type.c_str(), info.api_version.c_str(),
                static_cast<unsigned long long>(info.max_storage_buffer_range >> 20));
  }

  const auto want = [&](const char* section) {
    return std::find(sections.begin(), sections.end(), section) != sections.end();
  };
  if (want("model"))
    tools::model_section(context, model_options, model_plane_fill, model_region_planes,
                         model_edge_check, model_membrane_fill, model_resolution, json);
  if (want("accuracy")) tools::accuracy_section(context, accuracy, json);
  if (want("stages")) stage_section(context, resolutions, iterations, json);
  if (want("filters")) filter_section(context, filter_resolution, iterations, skip_fbs, json);
  if (want("codecs")) tools::codec_section(context, kaist_dir, json);
  if (want("ros2")) tools::ros2_section(context, json);
  if (want("reproject")) tools::reproject_section(context, iterations, json);
  if (want("record")) tools::record_section(json);
  if (want("security")) tools::security_section(OMNISWEEP_SOURCE_DIR, json);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return omnisweep::tools::run_tool("omnisweep-bench", argc, argv, run);
}
