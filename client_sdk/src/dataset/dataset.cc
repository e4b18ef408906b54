#include "omnisweep/dataset/dataset.h"

#include <algorithm>
#include <array>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <system_error>

#include "omnisweep/image/image_io.h"
#include "omnisweep/rig/basalt_calibration.h"

namespace omnisweep {
namespace fs = std::filesystem;
namespace {

constexpr std::array<std::string_view, 10> kImageExtensions = {
    ".jpg", ".jpeg", ".png", ".bmp", ".tif", ".tiff", ".exr", ".ppm", ".pgm", ".webp"};

bool is_image_file(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return std::ranges::find(kImageExtensions, ext) != kImageExtensions.end();
}

fs::path camera_dir(const fs::path& root, int camera) {
  return root / ("cam" + std::to_string(camera));
}

// The one image file of `frame` in a camera folder; throws DatasetError when missing or ambiguous.
fs::path find_frame_image(const fs::path& dir, const std::string& frame) {
  std::vector<fs::path> found;
  for (std::string_view ext : kImageExtensions) {
    std::string upper(ext);
    std::transform(upper.begin(), upper.end(), upper.begin(),
                   [](unsigned char c) { return std::toupper(c); });
    for (const std::string& e : {std::string(ext), upper}) {
      const fs::path p = dir / (frame + e);
      std::error_code ec;
      if (fs::is_regular_file(p, ec) && std::ranges::find(found, p) == found.end())
        found.push_back(p);
    }
  }
  if (found.empty()) throw DatasetError((dir / frame).string() + ".*: image is missing");
  if (found.size() > 1) {
    throw DatasetError(found[0].string() + ": ambiguous, " + found[1].filename().string() +
                       " has the same frame name");
  }
  return found[0];
}

// dataset.json: every field optional, each checked (DatasetError naming the file and field).
DatasetHints read_hints(const fs::path& path, const Rig& rig) {
  std::ifstream in(path);
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw DatasetError(path.string() + ": not JSON: " + e.what());
  }
  if (!json.is_object()) throw DatasetError(path.string() + ": expected a JSON object");
  auto fail = [&](const std::string& field, const std::string& what) {
    throw DatasetError(path.string() + ": \"" + field + "\" " + what);
  };
  auto number = [&](const std::string& field) -> std::optional<double> {
    if (!json.contains(field)) return std::nullopt;
    if (!json[field].is_number() || !(json[field].get<double>() > 0))
      fail(field, "must be a positive number of metres");
    return json[field].get<double>();
  };
  DatasetHints hints;
  if (json.contains("references")) {
    const auto& refs = json["references"];
    if (!refs.is_array() || refs.empty()) fail("references", "must be a non-empty array");
    for (const auto& r : refs) {
      if (!r.is_number_integer() || r.get<int>() < 0 || r.get<int>() >= rig.num_cameras()) {
        fail("references",
             "must list cameras 0-" + std::to_string(rig.num_cameras() - 1) + ", has " + r.dump());
      }
      hints.references.push_back(r.get<int>());
    }
  }
  if (json.contains("viewpoint")) {
    const auto& v = json["viewpoint"];
    if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() ||
        !v[2].is_number())
      fail("viewpoint", "must be [x, y, z] in metres");
    hints.viewpoint = Eigen::Vector3d(v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
  }
  hints.min_distance = number("min_dist");
  hints.max_distance = number("max_dist");
  if (hints.min_distance && hints.max_distance && *hints.max_distance <= *hints.min_distance)
    fail("max_dist", "must exceed min_dist");
  return hints;
}

}  // namespace

bool natural_less(const std::string& a, const std::string& b) {
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (std::isdigit(static_cast<unsigned char>(a[i])) &&
        std::isdigit(static_cast<unsigned char>(b[j]))) {
      std::size_t i2 = i, j2 = j;
      while (i2 < a.size() && std::isdigit(static_cast<unsigned char>(a[i2]))) ++i2;
      while (j2 < b.size() && std::isdigit(static_cast<unsigned char>(b[j2]))) ++j2;
      std::string_view na(a.data() + i, i2 - i), nb(b.data() + j, j2 - j);
      while (na.size() > 1 && na.front() == '0') na.remove_prefix(1);
      while (nb.size() > 1 && nb.front() == '0') nb.remove_prefix(1);
      if (na.size() != nb.size()) return na.size() < nb.size();
      if (na != nb) return na < nb;
      i = i2;
      j = j2;
    } else {
      if (a[i] != b[j]) return a[i] < b[j];
      ++i;
      ++j;
    }
  }
  return a.size() - i < b.size() - j || (a.size() - i == b.size() - j && a < b);
}

