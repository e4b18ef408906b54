#include "server/synthetic/synthetic_rig.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace omnisweep::synthetic {
namespace {

constexpr double kPi = std::numbers::pi;

Eigen::Quaterniond rotation_ypr(double yaw_deg, double pitch_deg, double roll_deg) {
  const double d = kPi / 180.0;
  return Eigen::Quaterniond(Eigen::AngleAxisd(yaw_deg * d, Eigen::Vector3d::UnitY()) *
                            Eigen::AngleAxisd(pitch_deg * d, Eigen::Vector3d::UnitX()) *
                            Eigen::AngleAxisd(roll_deg * d, Eigen::Vector3d::UnitZ()));
}

// Path of the rig centre: a closed loop about 2.4 m x 1.6 m, starting at the origin.
Eigen::Vector3d path_position(double s) {
  return {1.2 * std::sin(2 * kPi * s), 0.05 * std::sin(4 * kPi * s),
          0.8 * (1 - std::cos(2 * kPi * s))};
}

}  // namespace

void SyntheticRigOptions::check() const {
  if (image_size < 16 || image_size > 8192) {
    throw std::invalid_argument("image size " + std::to_string(image_size) +
                                " must be within [16, 8192]");
  }
  if (frames_per_loop < 1) throw std::invalid_argument("frames per loop must be >= 1");
  if (!(lens_half_fov_deg > 0 && lens_half_fov_deg <= 180)) {
    throw std::invalid_argument("lens half field of view must be within (0, 180] degrees");
  }
  if (references.empty()) throw std::invalid_argument("at least one reference camera is needed");
  photometric.check();
}

Rig default_synthetic_rig(int image_size) {
  // Camera 0 looks forward (+z), 1 backward, 2 left (-x) and 3 right (+x); 2 and 3 sit 7 cm
  // higher, like the paper's prototype. Small mounting tilts keep the rig from being ideal.
  struct Mount {
    double yaw, pitch, roll;
    Eigen::Vector3d position;
  };
  const Mount mounts[4] = {{0.0, 0.0, 0.0, {0.0, 0.0, 0.0}},
                           {180.0, 0.4, -0.3, {-0.002, 0.001, -0.062}},
                           {-90.0, -0.5, 0.6, {-0.034, -0.070, -0.031}},
                           {90.0, 0.3, -0.4, {0.031, -0.069, -0.030}}};
  Rig rig;
  const double s = image_size / 1216.0;
  for (int c = 0; c < 4; ++c) {
    const double f = 272.0 * (1.0 + 0.004 * c);
    const double cx = 607.5 + 1.5 * (c - 1.5), cy = 607.5 - 1.0 * (c - 1.5);
    RigCamera cam;
    cam.model =
        DoubleSphereCamera<double>({f, f * 0.995, cx, cy, -0.2 + 0.01 * c, 0.6 - 0.005 * c});
    cam.width = cam.height = 1216;
    cam.rig_from_cam =
        Rigid3d(rotation_ypr(mounts[c].yaw, mounts[c].pitch, mounts[c].roll), mounts[c].position);
    rig.cameras.push_back(s == 1.0 ? cam : cam.resized(image_size, image_size));
  }
  return rig;
}

SyntheticRig::SyntheticRig(const SyntheticRigOptions& options, const Rig* calibration)
    : options_(options),
      rig_(calibration ? *calibration : default_synthetic_rig(options.image_size)) {
  options_.check();
  rig_.check();
  for (int r : options_.references) {
    if (r < 0 || r >= rig_.num_cameras()) {
      throw std::invalid_argument("reference camera " + std::to_string(r) +
                                  " does not exist (the rig has " +
                                  std::to_string(rig_.num_cameras()) + " cameras)");
    }
  }
  std::vector<Eigen::Vector3f> path;
  for (int i = 0; i < 256; ++i) path.push_back(path_position(i / 256.0).cast<float>());
  scene_ = Scene::hall(options_.seed, path);
  for (int c = 0; c < rig_.num_cameras(); ++c)
    responses_.push_back(draw_camera_response(options_.photometric, options_.seed, c));
}

Eigen::Vector3d SyntheticRig::viewpoint() const {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int r : options_.references) sum += rig_.cameras[r].center_in_rig();
  return sum / double(options_.references.size());
}

Rigid3d SyntheticRig::world_from_rig(int index) const {
  if (options_.static_rig) index = 0;
  const int n = options_.frames_per_loop;
  const double s = double(((index % n) + n) % n) / n;
  const double yaw = 0.35 * std::sin(2 * kPi * s);
  return Rigid3d(Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY())),
                 path_position(s));
}

std::vector<Gray8Image> SyntheticRig::masks() const {
  std::vector<Gray8Image> out;
  for (const RigCamera& cam : rig_.cameras)
    out.push_back(lens_mask(cam, options_.lens_half_fov_deg * kPi / 180));
  return out;
}

SyntheticFrame SyntheticRig::render(int index, int panorama_width, int panorama_height) const {
  SyntheticFrame frame;
  frame.world_from_rig = world_from_rig(index);
  for (int c = 0; c < rig_.num_cameras(); ++c) {
    const RigCamera& cam = rig_.cameras[c];
    frame.cameras.push_back(render_camera(scene_, cam, frame.world_from_rig,
                                          options_.lens_half_fov_deg * kPi / 180,
                                          options_.photometric.any()));
    // Noise differs from frame to frame and camera to camera, and repeats with the seed.
    const std::uint64_t noise_seed =
        (options_.seed * 0x9e3779b97f4a7c15ull) ^ (std::uint64_t(index) << 8) ^ std::uint64_t(c);
    RenderedImage& image = frame.cameras.back();
    apply_camera_response(options_.photometric, responses_[c], cam, noise_seed, image.radiance,
                          &image.rgb);
    image.radiance = {};  // the sensor's output is `rgb`; the float copy is 12 bytes a pixel
  }
  frame.panorama =
      render_panorama(scene_, frame.world_from_rig, viewpoint(), panorama_width, panorama_height);
  return frame;
}

RenderedImage SyntheticRig::render_panorama_at(int index, const Eigen::Vector3d& viewpoint_in_rig,
                                               int width, int height) const {
  return render_panorama(scene_, world_from_rig(index), viewpoint_in_rig, width, height);
}

}  // namespace omnisweep::synthetic
