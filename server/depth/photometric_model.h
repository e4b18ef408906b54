// Each camera's photometric response, estimated from what the cameras see in common, and undone:
// a gain per channel (exposure, white balance) and a radial vignetting,
//   value = gain[k] * V(theta) * radiance,  V(theta) = 1 + b1 t^2 + b2 t^4,  t = theta / 110 deg,
// theta the angle of the pixel's ray from the optical axis. The gains are fixed up to one common
// factor per channel: their geometric mean over the cameras is 1.
//
// Estimation (estimate_photometry): the images are reduced to the mean colour of cells of about
// 1/128 of their width (usable pixels only); directions spread evenly over the sphere are taken to
// a point at `distance` from the rig's centre and projected into every camera that sees it; each
// pair of cameras gives the log ratio of their cell colours, and a robust (Huber) Gauss-Newton fit
// of the 5 parameters per camera explains them. A low-order model over tens of thousands of pairs
// cannot take up texture, parallax (the point's true distance is unknown) or occlusion, which
// stay in the residuals. Written by hand: it is a 20-parameter least-squares problem that Eigen
// solves in a few lines, with no library here that fits it.
#pragma once

#include <array>
#include <future>
#include <optional>
#include <vector>

#include "omnisweep/image/image.h"
#include "omnisweep/rig/rig.h"

namespace omnisweep::depth {

struct CameraPhotometry {
  std::array<double, 3> gain = {1.0, 1.0, 1.0};
  double b1 = 0.0;
  double b2 = 0.0;
  // V at `theta` radians off the optical axis (at least 0.05).
  double vignetting(double theta) const;
};

struct PhotometryFit {
  std::vector<CameraPhotometry> cameras;
  int pairs = 0;            // camera pairs (times channels) the fit used
  double rms_residual = 0;  // of the log ratios it explains, over the inliers
};

struct PhotometryOptions {
  int directions = 6000;  // spread over the sphere
  double distance = 2.0;  // metres from the rig's centre, where the directions are taken
  int iterations = 6;     // Gauss-Newton steps
};

// `images` at their cameras' resolution in `rig`; `usable` as for DepthEstimator (any
// resolution, nullopt = all usable). Throws std::invalid_argument on mismatched inputs.
PhotometryFit estimate_photometry(const Rig& rig, std::span<const Rgb8View> images,
                                  const std::vector<std::optional<Gray8Image>>& usable,
                                  const PhotometryOptions& options = {});

// One camera's (theta / 110 deg)^2 per pixel, pixel after pixel, -1 where it has no ray: the
// variable of V, for PhotometricCorrection and GpuPhotometricCorrection. Rounded to 16-bit
// floats, as the GPU stores them (half the table's bytes each frame; a change of V below 1e-3).
std::vector<float> vignetting_angles(const RigCamera& camera);

// Undoes the responses of a fit: every pixel divided by its camera's gain and vignetting (and
// clamped to 255). The per-pixel angles are computed once, for the cameras of `rig`.
class PhotometricCorrection {
 public:
  explicit PhotometricCorrection(const Rig& rig);
  // images[i] is camera cameras[i] (all cameras in order when `cameras` is empty), at its size
  // in the rig.
  void apply(const PhotometryFit& fit, std::vector<Rgb8Image>& images,
             const std::vector<int>& cameras = {}) const;

 private:
  std::vector<std::vector<float>> t2_;  // per camera and pixel: (theta / 110 deg)^2, -1 = no ray
  std::vector<std::pair<int, int>> sizes_;
};

// Frame after frame (omnisweep-process, omnisweep-server, DepthOptions::correct_photometry):
// estimates the responses on the matching images, for pipeline::GpuFrame to undo on the GPU in
// the matching images and in the colour images of the references, so the sweep and the
// panorama's colour both see the scene's own colours.
class PhotometricCorrector {
 public:
  // `usable` (at the matching resolution) must outlive this. The responses are estimated on the
  // first frame and again every `refresh_every` frames (exposure and white balance change
  // slowly; a stream need not pay for the fit every frame). With `refit_in_background` (the
  // server), a refit after the first runs on its own thread on a copy of its frame's images, and
  // the frames go on with the last fit until it is done, so no frame waits for a fit but the
  // first; without (omnisweep-process), each fit is its own frame's.
  PhotometricCorrector(const Rig& matching_rig,
                       const std::vector<std::optional<Gray8Image>>& usable, int refresh_every = 1,
                       bool refit_in_background = false);
  ~PhotometricCorrector();  // waits for a refit still running
  PhotometricCorrector(const PhotometricCorrector&) = delete;
  PhotometricCorrector& operator=(const PhotometricCorrector&) = delete;

  // `matching`: every camera, as captured (uncorrected). The fit to undo in this frame; it stays
  // valid until the next call.
  const PhotometryFit& fit(std::span<const Rgb8View> matching);
  const PhotometryFit& last() const { return last_; }
  // With refit_in_background: waits for the refit running (if any) and takes its result, so
  // the next fit() returns it.
  void finish_refit();

 private:
  Rig matching_rig_;
  const std::vector<std::optional<Gray8Image>>* usable_;
  int refresh_every_;
  bool refit_in_background_;
  long frames_ = 0;
  PhotometryFit last_;
  std::future<PhotometryFit> refit_;
};

}  // namespace omnisweep::depth
