#include "server/depth/depth_reference.h"

#include <algorithm>
#include <bit>
#include <cmath>

namespace omnisweep::depth {
namespace {

bool usable_at(const std::vector<std::optional<Gray8Image>>& usable, int camera,
               const RigCamera& cam, const Eigen::Vector2d& uv, bool* fragile) {
  const double fx = std::floor(uv.x() + 0.5), fy = std::floor(uv.y() + 0.5);
  // Within 1e-3 px of a rounding boundary (k + 0.5) or of the image edge, float may decide
  // otherwise.
  for (double v : {uv.x(), uv.y()}) {
    if (std::abs(v - std::floor(v) - 0.5) < 2e-4) *fragile = true;
  }
  if (fx < 0 || fy < 0 || fx >= cam.width || fy >= cam.height) return false;
  if (usable.empty() || !usable[camera]) return true;
  return (*usable[camera])(int(fx), int(fy)) != 0;
}

std::array<float, 3> rgb_at(Rgb8View im, int x, int y) {
  if (x < 0 || y < 0 || x >= im.width() || y >= im.height()) return {0, 0, 0};
  return {float(im(x, y, 0)), float(im(x, y, 1)), float(im(x, y, 2))};
}

std::array<float, 3> unpack(std::uint32_t g) {
  return {float(g & 255), float((g >> 8) & 255), float((g >> 16) & 255)};
}

// In float, like the shader, so that 8-bit guide rounding decides the same way.
float range_weight(std::uint32_t a, std::uint32_t b, float inv_two_sigma_sq) {
  const auto ga = unpack(a), gb = unpack(b);
  const float g = std::abs(ga[0] - gb[0]) + std::abs(ga[1] - gb[1]) + std::abs(ga[2] - gb[2]);
  return std::exp(-g * g * inv_two_sigma_sq) + 0.01f;
}

std::uint32_t round_pack(const std::array<float, 3>& v) {
  std::uint32_t out = 0;
  for (int k = 0; k < 3; ++k)
    out |= std::uint32_t(std::clamp(std::floor(v[k] + 0.5f), 0.0f, 255.0f)) << (8 * k);
  return out;
}

}  // namespace

SelectionReference select_cameras_cpu(const Rig& rig, int reference,
                                      const std::vector<std::optional<Gray8Image>>& usable,
                                      double d_min, double d_max, double second_power) {
  const RigCamera& ref = rig.cameras[reference];
  SelectionReference out{Image<std::int32_t>::filled(ref.width, ref.height, -1),
                         Image<std::int32_t>::filled(ref.width, ref.height, -1),
                         Gray8Image(ref.width, ref.height)};
  for (int y = 0; y < ref.height; ++y) {
    for (int x = 0; x < ref.width; ++x) {
      bool fragile = false;
      Eigen::Vector3d ray;
      if (!usable_at(usable, reference, ref, Eigen::Vector2d(x, y), &fragile)) continue;
      if (!ref.model.unproject(Eigen::Vector2d(x, y), &ray)) continue;
      if (std::abs(std::acos(std::clamp(ray.z(), -1.0, 1.0)) - ref.model.max_angle()) < 1e-4)
        fragile = true;
      // The longest, the next longest and the one after (for ties), each over 1 px.
      double best = 1.0, second = 1.0, third = 1.0;
      int chosen = -1, chosen_second = -1;
      for (int c = 0; c < rig.num_cameras(); ++c) {
        if (c == reference) continue;
        const RigCamera& cam = rig.cameras[c];
        const Rigid3d cam_from_ref = rig.cam_from_cam(c, reference);
        Eigen::Vector2d near_uv, far_uv;
        const Eigen::Vector3d near_p = cam_from_ref * (ray * d_min),
                              far_p = cam_from_ref * (ray * d_max);
        const bool near_ok = cam.model.project(near_p, &near_uv),
                   far_ok = cam.model.project(far_p, &far_uv);
        for (const Eigen::Vector3d& p : {near_p, far_p}) {
          if (std::abs(std::acos(std::clamp(p.normalized().z(), -1.0, 1.0)) -
                       cam.model.max_angle()) < 1e-4)
            fragile = true;
        }
        if (!near_ok || !far_ok) continue;
        const bool near_usable = usable_at(usable, c, cam, near_uv, &fragile);
        const bool far_usable = usable_at(usable, c, cam, far_uv, &fragile);
        if (!near_usable || !far_usable) continue;
        const double displacement = (far_uv - near_uv).norm();
        if (std::abs(displacement - 1.0) < 1e-3) fragile = true;
        if (displacement > best) {
          third = second;
          second = best;
          chosen_second = chosen;
          best = displacement;
          chosen = c;
        } else if (displacement > second) {
          third = second;
          second = displacement;
          chosen_second = c;
        } else {
          third = std::max(third, displacement);
        }
      }
      if (chosen >= 0 && best - second < 1e-3) fragile = true;
      if (chosen_second >= 0 &&
          (second - third < 1e-3 || std::abs(second - second_power * best) < 1e-3))
        fragile = true;
      if (second < second_power * best) chosen_second = -1;
      out.selected(x, y) = chosen;
      out.second(x, y) = chosen_second;
      out.fragile(x, y) = fragile ? 1 : 0;
    }
  }
  return out;
}

std::vector<float> sweep_cost_cpu(const Rig& rig, int reference, int selected,
                                  std::span<const Rgb8View> images, const DepthOptions& options,
                                  int x, int y) {
  std::vector<float> costs(options.num_candidates, 0.0f);
  Eigen::Vector3d ray;
  if (selected < 0 || !rig.cameras[reference].model.unproject(Eigen::Vector2d(x, y), &ray))
    return costs;
  const auto ref_rgb = rgb_at(images[reference], x, y);
  const RigCamera& cam = rig.cameras[selected];
  const Rigid3d cam_from_ref = rig.cam_from_cam(selected, reference);
  for (int i = 0; i < options.num_candidates; ++i) {
    const double distance = 1.0 / options.inverse_distance(i);
    Eigen::Vector2d uv;
    std::array<float, 3> rgb = {0, 0, 0};
    if (cam.model.project(cam_from_ref * (ray * distance), &uv) && uv.x() > -2 && uv.y() > -2 &&
        uv.x() < cam.width + 1 && uv.y() < cam.height + 1) {
      const int x0 = int(std::floor(uv.x())), y0 = int(std::floor(uv.y()));
      const double tx = uv.x() - x0, ty = uv.y() - y0;
      const Rgb8View& im = images[selected];
      for (int k = 0; k < 3; ++k) {
        const double top = (1 - tx) * rgb_at(im, x0, y0)[k] + tx * rgb_at(im, x0 + 1, y0)[k];
        const double bottom =
            (1 - tx) * rgb_at(im, x0, y0 + 1)[k] + tx * rgb_at(im, x0 + 1, y0 + 1)[k];
        rgb[k] = float((1 - ty) * top + ty * bottom);
      }
    }
    costs[i] = std::min(std::abs(rgb[0] - ref_rgb[0]) + std::abs(rgb[1] - ref_rgb[1]) +
                            std::abs(rgb[2] - ref_rgb[2]),
                        500.0f);
  }
  return costs;
}

namespace {

// The luminance census of pixel (x, y) in the high byte, as matching_features.comp packs it.
std::uint32_t census_cpu(const Rgb8Image& rgb, int x, int y, int r) {
  const int w = rgb.width(), h = rgb.height();
  auto luma = [&](int u, int v) {  // clamped to the image, as the shader
    const auto c = rgb_at(rgb, std::clamp(u, 0, w - 1), std::clamp(v, 0, h - 1));
    return 0.299f * c[0] + 0.587f * c[1] + 0.114f * c[2];
  };
  const float c = luma(x, y) + 1.0f;
  const int offsets[8][2] = {{r, 0}, {r, -r}, {0, -r}, {-r, -r}, {-r, 0}, {-r, r}, {0, r}, {r, r}};
  std::uint32_t census = 0;
  for (int bit = 0; bit < 8; ++bit) {
    if (luma(x + offsets[bit][0], y + offsets[bit][1]) > c) census |= 1u << (24 + bit);
  }
  return census;
}

}  // namespace

std::vector<std::uint32_t> matching_features_cpu(const Rgb8Image& rgb, int radius,
                                                 int census_radius, double epsilon) {
  const int w = rgb.width(), h = rgb.height();
  auto at = [&](int x, int y) {  // clamped to the image, as the shader
    return rgb_at(rgb, std::clamp(x, 0, w - 1), std::clamp(y, 0, h - 1));
  };
  std::vector<std::uint32_t> out(std::size_t(w) * h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      std::array<double, 3> sum{}, sum2{};
      for (int dy = -radius; dy <= radius; ++dy) {
        for (int dx = -radius; dx <= radius; ++dx) {
          const auto v = at(x + dx, y + dy);
          for (int k = 0; k < 3; ++k) {
            sum[k] += v[k];
            sum2[k] += double(v[k]) * v[k];
          }
        }
      }
      const double n = double((2 * radius + 1) * (2 * radius + 1));
      const auto centre = at(x, y);
      std::uint32_t packed = census_cpu(rgb, x, y, census_radius);
      for (int k = 0; k < 3; ++k) {
        const double mean = sum[k] / n;
        const double deviation = std::sqrt(std::max(sum2[k] / n - mean * mean, 0.0));
        const double v =
            std::clamp(128.0 + 32.0 * (centre[k] - mean) / (deviation + epsilon), 0.0, 255.0);
        packed |= std::uint32_t(std::floor(v + 0.5)) << (8 * k);
      }
      out[std::size_t(y) * w + x] = packed;
    }
  }
  return out;
}

