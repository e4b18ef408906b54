#include "server/depth/photometric_model.h"

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace omnisweep::depth {
namespace {

constexpr double kReferenceAngle = 110.0 * std::numbers::pi / 180.0;
constexpr int kParams = 5;  // per camera: log gain R, G, B, b1, b2

// One camera's image as the mean colour of cells (usable pixels only).
struct CellImage {
  int cell = 1, cols = 0, rows = 0;
  std::vector<std::array<float, 3>> mean;
  std::vector<float> usable;  // fraction of the cell's pixels that are usable
};

CellImage reduce(Rgb8View image, const Gray8Image* mask) {
  CellImage out;
  out.cell = std::max(1, image.width() / 128);
  out.cols = (image.width() + out.cell - 1) / out.cell;
  out.rows = (image.height() + out.cell - 1) / out.cell;
  std::vector<std::array<double, 3>> sum(std::size_t(out.cols) * out.rows, {0, 0, 0});
  std::vector<int> count(sum.size(), 0), total(sum.size(), 0);
  for (int y = 0; y < image.height(); ++y) {
    const int my = mask ? y * mask->height() / image.height() : 0;
    for (int x = 0; x < image.width(); ++x) {
      const std::size_t c = std::size_t(y / out.cell) * out.cols + x / out.cell;
      ++total[c];
      if (mask && (*mask)(x * mask->width() / image.width(), my) == 0) continue;
      ++count[c];
      for (int k = 0; k < 3; ++k) sum[c][k] += image(x, y, k);
    }
  }
  out.mean.resize(sum.size());
  out.usable.resize(sum.size());
  for (std::size_t c = 0; c < sum.size(); ++c) {
    for (int k = 0; k < 3; ++k) out.mean[c][k] = count[c] ? float(sum[c][k] / count[c]) : 0.0f;
    out.usable[c] = total[c] ? float(count[c]) / float(total[c]) : 0.0f;
  }
  return out;
}

struct Sample {
  int a, b;         // cameras
  double ta, tb;    // (theta / 110 deg)^2
  double ratio[3];  // log(a's colour / b's colour) per channel; NaN where not usable
};

double log_vignetting(const Eigen::VectorXd& p, int camera, double t2) {
  const double v = 1.0 + p[camera * kParams + 3] * t2 + p[camera * kParams + 4] * t2 * t2;
  return std::log(std::max(v, 0.05));
}

}  // namespace

double CameraPhotometry::vignetting(double theta) const {
  const double t2 = (theta / kReferenceAngle) * (theta / kReferenceAngle);
  return std::max(0.05, 1.0 + b1 * t2 + b2 * t2 * t2);
}

PhotometryFit estimate_photometry(const Rig& rig, std::span<const Rgb8View> images,
                                  const std::vector<std::optional<Gray8Image>>& usable,
                                  const PhotometryOptions& options) {
  const int n = rig.num_cameras();
  if (int(images.size()) != n || (!usable.empty() && int(usable.size()) != n)) {
    throw std::invalid_argument("photometry: expected one image and one mask (or none) per camera");
  }
  std::vector<CellImage> cells;
  for (int c = 0; c < n; ++c) {
    if (images[c].width() != rig.cameras[c].width || images[c].height() != rig.cameras[c].height) {
      throw std::invalid_argument("photometry: the image of camera " + std::to_string(c) +
                                  " is not at its calibrated size");
    }
    cells.push_back(reduce(images[c], usable.empty() || !usable[c] ? nullptr : &*usable[c]));
  }
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  std::vector<Rigid3d> cam_from_rig;
  for (const auto& cam : rig.cameras) {
    centre += cam.center_in_rig() / n;
    cam_from_rig.push_back(cam.rig_from_cam.inverse());
  }

  // Directions on a Fibonacci sphere, each seen by every camera whose usable cells it falls in.
  std::vector<Sample> samples;
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < options.directions; ++i) {
    const double z = 1.0 - 2.0 * (i + 0.5) / options.directions, r = std::sqrt(1.0 - z * z);
    const Eigen::Vector3d dir(r * std::cos(golden * i), r * std::sin(golden * i), z);
    const Eigen::Vector3d point = centre + options.distance * dir;
    struct Seen {
      int camera;
      double t2;
      std::array<float, 3> color;
    };
    std::vector<Seen> seen;
    for (int c = 0; c < n; ++c) {
      const Eigen::Vector3d p = cam_from_rig[c] * point;
      Eigen::Vector2d uv;
      if (!rig.cameras[c].model.project(p, &uv)) continue;
      const int cx = int(std::floor((uv.x() + 0.5) / cells[c].cell)),
                cy = int(std::floor((uv.y() + 0.5) / cells[c].cell));
      if (cx < 0 || cy < 0 || cx >= cells[c].cols || cy >= cells[c].rows) continue;
      const std::size_t cell = std::size_t(cy) * cells[c].cols + cx;
      if (cells[c].usable[cell] < 0.99f) continue;
      const double theta = std::acos(std::clamp(p.normalized().z(), -1.0, 1.0)) / kReferenceAngle;
      seen.push_back({c, theta * theta, cells[c].mean[cell]});
    }
    for (std::size_t i1 = 0; i1 < seen.size(); ++i1) {
      for (std::size_t i2 = i1 + 1; i2 < seen.size(); ++i2) {
        Sample s{seen[i1].camera, seen[i2].camera, seen[i1].t2, seen[i2].t2, {}};
        bool any = false;
        for (int k = 0; k < 3; ++k) {
          const double va = seen[i1].color[k], vb = seen[i2].color[k];
          // Dark cells are noise, bright ones may be clipped.
          s.ratio[k] = va > 8 && vb > 8 && va < 247 && vb < 247 ? std::log(va / vb) : std::nan("");
          any = any || !std::isnan(s.ratio[k]);
        }
        if (any) samples.push_back(s);
      }
    }
  }

  // Robust Gauss-Newton: residual = ratio - (g_a - g_b + log V_a - log V_b), Huber weights; the
  // gauge (log gains of each channel sum to 0 over the cameras) as heavy extra rows.
  Eigen::VectorXd p = Eigen::VectorXd::Zero(Eigen::Index(n) * kParams);
  const double huber = 0.05;
  PhotometryFit fit;
  for (int iteration = 0; iteration < options.iterations; ++iteration) {
    Eigen::MatrixXd normal =
        Eigen::MatrixXd::Zero(Eigen::Index(n) * kParams, Eigen::Index(n) * kParams);
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(Eigen::Index(n) * kParams);
    double squares = 0;
    int inliers = 0, used = 0;
    for (const Sample& s : samples) {
      const double va = log_vignetting(p, s.a, s.ta), vb = log_vignetting(p, s.b, s.tb);
      const double ea = std::exp(va), eb = std::exp(vb);
      for (int k = 0; k < 3; ++k) {
        if (std::isnan(s.ratio[k])) continue;
        const double residual =
            s.ratio[k] - (p[s.a * kParams + k] - p[s.b * kParams + k] + va - vb);
        const double weight = std::abs(residual) <= huber ? 1.0 : huber / std::abs(residual);
        // d(model)/d(parameter), the row of the Jacobian (sparse: 6 entries).
        const std::pair<int, double> row[6] = {
            {s.a * kParams + k, 1.0},        {s.b * kParams + k, -1.0},
            {s.a * kParams + 3, s.ta / ea},  {s.a * kParams + 4, s.ta * s.ta / ea},
            {s.b * kParams + 3, -s.tb / eb}, {s.b * kParams + 4, -s.tb * s.tb / eb}};
        for (const auto& [i, di] : row) {
          rhs[i] += weight * di * residual;
          for (const auto& [j, dj] : row) normal(i, j) += weight * di * dj;
        }
        ++used;
        if (std::abs(residual) <= huber) {
          squares += residual * residual;
          ++inliers;
        }
      }
    }
    const double gauge = 1e3 * std::max(1, used);
    for (int k = 0; k < 3; ++k) {
      double sum = 0;
      for (int c = 0; c < n; ++c) sum += p[c * kParams + k];
      for (int c1 = 0; c1 < n; ++c1) {
        rhs[c1 * kParams + k] -= gauge * sum;
        for (int c2 = 0; c2 < n; ++c2) normal(c1 * kParams + k, c2 * kParams + k) += gauge;
      }
    }
    normal.diagonal().array() += 1e-6 * std::max(1, used);  // unseen parameters stay put
    p += normal.ldlt().solve(rhs);
    fit.pairs = used;
    fit.rms_residual = inliers ? std::sqrt(squares / inliers) : 0.0;
  }
  for (int c = 0; c < n; ++c) {
    CameraPhotometry cam;
    for (int k = 0; k < 3; ++k) cam.gain[k] = std::exp(p[c * kParams + k]);
    cam.b1 = p[c * kParams + 3];
    cam.b2 = p[c * kParams + 4];
    fit.cameras.push_back(cam);
  }
  return fit;
}

