// RegionPlanes: the region planes on the GPU (region_planes.h), the region_*.comp kernels.
#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "omnisweep/gpu/shaders.h"
#include "server/stitch/panorama_rays.h"
#include "server/stitch/region_planes.h"
#include "server/stitch/region_planes_math.h"

namespace omnisweep::stitch {
namespace {

// region_planes.glsl's push constants.
struct RegionPush {
  std::uint32_t width, height;
  std::int32_t block, blocks_x, blocks_y, rim, min_pixels, max_regions, max_planes, draws,
      min_inliers, min_inlier_fraction;
  float fill_below, support, tau, inv_d_min, inv_d_max;
  std::int32_t plane, phase;
  float surround_cos;
};

gpu::Buffer ray_table(gpu::Context& context, int width, int height) {
  const std::vector<float> table = panorama_ray_table(width, height);
  gpu::Buffer buffer(context, table.size() * 4);
  buffer.upload(std::span<const float>(table));
  return buffer;
}

gpu::KernelLayout layout(std::uint32_t buffers, std::array<std::uint32_t, 3> local) {
  return gpu::KernelLayout::storage_buffers(buffers, sizeof(RegionPush), local);
}

constexpr std::array<std::uint32_t, 3> kPerBlock = {8, 8, 1};

// The regions' records, in uints: region_planes.glsl's kHeader and kRecord (keep in step).
constexpr std::uint64_t kRegionsHeader = 4, kRegionRecord = 9;
// region_ransac_step.comp keeps consecutive planes' alive lists and scores in two halves.
constexpr std::uint64_t kRansacHalves = 2;

}  // namespace

RegionPlanes::RegionPlanes(gpu::Context& context, int width, int height,
                           const RegionPlaneParams& params, double min_distance,
                           double max_distance)
    : width_(width),
      height_(height),
      params_((params.check(), params)),
      min_distance_(min_distance),
      max_distance_(max_distance),
      blocks_x_((width + params.block - 1) / params.block),
      blocks_y_((height + params.block - 1) / params.block),
      table_(ray_table(context, width, height)),
      blocks_(context, std::uint64_t(blocks_x_) * blocks_y_ * 16),
      parent_(context, std::uint64_t(blocks_x_) * blocks_y_ * 4),
      sizes_(context, std::uint64_t(blocks_x_) * blocks_y_ * 4),
      slots_(context, std::uint64_t(blocks_x_) * blocks_y_ * 4),
      regions_(context, 4 * (kRegionsHeader + kRegionRecord * kRegionPlaneMaxRegions)),
      histogram_(context, std::uint64_t(params.max_regions) * 256 * 4),
      candidates_(context, 8 * std::uint64_t(kRegionPlaneCandidates) * params.max_regions),
      sample_(context, 16 * std::uint64_t(kRegionPlaneSample) * params.max_regions),
      alive_(context, kRansacHalves * 4 * kRegionPlaneSample * params.max_regions),
      tags_(context, 4 * std::uint64_t(kRegionPlaneSample) * params.max_regions),
      scores_(context, kRansacHalves * 16 * params.draws * params.max_regions),
      planes_(context, 16 * std::uint64_t(kRegionPlaneMaxPlanes) * params.max_regions),
      surround_(context, std::uint64_t(blocks_x_) * blocks_y_ * 8),
      blocks_kernel_(context, gpu::Shader::kRegionBlocks, layout(5, kPerBlock)),
      merge_(context, gpu::Shader::kRegionMerge, layout(1, kPerBlock)),
      flatten_(context, gpu::Shader::kRegionFlatten, layout(3, kPerBlock)),
      number_(context, gpu::Shader::kRegionNumber, layout(5, {1024, 1, 1})),
      support_(context, gpu::Shader::kRegionSupport, layout(6, kPerBlock)),
      threshold_(context, gpu::Shader::kRegionThreshold,
                 layout(2, {std::uint32_t(kRegionPlaneMaxRegions), 1, 1})),
      sample_kernel_(context, gpu::Shader::kRegionSample,
                     layout(7, {std::uint32_t(kRegionPlaneCandidates / 2), 1, 1})),
      step_(context, gpu::Shader::kRegionRansacStep, layout(6, {256, 1, 1})),
      surround_kernel_(context, gpu::Shader::kRegionSurround, layout(7, kPerBlock)),
      apply_(context, gpu::Shader::kRegionApply, layout(5, {16, 16, 1})) {
  if (width < 1 || height < 1)
    throw std::invalid_argument("region planes: the panorama is " + std::to_string(width) + "x" +
                                std::to_string(height));
  if (!(min_distance > 0 && max_distance > min_distance))
    throw std::invalid_argument("region planes: the distance range must be 0 < min < max");
}

void RegionPlanes::record(gpu::Sequence& seq, gpu::Buffer& distance,
                          const gpu::Buffer& confidence) const {
  const std::uint64_t bytes = std::uint64_t(width_) * height_ * 4;
  if (distance.size() < bytes || confidence.size() < bytes)
    throw std::invalid_argument("region planes: the panorama buffers are smaller than its size");
  const RegionPlaneParams& p = params_;
  RegionPush push{std::uint32_t(width_),
                  std::uint32_t(height_),
                  p.block,
                  blocks_x_,
                  blocks_y_,
                  p.rim,
                  p.min_pixels,
                  p.max_regions,
                  p.max_planes,
                  p.draws,
                  p.min_inliers,
                  p.min_inlier_fraction,
                  float(p.fill_below),
                  float(p.support),
                  float(p.tau),
                  float(1.0 / min_distance_),
                  float(1.0 / max_distance_),
                  0,
                  0,
                  region_math::surround_cos(p.surround_angle_deg)};
  const auto per_block =
      blocks_kernel_.groups_for(std::uint32_t(blocks_x_), std::uint32_t(blocks_y_));
  const auto regions = std::uint32_t(p.max_regions);
  seq.dispatch(blocks_kernel_, {distance, confidence, blocks_, parent_, sizes_}, push, per_block);
  seq.barrier();
  seq.dispatch(merge_, {parent_}, push, per_block);
  seq.barrier();
  seq.dispatch(flatten_, {blocks_, parent_, sizes_}, push, per_block);
  seq.barrier();
  seq.dispatch(number_, {parent_, sizes_, slots_, regions_, histogram_}, push, {1, 1, 1});
  seq.barrier();
  seq.dispatch(support_, {blocks_, parent_, slots_, regions_, histogram_, candidates_}, push,
               per_block);
  seq.barrier();
  seq.dispatch(threshold_, {regions_, histogram_}, push, {1, 1, 1});
  seq.barrier();
  push.phase = 1;
  seq.dispatch(support_, {blocks_, parent_, slots_, regions_, histogram_, candidates_}, push,
               per_block);
  seq.barrier();
  seq.dispatch(sample_kernel_, {blocks_, regions_, candidates_, table_, sample_, alive_, tags_},
               push, {regions, 1, 1});
  seq.barrier();
  // Plane k's draws scored, plane k - 1 concluded, in one dispatch (region_ransac_step.comp).
  for (int k = 0; k <= p.max_planes; ++k) {
    push.plane = k;
    seq.dispatch(step_, {regions_, sample_, alive_, tags_, scores_, planes_}, push,
                 step_.groups_for(std::uint32_t(p.draws), regions));
    seq.barrier();
  }
  seq.dispatch(surround_kernel_, {parent_, slots_, regions_, sample_, tags_, table_, surround_},
               push, per_block);
  seq.barrier();
  seq.dispatch(apply_, {distance, confidence, table_, planes_, surround_}, push,
               apply_.groups_for(std::uint32_t(width_), std::uint32_t(height_)));
}

}  // namespace omnisweep::stitch