std::vector<std::uint32_t> ratio_features_cpu(const Rgb8Image& rgb, const Gray8Image* usable,
                                              int radius, int census_radius, double epsilon) {
  const int w = rgb.width(), h = rgb.height();
  std::vector<std::uint32_t> out(std::size_t(w) * h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      std::array<double, 3> sum{};
      double weights = 0;
      for (int ky = -4; ky <= 4; ++ky) {
        for (int kx = -4; kx <= 4; ++kx) {
          const int u = std::clamp(x + kx * radius / 4, 0, w - 1);  // truncated, as the shader
          const int v = std::clamp(y + ky * radius / 4, 0, h - 1);
          if (usable && !(*usable)(u, v)) continue;
          const double weight = std::exp(-(kx * kx + ky * ky) / 8.0);
          const auto c = rgb_at(rgb, u, v);
          for (int k = 0; k < 3; ++k) sum[k] += weight * c[k];
          weights += weight;
        }
      }
      const auto centre = rgb_at(rgb, x, y);
      std::uint32_t packed = census_cpu(rgb, x, y, census_radius);
      for (int k = 0; k < 3; ++k) {
        const double mean = weights > 0 ? sum[k] / weights : centre[k];
        const double v = std::clamp(128.0 * centre[k] / (mean + epsilon), 0.0, 255.0);
        packed |= std::uint32_t(std::floor(v + 0.5)) << (8 * k);
      }
      out[std::size_t(y) * w + x] = packed;
    }
  }
  return out;
}