std::vector<float> vignetting_angles(const RigCamera& cam) {
  std::vector<float> t2(std::size_t(cam.width) * cam.height, -1.0f);
  for (int v = 0; v < cam.height; ++v) {
    for (int u = 0; u < cam.width; ++u) {
      Eigen::Vector3d ray;
      if (!cam.model.unproject(Eigen::Vector2d(u, v), &ray)) continue;
      const double t = std::acos(std::clamp(ray.normalized().z(), -1.0, 1.0)) / kReferenceAngle;
      t2[std::size_t(v) * cam.width + u] = float(Eigen::half(float(t * t)));
    }
  }
  return t2;
}

PhotometricCorrection::PhotometricCorrection(const Rig& rig) {
  for (const RigCamera& cam : rig.cameras) {
    t2_.push_back(vignetting_angles(cam));
    sizes_.emplace_back(cam.width, cam.height);
  }
}

void PhotometricCorrection::apply(const PhotometryFit& fit, std::vector<Rgb8Image>& images,
                                  const std::vector<int>& cameras) const {
  for (std::size_t i = 0; i < images.size(); ++i) {
    const int c = cameras.empty() ? int(i) : cameras[i];
    if (c < 0 || c >= int(t2_.size()) || c >= int(fit.cameras.size()))
      throw std::invalid_argument("photometric correction: no camera " + std::to_string(c));
    Rgb8Image& im = images[i];
    if (im.width() != sizes_[c].first || im.height() != sizes_[c].second) {
      throw std::invalid_argument("photometric correction: the image of camera " +
                                  std::to_string(c) + " is not at its calibrated size");
    }
    const CameraPhotometry& response = fit.cameras[c];
    const std::vector<float>& t2 = t2_[c];
#pragma omp parallel for schedule(static)
    for (int y = 0; y < im.height(); ++y) {
      for (int x = 0; x < im.width(); ++x) {
        const float t = t2[std::size_t(y) * im.width() + x];
        if (t < 0) continue;
        const double v = std::max(0.05, 1.0 + response.b1 * t + response.b2 * t * t);
        for (int k = 0; k < 3; ++k) {
          const double value = im(x, y, k) / (response.gain[k] * v);
          im(x, y, k) = std::uint8_t(std::lround(std::min(value, 255.0)));
        }
      }
    }
  }
}

