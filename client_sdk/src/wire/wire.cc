#include "omnisweep/wire/wire.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace omnisweep::wire {
namespace {

[[noreturn]] void fail(const std::string& field, const std::string& what) {
  throw WireError(field + ": " + what);
}

}  // namespace

msg::CameraCalibration to_message(const RigCamera& camera) {
  msg::CameraCalibration m;
  m.camera_type(std::string(camera.model.name()));
  const auto params = camera.model.params();
  m.params(std::vector<double>(params.begin(), params.end()));
  m.width(std::uint32_t(camera.width));
  m.height(std::uint32_t(camera.height));
  const auto& t = camera.rig_from_cam.translation;
  const auto& q = camera.rig_from_cam.rotation;
  msg::Vector3 translation;
  translation.x(t.x());
  translation.y(t.y());
  translation.z(t.z());
  msg::Quaternion rotation;
  rotation.x(q.x());
  rotation.y(q.y());
  rotation.z(q.z());
  rotation.w(q.w());
  m.rig_from_cam_translation(translation);
  m.rig_from_cam_rotation(rotation);
  return m;
}

msg::DistanceCodecParams to_message(const codec::DistanceParams& params) {
  msg::DistanceCodecParams m;
  m.min_distance(params.min_distance);
  m.max_distance(params.max_distance);
  m.levels(params.levels);
  m.downsample(params.downsample);
  return m;
}

codec::DistanceParams from_message(const msg::DistanceCodecParams& m) {
  const codec::DistanceParams params{m.min_distance(), m.max_distance(), m.levels(),
                                     m.downsample()};
  try {
    params.check();
  } catch (const codec::CodecError& e) {
    fail("distance_params", e.what());
  }
  return params;
}

void add_rig(const Rig& rig, msg::StreamDescription* description) {
  std::vector<msg::CameraCalibration> cameras;
  for (const RigCamera& cam : rig.cameras) cameras.push_back(to_message(cam));
  description->cameras(cameras);
}

Rig rig_from_description(const msg::StreamDescription& description) {
  Rig rig;
  for (std::size_t c = 0; c < description.cameras().size(); ++c) {
    const msg::CameraCalibration& m = description.cameras()[c];
    const std::string field = "description.cameras[" + std::to_string(c) + "]";
    RigCamera cam;
    try {
      cam.model = CameraModel<double>::from_params(m.camera_type(), m.params());
    } catch (const std::invalid_argument& e) {
      fail(field, e.what());
    }
    if (auto issue = cam.model.check()) {
      fail(field + ".params." + std::string(cam.model.param_names()[issue->index]), issue->problem);
    }
    if (m.width() == 0 || m.height() == 0 || m.width() > 65536 || m.height() > 65536)
      fail(field, "bad image size");
    cam.width = int(m.width());
    cam.height = int(m.height());
    const auto& t = m.rig_from_cam_translation();
    const auto& q = m.rig_from_cam_rotation();
    Eigen::Quaterniond rotation(q.w(), q.x(), q.y(), q.z());
    if (!(std::abs(rotation.norm() - 1.0) < 1e-3))
      fail(field + ".rig_from_cam_rotation", "not a unit quaternion");
    if (!std::isfinite(t.x()) || !std::isfinite(t.y()) || !std::isfinite(t.z())) {
      fail(field + ".rig_from_cam_translation", "not finite");
    }
    cam.rig_from_cam = Rigid3d(rotation.normalized(), Eigen::Vector3d(t.x(), t.y(), t.z()));
    rig.cameras.push_back(std::move(cam));
  }
  if (rig.num_cameras() < 2) fail("description.cameras", "a rig needs at least 2 cameras");
  return rig;
}

namespace {
constexpr std::pair<ServerState, std::string_view> kServerStates[] = {
    {ServerState::kStarting, "starting"},
    {ServerState::kRunning, "running"},
    {ServerState::kSourceStalled, "source stalled"},
    {ServerState::kSourceEnded, "source ended"},
    {ServerState::kStopping, "stopping"},
    {ServerState::kFailed, "failed"},
};
}  // namespace

std::string_view to_string(ServerState state) {
  for (const auto& [s, text] : kServerStates)
    if (s == state) return text;
  return "unknown";
}

std::optional<ServerState> parse_server_state(std::string_view text) {
  for (const auto& [s, t] : kServerStates)
    if (t == text) return s;
  return std::nullopt;
}

StatusReport from_message(const msg::ServerStatus& status) {
  StatusReport r;
  r.time_ns = status.time_ns();
  r.state = status.state();
  r.known_state = parse_server_state(r.state);
  r.fps_in = status.fps_in();
  r.fps_out = status.fps_out();
  for (const auto& t : status.stage_ms()) r.stage_ms.emplace_back(t.stage(), t.ms());
  for (const auto& d : status.dropped()) r.dropped[d.reason()] += d.count();
  r.matched_subscribers = status.matched_subscribers();
  for (const auto& c : status.cameras()) {
    r.cameras.push_back({.camera = c.camera(),
                         .delivering = c.delivering(),
                         .fps = c.fps(),
                         .last_frame_ns = c.last_frame_ns(),
                         .message = c.message()});
  }
  r.color_quality = status.color_quality();
  r.frames_over_budget = status.frames_over_budget();
  return r;
}

std::optional<StatusReport> from_message(const std::optional<msg::ServerStatus>& status) {
  if (!status) return std::nullopt;
  return from_message(*status);
}

msg::Payload make_payload(std::string_view codec_name, const codec::Bytes& data) {
  msg::Payload p;
  p.codec(std::string(codec_name));
  p.data(data);
  p.crc32(codec::checksum(data));
  return p;
}

std::span<const std::uint8_t> checked_bytes(const msg::Payload& payload, const std::string& what) {
  try {
    codec::verify_checksum(payload.data(), payload.crc32());
  } catch (const codec::CodecError& e) {
    fail(what, e.what());
  }
  return payload.data();
}

DecodedFrame decode_frame(const msg::RgbdFrame& frame) {
  const auto width = int(frame.width()), height = int(frame.height());
  if (width <= 0 || height <= 0 || width > 16384 || height > 16384 || width != 2 * height) {
    fail("frame", "panorama size " + std::to_string(frame.width()) + "x" +
                      std::to_string(frame.height()) + " is not a 2:1 size up to 16384x8192");
  }
  DecodedFrame out;
  out.sequence_number = frame.sequence_number();
  const auto color_codec = codec::make_color_codec(frame.color().codec());
  out.rgb = color_codec->decode(checked_bytes(frame.color(), "frame.color"), width, height);
  const auto distance_codec = codec::make_distance_codec(frame.distance().codec());
  out.distance = distance_codec->decode(checked_bytes(frame.distance(), "frame.distance"), width,
                                        height, from_message(frame.distance_params()));
  return out;
}

Gray8Image decode_confidence(const msg::ConfidenceFrame& confidence, int width, int height) {
  if (int64_t(confidence.width()) != width || int64_t(confidence.height()) != height) {
    fail("confidence", "size " + std::to_string(confidence.width()) + "x" +
                           std::to_string(confidence.height()) + " is not the frame's " +
                           std::to_string(width) + "x" + std::to_string(height));
  }
  const auto codec = codec::make_confidence_codec(confidence.confidence().codec());
  return codec->decode(checked_bytes(confidence.confidence(), "confidence.confidence"), width,
                       height);
}

}  // namespace omnisweep::wire