std::vector<float> feature_cost_cpu(const Rig& rig, int reference, int selected,
                                    const std::vector<std::vector<std::uint32_t>>& features,
                                    const DepthOptions& options, int x, int y) {
  std::vector<float> costs(options.num_candidates, 0.0f);
  Eigen::Vector3d ray;
  if (selected < 0 || !rig.cameras[reference].model.unproject(Eigen::Vector2d(x, y), &ray))
    return costs;
  const RigCamera& cam = rig.cameras[selected];
  const int w = cam.width, h = cam.height;
  const std::uint32_t ref = features[reference][std::size_t(y) * w + x];
  auto difference = [&](std::uint32_t f) {
    const auto a = unpack(f), b = unpack(ref);
    const float color = std::abs(a[0] - b[0]) + std::abs(a[1] - b[1]) + std::abs(a[2] - b[2]);
    const float census = float(std::popcount((f ^ ref) >> 24)) * float(options.census_scale);
    switch (options.cost) {
      case MatchingCost::kNormalised:
      case MatchingCost::kRatio:
        return color;
      case MatchingCost::kCensus:
        return census;
      default:
        return color + census;
    }
  };
  auto tap = [&](int u, int v) {  // outside the image: the largest cost
    if (u < 0 || v < 0 || u >= w || v >= h) return 500.0f;
    return difference(features[selected][std::size_t(v) * w + u]);
  };
  const Rigid3d cam_from_ref = rig.cam_from_cam(selected, reference);
  for (int i = 0; i < options.num_candidates; ++i) {
    const double distance = 1.0 / options.inverse_distance(i);
    Eigen::Vector2d uv;
    float cost = 500.0f;
    if (cam.model.project(cam_from_ref * (ray * distance), &uv) && uv.x() >= -2 && uv.y() >= -2 &&
        uv.x() <= w + 1 && uv.y() <= h + 1) {
      const int x0 = int(std::floor(uv.x())), y0 = int(std::floor(uv.y()));
      const double tx = uv.x() - x0, ty = uv.y() - y0;
      const double top = (1 - tx) * tap(x0, y0) + tx * tap(x0 + 1, y0);
      const double bottom = (1 - tx) * tap(x0, y0 + 1) + tx * tap(x0 + 1, y0 + 1);
      cost = float((1 - ty) * top + ty * bottom);
    }
    costs[i] = std::min(cost, 500.0f);
  }
  return costs;
}

