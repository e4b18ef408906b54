#include "omnisweep/rig/basalt_calibration.h"

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <system_error>

#include "rig/json_path_parser.h"

namespace omnisweep {
namespace {

using json_detail::index_path;
using json_detail::join_path;
using nlohmann::json;

std::string format_number(double v) {
  std::ostringstream s;
  s.precision(10);
  s << v;
  return s.str();
}

// Field access that throws CalibrationError naming the source and the JSON path.
class FieldReader {
 public:
  explicit FieldReader(std::string source) : source_(std::move(source)) {}

  [[noreturn]] void fail(const std::string& path, const std::string& what) const {
    throw CalibrationError(source_ + ": " + (path.empty() ? "" : path + ": ") + what);
  }

  const json& member(const json& object, const std::string& path, const std::string& key) const {
    if (!object.is_object())
      fail(path, std::string("expected an object, got ") + object.type_name());
    const auto it = object.find(key);
    if (it == object.end()) fail(join_path(path, key), "missing");
    return *it;
  }

  const json& array(const json& object, const std::string& path, const std::string& key) const {
    const json& value = member(object, path, key);
    if (!value.is_array()) {
      fail(join_path(path, key), std::string("expected an array, got ") + value.type_name());
    }
    return value;
  }

  double number(const json& value, const std::string& path) const {
    if (!value.is_number()) fail(path, std::string("expected a number, got ") + value.type_name());
    const double v = value.get<double>();
    if (!std::isfinite(v)) fail(path, "is not a finite number");
    return v;
  }

  double number(const json& object, const std::string& path, const std::string& key) const {
    return number(member(object, path, key), join_path(path, key));
  }

  int positive_int(const json& value, const std::string& path) const {
    if (!value.is_number_integer() || value.get<std::int64_t>() <= 0 ||
        value.get<std::int64_t>() > 1 << 20) {
      fail(path, "expected a positive integer (pixels), got " + value.dump());
    }
    return value.get<int>();
  }

