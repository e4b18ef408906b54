// Camera selection, sweep cost and YCbCr guide shaders against their plain C++ versions.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "omnisweep/dataset/dataset.h"
#include "omnisweep/gpu/sequence.h"
#include "omnisweep/image/image_io.h"
#include "server/depth/depth_estimator.h"
#include "server/depth/depth_fixtures.h"
#include "server/depth/depth_reference.h"
#include "tests/support/gpu_test_support.h"
#include "tests/support/test_support.h"

namespace omnisweep::depth {
namespace {

using omnisweep::testing::ValidatedGpuTest;
using DepthKernelTest = ValidatedGpuTest;

// GPU selection (float) equals the double-precision CPU version wherever the decision is not
// within rounding of a tie or boundary; such fragile pixels must be rare.
void expect_selection_matches(gpu::Context& context, const Rig& rig,
                              const std::vector<std::optional<Gray8Image>>& usable,
                              DepthOptions options) {
  const DepthEstimator estimator(context, rig, usable, options);
  for (std::size_t slot = 0; slot < options.references.size(); ++slot) {
    const Image<std::int32_t> gpu = estimator.selection(int(slot));
    const Image<std::int32_t> gpu_second = estimator.second_selection(int(slot));
    const SelectionReference cpu =
        select_cameras_cpu(rig, options.references[slot], usable, options.min_distance,
                           options.max_distance, options.second_camera_power);
    long fragile = 0, mismatched = 0, selected = 0, seconds = 0;
    std::vector<long> per_camera(rig.num_cameras(), 0);
    for (int y = 0; y < gpu.height(); ++y) {
      for (int x = 0; x < gpu.width(); ++x) {
        if (cpu.fragile(x, y)) {
          ++fragile;
          continue;
        }
        mismatched += gpu(x, y) != cpu.selected(x, y);
        mismatched += gpu_second(x, y) != cpu.second(x, y);
        seconds += cpu.second(x, y) >= 0;
        if (cpu.selected(x, y) >= 0) ++per_camera[cpu.selected(x, y)], ++selected;
      }
    }
    std::cout << "reference " << options.references[slot] << ": " << selected
              << " pixels matched (";
    for (int c = 0; c < rig.num_cameras(); ++c)
      std::cout << (c ? ", " : "") << "cam" << c << " " << per_camera[c];
    std::cout << "), " << seconds << " with a second camera, " << fragile << " fragile, "
              << mismatched << " mismatched\n";
    EXPECT_EQ(mismatched, 0);
    EXPECT_LT(double(fragile) / gpu.size(), 0.01);
    EXPECT_GT(selected, gpu.size() / 3);
  }
}

TEST_F(DepthKernelTest, CameraSelectionEqualsCpuOnTheSyntheticRig) {
  const auto scene = fixtures::render_depth_case(160);
  DepthOptions options;
  options.matching_width = options.matching_height = 160;
  expect_selection_matches(context(), scene.rig.rig(), scene.usable, options);
}

TEST_F(DepthKernelTest, CameraSelectionEqualsCpuOnTheKaistRigWithItsMasks) {
  const Dataset kaist = Dataset::open(omnisweep::testing::kaist_rig_dir());
  DepthOptions options;
  options.matching_width = options.matching_height = 256;
  std::vector<std::optional<Gray8Image>> usable;
  for (const auto& mask : kaist.masks()) usable.emplace_back(usable_mask(*mask, 256, 256));
  expect_selection_matches(context(), kaist.rig().resized(256, 256), usable, options);
}

// Half the spacing of 16-bit floats around v: what storing v as a half may move it.
float half_rounding(float v) {
  const float a = std::abs(v);
  return a < 6.1e-5f ? 3e-8f : std::ldexp(1.0f, int(std::floor(std::log2(a))) - 11);
}

// With match_cameras = 2 the CPU's cost is the mean of the two cameras' where there is a second.
TEST_F(DepthKernelTest, SweepCostEqualsCpu) {
  const auto scene = fixtures::render_depth_case(128);
  for (const auto& [half, cameras] : {std::pair{false, 1}, {true, 1}, {false, 2}}) {
    DepthOptions options;
    options.matching_width = options.matching_height = 128;
    options.half_costs = half;
    options.match_cameras = cameras;
    DepthEstimator estimator(context(), scene.rig.rig(), scene.usable, options);
    if (half && !estimator.volume_layout().half) {
      std::cout << "the device stores no 16-bit floats: 16-bit costs not checked\n";
      continue;
    }
    const auto images = scene.image_views();
    for (std::size_t slot = 0; slot < 2; ++slot) {
      const std::vector<float> gpu = estimator.cost_volume(images, int(slot), false);
      const Image<std::int32_t> selected = estimator.selection(int(slot));
      const Image<std::int32_t> second = estimator.second_selection(int(slot));
      std::vector<float> differences;
      long averaged = 0;
      for (int y = 0; y < 128; y += 3) {
        for (int x = 0; x < 128; x += 3) {
          auto cpu = sweep_cost_cpu(scene.rig.rig(), options.references[slot], selected(x, y),
                                    images, options, x, y);
          if (cameras == 2 && second(x, y) >= 0) {
            const auto other = sweep_cost_cpu(scene.rig.rig(), options.references[slot],
                                              second(x, y), images, options, x, y);
            for (int i = 0; i < options.num_candidates; ++i) cpu[i] = 0.5f * (cpu[i] + other[i]);
            ++averaged;
          }
          for (int i = 0; i < options.num_candidates; ++i) {
            const float d =
                std::abs(cpu[i] - gpu[(std::size_t(y) * 128 + x) * options.num_candidates + i]);
            // 16-bit storage rounds each cost to 11 significant bits: beyond that, equal.
            differences.push_back(half ? std::max(0.0f, d - half_rounding(cpu[i])) : d);
          }
        }
      }
      std::sort(differences.begin(), differences.end());
      const float p99 = differences[differences.size() * 99 / 100], worst = differences.back();
      std::cout << (half ? "16-bit" : "32-bit") << ", " << cameras
                << " camera(s): sweep cost vs CPU: 99th percentile difference " << p99
                << ", largest " << worst << " (" << averaged << " pixels averaged)\n";
      if (cameras == 2) {
        EXPECT_GT(averaged, 100);
      }
      EXPECT_LT(p99, 0.05f);    // float vs double projection moves a tap by ~1e-4 px
      EXPECT_LT(worst, 20.0f);  // at most a pixel-boundary tap flip at a strong edge
    }
  }
}

TEST_F(DepthKernelTest, YCbCrGuideEqualsCpu) {
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> byte(0, 255);
  const int w = 33, h = 17;
  Rgb8Image rgb(w, h);
  for (auto& v : rgb.pixels()) v = std::uint8_t(byte(rng));
  rgb(0, 0, 0) = rgb(0, 0, 1) = rgb(0, 0, 2) = 255;  // clamps
  std::vector<std::uint32_t> packed(std::size_t(w) * h);
  for (std::ptrdiff_t p = 0; p < std::ptrdiff_t(w) * h; ++p)
    packed[p] = rgb.data()[3 * p] | (rgb.data()[3 * p + 1] << 8) | (rgb.data()[3 * p + 2] << 16);
  gpu::Buffer images(context(), packed.size() * 4), guide(context(), packed.size() * 4);
  images.upload(std::span<const std::uint32_t>(packed));
  const gpu::Kernel kernel(
      context(), gpu::Shader::kYcbcrGuide,
      {.bindings = {gpu::BindingSlot::texels(), 1}, .push_constant_bytes = 4 * (2 + 8)});
  gpu::Sequence seq(context());
  seq.begin();
  const std::uint32_t push[2 + 8] = {w, h, 0};  // width, height, the camera of slot 0
  seq.dispatch(kernel, {gpu::Texels(images, gpu::TexelFormat::kR32Uint), guide}, push, sizeof(push),
               kernel.groups_for(w, h));
  seq.submit_and_wait();
  EXPECT_EQ(guide.download<std::uint32_t>(), ycbcr_guide_cpu(rgb));
}

}  // namespace
}  // namespace omnisweep::depth