std::vector<std::uint32_t> ycbcr_guide_cpu(const Rgb8Image& rgb) {
  std::vector<std::uint32_t> out(std::size_t(rgb.width()) * rgb.height());
  for (std::size_t p = 0; p < out.size(); ++p) {
    const double r = rgb.data()[3 * p], g = rgb.data()[3 * p + 1], b = rgb.data()[3 * p + 2];
    const double y = std::clamp(16 + 0.1826 * r + 0.6142 * g + 0.0620 * b, 16.0, 235.0);
    const double cb = std::clamp(128 - 0.1006 * r - 0.3386 * g + 0.4392 * b, 16.0, 240.0);
    const double cr = std::clamp(128 + 0.4392 * r - 0.3989 * g - 0.0403 * b, 16.0, 240.0);
    out[p] = round_pack({float(y), float(cb), float(cr)});
  }
  return out;
}

std::vector<float> isb_filter_cpu(std::vector<std::uint32_t> guide, std::vector<float> values,
                                  int width, int height, int channels, double sigma_i,
                                  double sigma_s, double sigma_s_confident) {
  const bool confident = sigma_s_confident > 0;
  if (!confident)
    for (auto& g : guide) g &= 0x00ffffffu;
  // Single precision throughout, in the order the shaders sum, as a GPU computes it.
  const float inv2s = float(1.0 / (2 * sigma_i * sigma_i));
  const int levels = std::max(1, int(std::floor(std::log2(double(std::min(width, height))))) - 1);
  std::vector<int> w{width}, h{height};
  std::vector<std::vector<std::uint32_t>> g{std::move(guide)};
  std::vector<std::vector<float>> v{std::move(values)};
  for (int l = 0; l + 1 < levels; ++l) {  // down
    const int cw = (w[l] + 1) / 2, ch = (h[l] + 1) / 2;
    std::vector<std::uint32_t> cg(std::size_t(cw) * ch);
    std::vector<float> cv(std::size_t(cw) * ch * channels);
    for (int y = 0; y < ch; ++y) {
      for (int x = 0; x < cw; ++x) {
        const std::uint32_t centre = g[l][std::size_t(2 * y) * w[l] + std::size_t(2) * x];
        float total = 0;
        std::array<float, 3> gsum = {0, 0, 0};
        float confidence_sum = 0;
        std::vector<float> acc(channels, 0.0f);
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dx = -1; dx <= 1; ++dx) {
            const int qx = std::clamp(2 * x + dx, 0, w[l] - 1),
                      qy = std::clamp(2 * y + dy, 0, h[l] - 1);
            const std::size_t q = std::size_t(qy) * w[l] + qx;
            const int manhattan = std::abs(dx) + std::abs(dy);
            const float weight = manhattan == 0 ? 1.0f
                                                : (manhattan == 1 ? 0.5f : 0.25f) *
                                                      range_weight(centre, g[l][q], inv2s);
            total += weight;
            const auto gq = unpack(g[l][q]);
            for (int k = 0; k < 3; ++k) gsum[k] += weight * gq[k];
            confidence_sum += weight * float(g[l][q] >> 24);
            for (int c = 0; c < channels; ++c) acc[c] += weight * v[l][q * channels + c];
          }
        }
        const std::size_t o = std::size_t(y) * cw + x;
        cg[o] = round_pack({gsum[0] / total, gsum[1] / total, gsum[2] / total}) |
                (std::uint32_t(std::clamp(std::floor(confidence_sum / total + 0.5f), 0.0f, 255.0f))
                 << 24);
        const float inv_total = 1.0f / total;
        for (int c = 0; c < channels; ++c) cv[o * channels + c] = acc[c] * inv_total;
      }
    }
    w.push_back(cw);
    h.push_back(ch);
    g.push_back(std::move(cg));
    v.push_back(std::move(cv));
  }
  for (int l = levels - 2; l >= 0; --l) {  // up
    const double scale = std::ldexp(1.0, l) - 0.5;
    const float level_w_down = float(std::exp(-scale * scale / (2 * sigma_s * sigma_s)));
    const int cw = w[l + 1], ch = h[l + 1];
    for (int fy = 0; fy < h[l]; ++fy) {
      for (int fx = 0; fx < w[l]; ++fx) {
        const int x = fx / 2, y = fy / 2;
        std::vector<std::pair<std::array<int, 2>, float>> neighbours;
        if (fx % 2 == 0 && fy % 2 == 0) {
          for (int j = 0; j < 9; ++j)
            neighbours.push_back({{x + j % 3 - 1, y + j / 3 - 1}, j == 4 ? 8.0f : 1.0f});
        } else if (fx % 2 == 0) {
          neighbours = {{{x, y}, 8},         {{x, y + 1}, 8}, {{x - 1, y}, 1},
                        {{x - 1, y + 1}, 1}, {{x + 1, y}, 1}, {{x + 1, y + 1}, 1}};
        } else if (fy % 2 == 0) {
          neighbours = {{{x, y}, 8},         {{x + 1, y}, 8}, {{x, y - 1}, 1},
                        {{x + 1, y - 1}, 1}, {{x, y + 1}, 1}, {{x + 1, y + 1}, 1}};
        } else {
          neighbours = {{{x, y}, 1}, {{x + 1, y}, 1}, {{x, y + 1}, 1}, {{x + 1, y + 1}, 1}};
        }
        const std::size_t f = std::size_t(fy) * w[l] + fx;
        const std::uint32_t own = g[l][f];
        float w_down = level_w_down;
        if (confident) {  // isb_weights.glsl's confident_w_down
          const float a = std::clamp((float(own >> 24) / 255.0f - 0.5f) / 0.2f, 0.0f, 1.0f);
          const float sigma = float(sigma_s) + (float(sigma_s_confident) - float(sigma_s)) * a;
          w_down = std::exp(-float(scale * scale) / (2.0f * sigma * sigma));
        }
        const float w_up = 1.0f - w_down;
        const auto go = unpack(own);
        float total = w_up;
        std::array<float, 3> gsum = {w_up * go[0], w_up * go[1], w_up * go[2]};
        std::vector<std::size_t> index;
        std::vector<float> weight;
        for (const auto& [xy, spatial] : neighbours) {
          const std::size_t q =
              std::size_t(std::clamp(xy[1], 0, ch - 1)) * cw + std::clamp(xy[0], 0, cw - 1);
          index.push_back(q);
          weight.push_back(w_down * spatial * range_weight(own, g[l + 1][q], inv2s));
          total += weight.back();
          const auto gq = unpack(g[l + 1][q]);
          for (int k = 0; k < 3; ++k) gsum[k] += weight.back() * gq[k];
        }
        const float inv_total = 1.0f / total;
        for (int c = 0; c < channels; ++c) {
          float sum = w_up * v[l][f * channels + c];
          for (std::size_t j = 0; j < index.size(); ++j)
            sum += weight[j] * v[l + 1][index[j] * channels + c];
          v[l][f * channels + c] = sum * inv_total;
        }
        g[l][f] = round_pack({gsum[0] * inv_total, gsum[1] * inv_total, gsum[2] * inv_total}) |
                  (own & 0xff000000u);
      }
    }
  }
  return std::move(v[0]);
}