Dataset Dataset::open(const fs::path& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw DatasetError(dir.string() + ": dataset folder does not exist");
  Dataset ds;
  ds.dir_ = dir;
  ds.rig_ = read_basalt_calibration(dir / "calibration.json");
  std::set<std::string> names;
  for (int c = 0; c < ds.rig_.num_cameras(); ++c) {
    const fs::path cam_dir = camera_dir(dir, c);
    if (!fs::is_directory(cam_dir, ec)) {
      throw DatasetError(cam_dir.string() + ": camera folder is missing (calibration.json has " +
                         std::to_string(ds.rig_.num_cameras()) + " cameras)");
    }
    for (const auto& entry : fs::directory_iterator(cam_dir, ec)) {
      if (!entry.is_regular_file() || !is_image_file(entry.path())) continue;
      const std::string stem = entry.path().stem().string();
      if (stem != "mask") names.insert(stem);
    }
    if (ec) throw DatasetError(cam_dir.string() + ": cannot list folder: " + ec.message());
    const fs::path mask_path = cam_dir / "mask.png";
    if (fs::exists(mask_path, ec)) {
      try {
        Gray8Image mask = read_gray8_image(mask_path);
        const RigCamera& cam = ds.rig_.cameras[c];
        if (mask.width() != cam.width || mask.height() != cam.height) {
          throw DatasetError(mask_path.string() + ": mask is " + std::to_string(mask.width()) +
                             "x" + std::to_string(mask.height()) + ", calibration says " +
                             std::to_string(cam.width) + "x" + std::to_string(cam.height));
        }
        ds.masks_.emplace_back(std::move(mask));
      } catch (const ImageIoError& e) {
        throw DatasetError(e.what());
      }
    } else {
      ds.masks_.emplace_back(std::nullopt);
    }
  }
  ds.frames_.assign(names.begin(), names.end());
  std::sort(ds.frames_.begin(), ds.frames_.end(), natural_less);
  if (fs::exists(dir / "dataset.json", ec)) ds.hints_ = read_hints(dir / "dataset.json", ds.rig_);
  return ds;
}

bool Dataset::has_ground_truth() const {
  std::error_code ec;
  return fs::is_directory(dir_ / "gt", ec);
}

Frame Dataset::load_frame(const std::string& name) const {
  Frame frame;
  frame.name = name;
  try {
    for (int c = 0; c < rig_.num_cameras(); ++c) {
      const fs::path path = find_frame_image(camera_dir(dir_, c), name);
      AnyImage image = read_color_image(path);
      const RigCamera& cam = rig_.cameras[c];
      if (width_of(image) != cam.width || height_of(image) != cam.height) {
        throw DatasetError(path.string() + ": image is " + std::to_string(width_of(image)) + "x" +
                           std::to_string(height_of(image)) + ", calibration says " +
                           std::to_string(cam.width) + "x" + std::to_string(cam.height));
      }
      frame.images.push_back(std::move(image));
    }
    const fs::path gt_rgb = dir_ / "gt" / ("rgb_" + name + ".png");
    const fs::path gt_inv = dir_ / "gt" / ("inv_distance_" + name + ".exr");
    std::error_code ec;
    if (fs::exists(gt_rgb, ec) || fs::exists(gt_inv, ec)) {
      GroundTruth gt;
      gt.rgb = to_rgb8(read_color_image(gt_rgb));
      gt.inverse_distance = read_exr(gt_inv);
      if (gt.rgb.width() != gt.inverse_distance.width() ||
          gt.rgb.height() != gt.inverse_distance.height()) {
        throw DatasetError(gt_inv.string() + ": ground truth is " +
                           std::to_string(gt.inverse_distance.width()) + "x" +
                           std::to_string(gt.inverse_distance.height()) + ", its colour panorama " +
                           std::to_string(gt.rgb.width()) + "x" + std::to_string(gt.rgb.height()));
      }
      for (int c = 0; c < rig_.num_cameras(); ++c) {
        const fs::path p =
            dir_ / "gt" / ("cam" + std::to_string(c)) / ("inv_distance_" + name + ".exr");
        if (fs::exists(p, ec)) {
          gt.camera_inverse_distance.emplace_back(read_exr(p));
        } else {
          gt.camera_inverse_distance.emplace_back(std::nullopt);
        }
      }
      frame.ground_truth = std::move(gt);
    }
  } catch (const ImageIoError& e) {
    throw DatasetError("frame '" + name + "': " + e.what());
  } catch (const DatasetError& e) {
    throw DatasetError("frame '" + name + "': " + e.what());
  }
  return frame;
}

