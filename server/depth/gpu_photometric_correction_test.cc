// The photometric correction on the GPU (photometric_correction.comp) against its CPU check,
// PhotometricCorrection::apply, on synthetic frames through realistic lenses.
#include "server/depth/gpu_photometric_correction.h"

#include <gtest/gtest.h>

#include <cstdlib>

#include "server/depth/depth_fixtures.h"
#include "tests/support/gpu_test_support.h"

namespace omnisweep::depth {
namespace {

using GpuPhotometricCorrectionTest = omnisweep::testing::ValidatedGpuTest;

// A synthetic frame through realistic lenses, its images at `size` (depth_fixtures).
fixtures::SyntheticDepthCase render(int size) {
  return fixtures::render_depth_case(size, 0, 1, synthetic::PhotometricOptions::realistic());
}

// Corrects `cameras`' images (all when empty) on the GPU and returns them.
std::vector<Rgb8Image> corrected_on_gpu(gpu::Context& context,
                                        const fixtures::SyntheticDepthCase& f,
                                        const PhotometryFit& fit, const std::vector<int>& cameras) {
  std::vector<Rgb8View> views;
  for (const int c : cameras.empty() ? std::vector<int>{0, 1, 2, 3} : cameras)
    views.emplace_back(f.images[std::size_t(c)]);
  const std::vector<std::uint32_t> packed = fixtures::packed_images(views);
  gpu::Buffer buffer(context, packed.size() * 4);
  buffer.upload(std::span<const std::uint32_t>(packed));
  GpuPhotometricCorrection correction(context, f.rig.rig(), cameras);
  gpu::Sequence seq(context);
  seq.begin();
  correction.record(seq, buffer, fit);
  seq.submit_and_wait();
  return fixtures::unpacked_images(buffer.download<std::uint32_t>(), f.images[0].width(),
                                   f.images[0].height());
}

TEST_F(GpuPhotometricCorrectionTest, EqualsCpu) {
  const fixtures::SyntheticDepthCase f = render(96);
  const PhotometryFit fit = estimate_photometry(f.rig.rig(), f.image_views(), f.usable);
  for (const std::vector<int>& cameras : {std::vector<int>{}, std::vector<int>{2, 3}}) {
    std::vector<Rgb8Image> cpu;
    for (const int c : cameras.empty() ? std::vector<int>{0, 1, 2, 3} : cameras)
      cpu.push_back(f.images[c].clone());
    PhotometricCorrection(f.rig.rig()).apply(fit, cpu, cameras);
    const std::vector<Rgb8Image> gpu = corrected_on_gpu(context(), f, fit, cameras);
    ASSERT_EQ(gpu.size(), cpu.size());
    int worst = 0;
    std::size_t changed = 0;
    for (std::size_t k = 0; k < cpu.size(); ++k)
      for (std::size_t i = 0; i < cpu[k].size(); ++i) {
        worst = std::max(worst, std::abs(int(cpu[k].data()[i]) - int(gpu[k].data()[i])));
        const int c = cameras.empty() ? int(k) : cameras[k];
        changed += gpu[k].data()[i] != f.images[c].data()[i];
      }
    EXPECT_LE(worst, 1);  // float on the GPU, double on the CPU: a rounding apart at most
    EXPECT_GT(changed, cpu[0].size() / 4);  // the lenses' responses were undone, not skipped
  }
}

TEST_F(GpuPhotometricCorrectionTest, RejectsMismatchedInputs) {
  const fixtures::SyntheticDepthCase f = render(32);
  EXPECT_THROW(GpuPhotometricCorrection(context(), f.rig.rig(), {0, 7}), std::invalid_argument);
  GpuPhotometricCorrection correction(context(), f.rig.rig(), {0, 3});
  gpu::Buffer buffer(context(), vk::DeviceSize(32) * 32 * 4 * 2);
  gpu::Sequence seq(context());
  seq.begin();
  PhotometryFit three;
  three.cameras.resize(3);  // no camera 3
  EXPECT_THROW(correction.record(seq, buffer, three), std::invalid_argument);
}

}  // namespace
}  // namespace omnisweep::depth