float winner_take_all_cpu(const float* costs, const DepthOptions& options) {
  const int n = options.num_candidates;
  const auto [lo, hi] = std::minmax_element(costs, costs + n);
  if (*lo == *hi) return float(options.max_distance);
  const int best = int(lo - costs);
  double delta = 0;
  if (best > 0 && best + 1 < n) {
    const double a = costs[best - 1], b = costs[best + 1], c = costs[best];
    delta = std::clamp(0.5 * (a - b) / (a + b - 2 * c + 1e-8), -0.5, 0.5);
  }
  return float(1.0 / options.inverse_distance(best + delta));
}

float raw_agreement_cpu(const float* filtered, const float* raw, int n, double tolerance) {
  if (tolerance <= 0) return 1.0f;
  const int best = int(std::min_element(filtered, filtered + n) - filtered);  // the first lowest
  const auto [lo, hi] = std::minmax_element(raw, raw + n);  // lo: the first lowest
  if (lo - raw >= best) return 1.0f;  // the raw curve puts the surface no nearer
  const float range = *hi - *lo;
  const float d = range > 0 ? (raw[best] - *lo) / range : 0.0f;
  const float power = *hi > 0 ? 1.0f - *lo / *hi : 0.0f;
  const float x = float(d * power / tolerance);
  return std::exp(-x * x);
}