PhotometricCorrector::PhotometricCorrector(const Rig& matching_rig,
                                           const std::vector<std::optional<Gray8Image>>& usable,
                                           int refresh_every, bool refit_in_background)
    : matching_rig_(matching_rig),
      usable_(&usable),
      refresh_every_(std::max(1, refresh_every)),
      refit_in_background_(refit_in_background) {}

PhotometricCorrector::~PhotometricCorrector() {
  if (refit_.valid()) refit_.wait();
}

void PhotometricCorrector::finish_refit() {
  if (refit_.valid()) last_ = refit_.get();
}

const PhotometryFit& PhotometricCorrector::fit(std::span<const Rgb8View> matching) {
  using namespace std::chrono_literals;
  if (refit_.valid() && refit_.wait_for(0s) == std::future_status::ready) last_ = refit_.get();
  if (frames_++ % refresh_every_ != 0) return last_;
  if (!refit_in_background_ || frames_ == 1) {
    last_ = estimate_photometry(matching_rig_, matching, *usable_);
  } else if (!refit_.valid()) {  // (one refit at a time: a slow one skips the next turn)
    std::vector<Rgb8Image> copies;
    for (const Rgb8View& image : matching) copies.push_back(Rgb8Image::copy_of(image));
    refit_ = std::async(std::launch::async, [this, images = std::move(copies)] {
      return estimate_photometry(matching_rig_, views(images), *usable_);
    });
  }
  return last_;
}

}  // namespace omnisweep::depth
