#include "server/depth/depth_fixtures.h"

#include <numbers>

#include "omnisweep/gpu/sequence.h"
#include "omnisweep/reproject/gpu_camera.h"

namespace omnisweep::depth::fixtures {

std::vector<Rgb8View> SyntheticDepthCase::image_views() const { return views(images); }

SyntheticDepthCase render_depth_case(int size, int frame, std::uint64_t seed,
                                     const synthetic::PhotometricOptions& photometric) {
  synthetic::SyntheticRigOptions options;
  options.image_size = size;
  options.seed = seed;
  options.photometric = photometric;
  SyntheticDepthCase out{synthetic::SyntheticRig(options), {}, {}, {}};
  const synthetic::SyntheticFrame rendered = out.rig.render(frame, 64, 32);
  for (auto& cam : const_cast<synthetic::SyntheticFrame&>(rendered).cameras) {
    out.images.push_back(std::move(cam.rgb));
    out.inverse_gt.push_back(std::move(cam.inverse_distance));
  }
  for (auto& mask : out.rig.masks()) out.usable.emplace_back(std::move(mask));
  return out;
}

Accuracy inverse_distance_accuracy(const FloatImage& distance, const FloatImage& inverse_gt,
                                   const Gray8Image& usable) {
  Accuracy a;
  for (int y = 0; y < distance.height(); ++y) {
    for (int x = 0; x < distance.width(); ++x) {
      if (!usable(x, y) || inverse_gt(x, y) <= 0) continue;
      const double e = std::abs(1.0 / distance(x, y) - inverse_gt(x, y));
      a.mae += e;
      a.bad_0_1 += e > 0.1;
      a.bad_0_4 += e > 0.4;
      ++a.pixels;
    }
  }
  a.mae /= a.pixels;
  a.bad_0_1 /= a.pixels;
  a.bad_0_4 /= a.pixels;
  return a;
}

std::vector<float> isb_filter_gpu(gpu::Context& context, const std::vector<std::uint32_t>& guide,
                                  const std::vector<float>& values, int width, int height,
                                  int channels, const IsbParams& params) {
  const VolumeLayout layout = plan_volume(context, width, height, channels);
  CostVolume volume(context, width, height, layout);
  volume.upload(values, channels);
  gpu::Buffer guide_buffer(context, guide.size() * 4);
  guide_buffer.upload(std::span<const std::uint32_t>(guide));
  IsbFilter filter(context, width, height, layout, params.sigma_s_confident > 0);
  gpu::Sequence seq(context);
  seq.begin();
  filter.record(seq, guide_buffer, volume, params);
  seq.submit_and_wait();
  return volume.download(channels);
}

std::vector<std::uint32_t> packed_images(std::span<const Rgb8View> images) {
  if (images.empty()) return {};
  const std::size_t pixels = std::size_t(images[0].width()) * images[0].height();
  std::vector<std::uint32_t> packed(pixels * images.size());
  for (std::size_t k = 0; k < images.size(); ++k)
    reproject::pack_rgba8(images[k], std::span(packed).subspan(k * pixels, pixels));
  return packed;
}

std::vector<Rgb8Image> unpacked_images(std::span<const std::uint32_t> packed, int width,
                                       int height) {
  const std::size_t pixels = std::size_t(width) * height;
  std::vector<Rgb8Image> images;
  for (std::size_t k = 0; k + pixels <= packed.size(); k += pixels) {
    Rgb8Image im(width, height);
    for (std::size_t p = 0; p < pixels; ++p)
      for (int ch = 0; ch < 3; ++ch)
        im.data()[p * 3 + ch] = std::uint8_t((packed[k + p] >> (8 * ch)) & 0xff);
    images.push_back(std::move(im));
  }
  return images;
}

}  // namespace omnisweep::depth::fixtures
