#include "server/stitch/blend_weights.h"

#include <algorithm>
#include <cmath>

#include "omnisweep/geometry/equirectangular.h"

namespace omnisweep::stitch {
namespace {

// 1D running-sum box along x or y. Outside the image: wrap (x only) or `border`.
FloatImage box_1d(const FloatImage& in, int size, bool along_x, bool wrap, float border) {
  const int w = in.width(), h = in.height(), r = size / 2;
  FloatImage out(w, h);
  const int n = along_x ? w : h, lines = along_x ? h : w;
  std::vector<double> line(n);
  auto at = [&](int line_index, int i) -> float {
    if (i < 0 || i >= n) {
      if (!wrap) return border;
      i = ((i % n) + n) % n;
    }
    return along_x ? in(i, line_index) : in(line_index, i);
  };
  for (int l = 0; l < lines; ++l) {
    double sum = 0;
    for (int i = -r; i <= r; ++i) sum += at(l, i);
    for (int i = 0; i < n; ++i) {
      const float value = float(sum / size);
      (along_x ? out(i, l) : out(l, i)) = value;
      sum += at(l, i + r + 1) - at(l, i - r);
    }
  }
  return out;
}

float bilinear(const FloatImage& im, const Eigen::Vector2d& uv) {
  const int x0 = int(std::floor(uv.x())), y0 = int(std::floor(uv.y()));
  const double tx = uv.x() - x0, ty = uv.y() - y0;
  auto at = [&](int x, int y) {
    return double(im(std::clamp(x, 0, im.width() - 1), std::clamp(y, 0, im.height() - 1)));
  };
  return float((1 - ty) * ((1 - tx) * at(x0, y0) + tx * at(x0 + 1, y0)) +
               ty * ((1 - tx) * at(x0, y0 + 1) + tx * at(x0 + 1, y0 + 1)));
}

}  // namespace

FloatImage box_filter(const FloatImage& image, int size, bool wrap_x, float border) {
  return box_1d(box_1d(image, size, true, wrap_x, border), size, false, false, border);
}

std::vector<FloatImage> blend_weights(const BlendSetup& s) {
  const int pw = s.panorama_width, ph = s.panorama_height;
  std::vector<FloatImage> weights;
  for (int ref : s.references) {
    const RigCamera& cam = s.rig->cameras[ref];
    const double w = cam.width, h = cam.height;
    // The usable mask smoothed with a 31x31 box, the border padded with 1.
    FloatImage mask = FloatImage::filled(cam.width, cam.height, 1.0f);
    if (!s.usable.empty() && s.usable[ref]) {
      for (std::size_t i = 0; i < mask.size(); ++i)
        mask.data()[i] = s.usable[ref]->data()[i] ? 1.0f : 0.0f;
    }
    const FloatImage smooth_mask = box_filter(mask, 31, false, 1.0f);
    const Eigen::Matrix3d cam_from_rig = cam.rig_from_cam.rotation.conjugate().toRotationMatrix();
    const Eigen::Vector3d t_c = cam_from_rig * (s.viewpoint_in_rig - cam.rig_from_cam.translation);
    auto clamp_px = [&](Eigen::Vector2d p) {
      return Eigen::Vector2d(std::clamp(p.x(), 0.1, w - 1.1), std::clamp(p.y(), 0.1, h - 1.1));
    };
    FloatImage out(pw, ph);
    for (int y = 0; y < ph; ++y) {
      for (int x = 0; x < pw; ++x) {
        const Eigen::Vector3d dir = cam_from_rig * equirect_direction<double>(x, y, pw, ph);
        Eigen::Vector2d uv, near_px, far_px;
        // ALGORITHM.md §5 step 3 as written: d_min dir - t_c and d_max dir - t_c. All three are
        // projected (near_px and far_px are used below whether or not they are valid).
        const bool sees = cam.model.project(dir, &uv);
        const bool sees_near = cam.model.project(s.min_distance * dir - t_c, &near_px);
        const bool sees_far = cam.model.project(s.max_distance * dir - t_c, &far_px);
        const bool valid = sees && sees_near && sees_far;
        near_px = clamp_px(near_px);
        far_px = clamp_px(far_px);
        float weight = 1e-8f;
        if (valid && bilinear(smooth_mask, near_px) > 0.99f &&
            bilinear(smooth_mask, far_px) > 0.99f) {
          weight = float(std::exp(-(far_px - near_px).squaredNorm() / (1e-4 * w * h)));
        }
        out(x, y) = weight;
      }
    }
    weights.push_back(std::move(out));
  }
  auto normalise = [&] {
    for (int i = 0; i < pw * ph; ++i) {
      double total = 0;
      for (const auto& wgt : weights) total += wgt.data()[i];
      for (auto& wgt : weights) wgt.data()[i] = float(wgt.data()[i] / total);
    }
  };
  normalise();
  for (auto& wgt : weights) wgt = box_filter(wgt, 31, true, 0.0f);
  normalise();
  return weights;
}

}  // namespace omnisweep::stitch