std::optional<Frame> Dataset::try_load_frame(const std::string& name, SkippedFrame* skipped) const {
  try {
    return load_frame(name);
  } catch (const DatasetError& e) {
    *skipped = {name, e.what()};
    return std::nullopt;
  }
}

std::vector<SkippedFrame> Dataset::for_each_frame(
    const std::vector<std::string>& names, const std::function<void(Frame&&)>& on_frame,
    const std::function<void(const SkippedFrame&)>& on_skip) const {
  std::vector<SkippedFrame> skipped;
  for (const std::string& name : names.empty() ? frames_ : names) {
    SkippedFrame why;
    if (auto frame = try_load_frame(name, &why)) {
      on_frame(std::move(*frame));
    } else {
      if (on_skip) on_skip(why);
      skipped.push_back(std::move(why));
    }
  }
  return skipped;
}

DatasetWriter::DatasetWriter(const fs::path& dir, const Rig& rig) : dir_(dir), rig_(rig) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  for (int c = 0; c < rig.num_cameras() && !ec; ++c) fs::create_directories(camera_dir(dir, c), ec);
  if (ec) throw DatasetError(dir.string() + ": cannot create dataset folder: " + ec.message());
  write_basalt_calibration(rig, dir / "calibration.json");
}

void DatasetWriter::write_hints(const DatasetHints& hints) const {
  nlohmann::json json = nlohmann::json::object();
  if (!hints.references.empty()) json["references"] = hints.references;
  if (hints.viewpoint)
    json["viewpoint"] = {hints.viewpoint->x(), hints.viewpoint->y(), hints.viewpoint->z()};
  if (hints.min_distance) json["min_dist"] = *hints.min_distance;
  if (hints.max_distance) json["max_dist"] = *hints.max_distance;
  std::ofstream out(dir_ / "dataset.json");
  out << json.dump(1) << "\n";
  if (!out) throw DatasetError((dir_ / "dataset.json").string() + ": cannot write");
}

void DatasetWriter::write_mask(int camera, Gray8View mask) const {
  write_png(camera_dir(dir_, camera) / "mask.png", mask);
}

void DatasetWriter::write_images(const std::string& name,
                                 const std::vector<Rgb8Image>& images) const {
  if (int(images.size()) != rig_.num_cameras()) {
    throw DatasetError(dir_.string() + ": frame '" + name + "' has " +
                       std::to_string(images.size()) + " images for " +
                       std::to_string(rig_.num_cameras()) + " cameras");
  }
  for (int c = 0; c < rig_.num_cameras(); ++c) {
    write_png(camera_dir(dir_, c) / (name + ".png"), images[c], 1);
  }
}

void DatasetWriter::write_ground_truth(const std::string& name, Rgb8View rgb,
                                       FloatView inverse_distance) const {
  std::error_code ec;
  fs::create_directories(dir_ / "gt", ec);
  write_png(dir_ / "gt" / ("rgb_" + name + ".png"), rgb, 1);
  write_exr(dir_ / "gt" / ("inv_distance_" + name + ".exr"), inverse_distance);
}

void DatasetWriter::write_camera_ground_truth(const std::string& name, int camera,
                                              FloatView inverse_distance) const {
  const fs::path dir = dir_ / "gt" / ("cam" + std::to_string(camera));
  std::error_code ec;
  fs::create_directories(dir, ec);
  write_exr(dir / ("inv_distance_" + name + ".exr"), inverse_distance);
}

}  // namespace omnisweep