 private:
  std::string source_;
};

Rigid3d read_pose(const FieldReader& r, const json& entry, const std::string& path) {
  const Eigen::Vector3d t(r.number(entry, path, "px"), r.number(entry, path, "py"),
                          r.number(entry, path, "pz"));
  // Eigen's constructor takes (w, x, y, z).
  Eigen::Quaterniond q(r.number(entry, path, "qw"), r.number(entry, path, "qx"),
                       r.number(entry, path, "qy"), r.number(entry, path, "qz"));
  const double norm = q.norm();
  if (!(std::abs(norm - 1.0) <= kQuaternionNormTolerance)) {
    r.fail(path, "quaternion (qx, qy, qz, qw) has norm " + format_number(norm) +
                     ", too far from 1 (tolerance " + format_number(kQuaternionNormTolerance) +
                     ")");
  }
  q.normalize();
  return Rigid3d(q, t);
}

CameraModel<double> read_intrinsics(const FieldReader& r, const json& entry,
                                    const std::string& path) {
  const json& type = r.member(entry, path, "camera_type");
  const std::string type_path = join_path(path, "camera_type");
  if (!type.is_string())
    r.fail(type_path, std::string("expected a string, got ") + type.type_name());
  const std::string name = type.get<std::string>();
  const auto names = CameraModel<double>::param_names(name);
  if (names.empty()) {
    r.fail(type_path, "unknown camera_type '" + name +
                          "' (known: " + CameraModel<double>::known_names() + ")");
  }
  const std::string values_path = join_path(path, "intrinsics");
  const json& values = r.member(entry, path, "intrinsics");
  std::vector<double> params;
  for (std::string_view n : names) params.push_back(r.number(values, values_path, std::string(n)));
  const auto model = CameraModel<double>::from_params(name, params);
  if (auto issue = model.check()) {
    r.fail(join_path(values_path, std::string(names[issue->index])),
           "= " + format_number(params[issue->index]) + " " + issue->problem);
  }
  return model;
}

}  // namespace

Rig parse_basalt_calibration(std::string_view json_text, std::string_view source) {
  const FieldReader r{std::string(source)};
  json root;
  json_detail::ParseFailure failure;
  if (!json_detail::parse_with_path(json_text, &root, &failure)) {
    r.fail(failure.path, "malformed JSON at line " + std::to_string(failure.line) + ", column " +
                             std::to_string(failure.column) + ": " + failure.message);
  }
  const json& value0 = r.member(root, "", "value0");
  const json& poses = r.array(value0, "value0", "T_imu_cam");
  const json& intrinsics = r.array(value0, "value0", "intrinsics");
  const json& resolutions = r.array(value0, "value0", "resolution");
  if (poses.size() != intrinsics.size() || poses.size() != resolutions.size()) {
    r.fail("value0", "T_imu_cam has " + std::to_string(poses.size()) + " entries, intrinsics " +
                         std::to_string(intrinsics.size()) + " and resolution " +
                         std::to_string(resolutions.size()) + "; they must have one per camera");
  }
  if (poses.size() < 2) {
    r.fail("value0.T_imu_cam",
           "a rig needs at least 2 cameras, found " + std::to_string(poses.size()));
  }
  Rig rig;
  for (std::size_t c = 0; c < poses.size(); ++c) {
    RigCamera cam;
    cam.rig_from_cam = read_pose(r, poses[c], index_path("value0.T_imu_cam", c));
    cam.model = read_intrinsics(r, intrinsics[c], index_path("value0.intrinsics", c));
    const std::string res_path = index_path("value0.resolution", c);
    const json& res = resolutions[c];
    if (!res.is_array() || res.size() != 2) {
      r.fail(res_path, "expected [width, height], got " + res.dump());
    }
    cam.width = r.positive_int(res[0], index_path(res_path, 0));
    cam.height = r.positive_int(res[1], index_path(res_path, 1));
    rig.cameras.push_back(std::move(cam));
  }
  return rig;
}

Rig read_basalt_calibration(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) {
    throw CalibrationError(path.string() + ": calibration file does not exist");
  }
  if (std::filesystem::is_directory(path, ec)) {
    throw CalibrationError(path.string() + ": is a directory, expected a calibration JSON file");
  }
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  if (!in || !(text << in.rdbuf())) {
    throw CalibrationError(path.string() + ": cannot read calibration file");
  }
  return parse_basalt_calibration(text.str(), path.string());
}

std::string to_basalt_json(const Rig& rig) {
  json poses = json::array(), intrinsics = json::array(), resolutions = json::array();
  for (const RigCamera& cam : rig.cameras) {
    const auto& q = cam.rig_from_cam.rotation;
    const auto& t = cam.rig_from_cam.translation;
    poses.push_back({{"px", t.x()},
                     {"py", t.y()},
                     {"pz", t.z()},
                     {"qx", q.x()},
                     {"qy", q.y()},
                     {"qz", q.z()},
                     {"qw", q.w()}});
    json values = json::object();
    const auto names = cam.model.param_names();
    const auto params = cam.model.params();
    for (std::size_t i = 0; i < names.size(); ++i) values[std::string(names[i])] = params[i];
    intrinsics.push_back({{"camera_type", std::string(cam.model.name())}, {"intrinsics", values}});
    resolutions.push_back({cam.width, cam.height});
  }
  const json root = {
      {"value0", {{"T_imu_cam", poses}, {"intrinsics", intrinsics}, {"resolution", resolutions}}}};
  return root.dump(4) + "\n";
}

void write_basalt_calibration(const Rig& rig, const std::filesystem::path& path) {
  const std::string text = to_basalt_json(rig);
  std::filesystem::path tmp = path;
  tmp += ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out || !out.write(text.data(), std::streamsize(text.size())) || !out.flush()) {
      throw CalibrationError(path.string() + ": cannot write calibration file");
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec)
    throw CalibrationError(path.string() + ": cannot write calibration file: " + ec.message());
}

}  // namespace omnisweep