float cost_confidence_cpu(const float* costs, int n) {
  // Local minima: no higher than the next candidate, lower than the one before (one neighbour
  // at the ends), so a plateau counts once.
  std::vector<float> minima;
  for (int i = 0; i < n; ++i) {
    const bool below_before = i == 0 || costs[i] < costs[i - 1];
    const bool not_above_after = i + 1 == n || costs[i] <= costs[i + 1];
    if (below_before && not_above_after) minima.push_back(costs[i]);
  }
  std::sort(minima.begin(), minima.end());
  const float highest = *std::max_element(costs, costs + n);
  const float lowest = minima.front();
  const float second = minima.size() > 1 ? std::min(minima[1], highest) : highest;
  const float ratio = second > lowest ? std::clamp(1.0f - lowest / second, 0.0f, 1.0f) : 0.0f;
  const int best = int(std::min_element(costs, costs + n) - costs);  // the first lowest
  float curvature;
  if (n == 1)
    curvature = 0;
  else if (best == 0)
    curvature = 2 * (costs[1] - lowest);
  else if (best + 1 == n)
    curvature = 2 * (costs[n - 2] - lowest);
  else
    curvature = costs[best - 1] + costs[best + 1] - 2 * lowest;
  const float sharpness = curvature / (curvature + lowest + 1e-12f);
  return std::sqrt(ratio * sharpness);
}

std::vector<float> coarse_agreement_cpu(const std::vector<float>& level, int level_width,
                                        int level_height, const FloatImage& distance,
                                        const DepthOptions& options) {
  constexpr int kBlock = 4;  // level-1 pixels per block side
  const int n = options.num_candidates;
  const int blocks_x = (level_width + kBlock - 1) / kBlock;
  const int blocks_y = (level_height + kBlock - 1) / kBlock;
  std::vector<float> winner(std::size_t(blocks_x) * blocks_y);
  for (int by = 0; by < blocks_y; ++by) {
    for (int bx = 0; bx < blocks_x; ++bx) {
      std::vector<float> sum(std::size_t(n), 0.0f);
      for (int y = by * kBlock; y < std::min(by * kBlock + kBlock, level_height); ++y)
        for (int x = bx * kBlock; x < std::min(bx * kBlock + kBlock, level_width); ++x)
          for (int i = 0; i < n; ++i)
            sum[std::size_t(i)] += level[(std::size_t(y) * level_width + x) * n + i];
      winner[std::size_t(by) * blocks_x + bx] = 1.0f / winner_take_all_cpu(sum.data(), options);
    }
  }
  // Bilinear between block centres, clamped at the edges (the shader's float arithmetic).
  const auto at = [&](int x, int y) { return winner[std::size_t(y) * blocks_x + x]; };
  std::vector<float> factor(distance.size());
  for (int y = 0; y < distance.height(); ++y) {
    const float v = std::max((float(y) + 0.5f) / float(2 * kBlock) - 0.5f, 0.0f);
    const int y0 = std::min(int(v), blocks_y - 1), y1 = std::min(y0 + 1, blocks_y - 1);
    const float fy = std::min(v - float(y0), 1.0f);
    for (int x = 0; x < distance.width(); ++x) {
      const float u = std::max((float(x) + 0.5f) / float(2 * kBlock) - 0.5f, 0.0f);
      const int x0 = std::min(int(u), blocks_x - 1), x1 = std::min(x0 + 1, blocks_x - 1);
      const float fx = std::min(u - float(x0), 1.0f);
      const float top = at(x0, y0) + (at(x1, y0) - at(x0, y0)) * fx;
      const float bottom = at(x0, y1) + (at(x1, y1) - at(x0, y1)) * fx;
      const double delta =
          (1.0 / distance(x, y) - (top + (bottom - top) * fy)) / options.coarse_agreement;
      factor[std::size_t(y) * distance.width() + x] = float(std::exp(-delta * delta));
    }
  }
  return factor;
}

}  // namespace omnisweep::depth
