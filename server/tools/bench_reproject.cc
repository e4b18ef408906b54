#include "server/tools/bench_reproject.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "omnisweep/reproject/reprojector.h"
#include "server/synthetic/synthetic_rig.h"
#include "server/tools/bench_stats.h"

namespace omnisweep::tools {
namespace {

using Clock = std::chrono::steady_clock;

}  // namespace

void reproject_section(gpu::Context& context, int iterations, bool json) {
  constexpr int kWidth = 2048, kHeight = 1024;
  const synthetic::SyntheticRig rig(synthetic::SyntheticRigOptions{.image_size = 64});
  const synthetic::RenderedImage pano = rig.render_panorama_at(0, rig.viewpoint(), kWidth, kHeight);
  const FloatImage distance = reciprocal_or_zero(pano.inverse_distance);
  reproject::Reprojector reprojector(context);
  reprojector.set_panorama(pano.rgb, distance, rig.viewpoint());

  struct Row {
    std::string target;
    double offset_m, gpu_ms, wall_ms;
    int passes;
  };
  std::vector<Row> rows;
  const auto measure = [&](const std::string& target, double offset,
                           const std::function<reproject::View(const Rigid3d&)>& render) {
    const Rigid3d pose(Eigen::Quaterniond::Identity(),
                       rig.viewpoint() + Eigen::Vector3d(offset, 0, 0));
    std::vector<double> gpu, wall;
    int passes = 0;
    for (int it = 0; it < iterations + 1; ++it) {  // the first run builds the warper
      const auto start = Clock::now();
      passes = render(pose).inpaint_passes;
      if (it == 0) continue;
      wall.push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
      gpu.push_back(reprojector.last_gpu_ms());
    }
    rows.push_back({target, offset, median(gpu), median(wall), passes});
  };
  const PinholeCamera<double> eye = reproject::pinhole_for_fov(1024, 1024, 90);
  for (const double offset : {0.05, 0.20}) {
    measure("pinhole 1024x1024, 90 deg", offset,
            [&](const Rigid3d& pose) { return reprojector.render_pinhole(pose, eye, 1024, 1024); });
    measure("panorama 2048x1024", offset, [&](const Rigid3d& pose) {
      return reprojector.render_panorama(pose, kWidth, kHeight);
    });
  }

  if (json) {
    for (const Row& r : rows) {
      std::printf(
          "{\"kind\": \"reproject\", \"target\": \"%s\", \"offset_m\": %.2f, \"gpu_ms\": %.2f, "
          "\"wall_ms\": %.2f, \"inpaint_passes\": %d}\n",
          r.target.c_str(), r.offset_m, r.gpu_ms, r.wall_ms, r.passes);
    }
    return;
  }
  std::printf(
      "\nReprojection of a %dx%d RGB-D panorama (synthetic ground truth), median of %d runs\n",
      kWidth, kHeight, iterations);
  std::printf("%-28s %8s %10s %10s %8s\n", "target", "offset", "GPU ms", "wall ms", "passes");
  for (const Row& r : rows) {
    std::printf("%-28s %6.0fcm %10.1f %10.1f %8d\n", r.target.c_str(), 100 * r.offset_m, r.gpu_ms,
                r.wall_ms, r.passes);
  }
  std::printf("(wall ms includes downloading the colour and distance of the view)\n");
}

}  // namespace omnisweep::tools
