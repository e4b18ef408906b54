// Datasets in the reference layout (ALGORITHM.md §6):
//   calibration.json                  basalt rig calibration
//   cam<i>/<frame>.<ext>              one image per camera and frame (8-bit, 16-bit or float)
//   cam<i>/mask.png                   optional 8-bit mask, 255 where usable
//   gt/rgb_<frame>.png                optional ground-truth colour panorama
//   gt/inv_distance_<frame>.exr       optional ground-truth inverse distance panorama (float32)
//   gt/cam<i>/inv_distance_<frame>.exr  optional per-camera inverse distance (our synthetic rig)
//   dataset.json                      optional: what the dataset was made for ("references",
//                                     "viewpoint" [x, y, z] in the rig frame, "min_dist",
//                                     "max_dist"): the tools' defaults, under their flags
// Frames are the image stems found in the camera folders, in natural order ("2" before "10").
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "omnisweep/image/image.h"
#include "omnisweep/rig/rig.h"

namespace omnisweep {

class DatasetError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct GroundTruth {
  Rgb8Image rgb;                // equirectangular colour panorama (ALGORITHM.md §5)
  FloatImage inverse_distance;  // same size, m^-1
  std::vector<std::optional<FloatImage>> camera_inverse_distance;  // per camera, when present
};

struct Frame {
  std::string name;
  std::vector<AnyImage> images;  // one per camera, RGB order, as stored
  std::optional<GroundTruth> ground_truth;
};

struct SkippedFrame {
  std::string name;
  std::string reason;  // names the file that was missing, unreadable or wrongly sized
};

// dataset.json's fields (absent ones empty).
struct DatasetHints {
  std::vector<int> references;
  std::optional<Eigen::Vector3d> viewpoint;
  std::optional<double> min_distance;
  std::optional<double> max_distance;
};

class Dataset {
 public:
  // Reads the calibration and masks and lists the frames. Throws DatasetError (or
  // CalibrationError) naming the file when the folder, calibration, a camera folder or a mask
  // is unusable.
  static Dataset open(const std::filesystem::path& dir);

  const std::filesystem::path& dir() const { return dir_; }
  const Rig& rig() const { return rig_; }
  const std::vector<std::string>& frames() const { return frames_; }
  // Per camera; nullopt where there is no mask.png.
  const std::vector<std::optional<Gray8Image>>& masks() const { return masks_; }
  const DatasetHints& hints() const { return hints_; }
  bool has_ground_truth() const;

  // Loads one frame; throws DatasetError naming the frame and the file at fault.
  Frame load_frame(const std::string& name) const;
  // Loads one frame, or returns nullopt and fills *skipped when it cannot be used.
  std::optional<Frame> try_load_frame(const std::string& name, SkippedFrame* skipped) const;
  // Calls on_frame for every loadable frame of `names` (all frames when empty) in order and
  // on_skip for every other one; returns the skipped frames.
  std::vector<SkippedFrame> for_each_frame(
      const std::vector<std::string>& names, const std::function<void(Frame&&)>& on_frame,
      const std::function<void(const SkippedFrame&)>& on_skip = {}) const;

 private:
  std::filesystem::path dir_;
  Rig rig_;
  std::vector<std::string> frames_;
  std::vector<std::optional<Gray8Image>> masks_;
  DatasetHints hints_;
};

// Writes a dataset in the reference layout (the synthetic rig uses it).
class DatasetWriter {
 public:
  // Creates `dir` (and parents) and writes calibration.json.
  DatasetWriter(const std::filesystem::path& dir, const Rig& rig);

  void write_mask(int camera, Gray8View mask) const;
  // Writes dataset.json with the fields `hints` has.
  void write_hints(const DatasetHints& hints) const;
  // Writes cam<i>/<name>.png for every camera (8-bit RGB images sized as calibrated).
  void write_images(const std::string& name, const std::vector<Rgb8Image>& images) const;
  void write_ground_truth(const std::string& name, Rgb8View rgb, FloatView inverse_distance) const;
  void write_camera_ground_truth(const std::string& name, int camera,
                                 FloatView inverse_distance) const;

 private:
  std::filesystem::path dir_;
  Rig rig_;
};

// "0" < "2" < "10" < "a": digit runs compare by value.
bool natural_less(const std::string& a, const std::string& b);

}  // namespace omnisweep
