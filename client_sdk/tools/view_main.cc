// omnisweep-view: subscribes to a stream, prints frame rate, end-to-end latency (the earliest
// camera's capture at the server to decoded here) and bitrate each second, and writes the
// latest frame as PNGs into --output: panorama.png (colour), panorama_inverse_distance.png
// (turbo colour map), view.png and view_inverse_distance.png (a novel pinhole view rendered on
// the GPU from --viewpoint / --offset / --yaw / --pitch / --pinhole). With --confidence, also
// panorama_confidence.png (8-bit, 255 = full confidence), and --min-confidence makes the view
// inpaint over less confident distances. With --frames N it exits 0 after N frames, or 1 when
// they have not arrived within --timeout.
#include <CLI/CLI.hpp>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <numbers>
#include <thread>

#include "client_sdk/tools/cli_checks.h"
#include "client_sdk/tools/dds_flags.h"
#include "client_sdk/tools/status_line.h"
#include "client_sdk/tools/tool_main.h"
#include "omnisweep/client/rgbd_subscriber.h"
#include "omnisweep/codec/codec.h"
#include "omnisweep/gpu/context.h"
#include "omnisweep/image/image_io.h"
#include "omnisweep/reproject/reprojector.h"

namespace {

using namespace omnisweep;
namespace fs = std::filesystem;

std::atomic<bool> g_stop{false};
void on_signal(int) { g_stop = true; }

struct ViewOptions {
  std::vector<double> viewpoint;           // rig frame; empty: the panorama's own viewpoint
  std::vector<double> offset = {0, 0, 0};  // added to the viewpoint
  double yaw_deg = 0, pitch_deg = 0;
  std::vector<double> pinhole = {1024, 768, 90};  // W H FOV
  double min_confidence = 0;                      // ReprojectorOptions::min_confidence
};

// Writes through a temporary name, so a program watching the folder never reads half a file.
template <typename View>
void write_png_atomically(const fs::path& path, const View& image) {
  const fs::path tmp = path.string() + ".tmp.png";
  write_png(tmp, image, 1);
  fs::rename(tmp, path);
}

// rig_from_view for the flags: yaw turns right about the rig's y (down) axis, pitch looks up.
Rigid3d view_pose(const ViewOptions& v, const client::RgbdFrame& frame) {
  const double yaw = v.yaw_deg * std::numbers::pi / 180,
               pitch = v.pitch_deg * std::numbers::pi / 180;
  const Eigen::Quaterniond rotation =
      Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY())) *
      Eigen::Quaterniond(Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitX()));
  const Eigen::Vector3d position =
      (v.viewpoint.empty() ? frame.viewpoint
                           : Eigen::Vector3d(v.viewpoint[0], v.viewpoint[1], v.viewpoint[2])) +
      Eigen::Vector3d(v.offset[0], v.offset[1], v.offset[2]);
  return Rigid3d(rotation, position);
}

class ImageWriter {
 public:
  ImageWriter(fs::path output, ViewOptions view, const std::string& vk_device)
      : output_(std::move(output)), view_(std::move(view)) {
    try {
      context_ = std::make_unique<gpu::Context>(tools::context_options(vk_device));
    } catch (const std::exception& e) {
      std::fprintf(stderr, "omnisweep-view: no novel view (needs a Vulkan device): %s\n", e.what());
    }
  }

  void write(const client::RgbdFrame& frame) {
    const float max_inverse =
        frame.stream ? 1.0f / frame.stream->distance_params.min_distance : 1 / 0.55f;
    write_png_atomically(output_ / "panorama.png", frame.color);
    write_png_atomically(
        output_ / "panorama_inverse_distance.png",
        colorize_inverse_distance(reciprocal_or_zero(frame.distance), max_inverse));
    if (!frame.confidence.empty()) {
      write_png_atomically(output_ / "panorama_confidence.png",
                           codec::confidence_levels(frame.confidence));
    }
    if (!context_) return;
    if (!reprojector_) {
      reproject::ReprojectorOptions options;
      if (frame.stream) {
        options.min_distance = frame.stream->distance_params.min_distance;
        options.max_distance = frame.stream->distance_params.max_distance;
      }
      options.min_confidence = view_.min_confidence;
      reprojector_.emplace(*context_, options);
    }
    reprojector_->set_panorama(frame.color, frame.distance, frame.viewpoint, frame.confidence);
    const int w = int(view_.pinhole[0]), h = int(view_.pinhole[1]);
    const reproject::View view = reprojector_->render_pinhole(
        view_pose(view_, frame), reproject::pinhole_for_fov(w, h, view_.pinhole[2]), w, h);
    write_png_atomically(output_ / "view.png", view.color);
    write_png_atomically(output_ / "view_inverse_distance.png",
                         colorize_inverse_distance(reciprocal_or_zero(view.distance), max_inverse));
  }

 private:
  fs::path output_;
  ViewOptions view_;
  std::unique_ptr<gpu::Context> context_;
  std::optional<reproject::Reprojector> reprojector_;
};

struct Window {
  std::mutex mutex;
  std::vector<double> latency_ms;
  std::uint64_t frames = 0, bytes = 0;
};

int run(int argc, char** argv) {
  CLI::App app{"View an omnisweep stream: statistics each second and the latest frame as PNGs."};
  client::SubscriberOptions options;
  options.participant.name = "omnisweep-view";
  ViewOptions view;
  std::string output = ".", vk_device;
  std::uint64_t want_frames = 0;
  double timeout_s = 60, write_interval_s = 5;
  tools::add_dds_flags(app, options.participant);
  app.add_option("--profile", options.profile, "Frame QoS: live or reliable");
  app.add_option("--frames", want_frames,
                 "Exit 0 after this many frames (default: run until Ctrl-C)")
      ->check(tools::not_negative());
  app.add_option("--timeout", timeout_s,
                 "With --frames: exit 1 if they have not arrived by then (s)")
      ->check(CLI::Range(0.1, 1e6));
  app.add_option("--output", output, "Folder for the PNGs (default: the current folder)");
  app.add_option("--write-interval", write_interval_s,
                 "Seconds between image writes while running (0: only at the end)")
      ->check(CLI::Range(0.0, 1e6));
  app.add_option("--viewpoint", view.viewpoint, "Novel view position X Y Z in the rig frame (m)")
      ->expected(3);
  app.add_option("--offset", view.offset, "Novel view offset DX DY DZ from that position (m)")
      ->expected(3);
  app.add_option("--yaw", view.yaw_deg, "Novel view yaw, degrees (positive turns right)");
  app.add_option("--pitch", view.pitch_deg, "Novel view pitch, degrees (positive looks up)")
      ->check(CLI::Range(-90.0, 90.0));
  app.add_option("--pinhole", view.pinhole,
                 "Novel view W H FOV (pixels, pixels, horizontal degrees)")
      ->expected(3);
  app.add_flag("--confidence", options.confidence,
               "Also receive the distance's confidence (omnisweep-server --confidence) and write "
               "panorama_confidence.png");
  app.add_option("--min-confidence", view.min_confidence,
                 "The novel view inpaints over distances less confident than this (0-1)")
      ->check(CLI::Range(0.0, 1.0));
  app.add_option("--vk-device", vk_device, "Vulkan device: index or name substring");
  CLI11_PARSE(app, argc, argv);
  if (view.pinhole[0] < 1 || view.pinhole[1] < 1 || view.pinhole[0] > 16384 ||
      view.pinhole[1] > 16384 || !(view.pinhole[2] > 0 && view.pinhole[2] < 179)) {
    std::fprintf(stderr,
                 "omnisweep-view: --pinhole needs W and H in 1-16384 and FOV in (0, 179)\n");
    return 2;
  }
  std::error_code ec;
  fs::create_directories(output, ec);
  if (!fs::is_directory(output)) {
    std::fprintf(stderr, "omnisweep-view: cannot create the output folder %s\n", output.c_str());
    return 2;
  }
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);

  Window window;
  client::RgbdSubscriber subscriber(options,
                                    [&](const std::shared_ptr<const client::RgbdFrame>& f) {
                                      const std::lock_guard lock(window.mutex);
                                      window.latency_ms.push_back(f->latency_ms());
                                      window.bytes += f->color_bytes + f->distance_bytes;
                                      ++window.frames;
                                    });
  ImageWriter writer(output, view, vk_device);

  const auto start = std::chrono::steady_clock::now();
  auto next_report = start + std::chrono::seconds(1);
  auto next_write = start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                std::chrono::duration<double>(write_interval_s));
  std::uint64_t written_sequence = ~0ull;
  bool timed_out = false;
  const auto write_latest = [&] {
    const auto frame = subscriber.latest_frame();
    if (!frame || frame->sequence_number == written_sequence) return;
    writer.write(*frame);
    written_sequence = frame->sequence_number;
  };
  while (!g_stop) {
    if (want_frames && subscriber.stats().frames_decoded >= want_frames) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    const auto now = std::chrono::steady_clock::now();
    if (want_frames && now - start > std::chrono::duration<double>(timeout_s)) {
      timed_out = true;
      break;
    }
    if (write_interval_s > 0 && now >= next_write) {
      write_latest();
      next_write = std::chrono::steady_clock::now() +
                   std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                       std::chrono::duration<double>(write_interval_s));
    }
    if (now < next_report) continue;
    next_report += std::chrono::seconds(1);
    const client::SubscriberStats stats = subscriber.stats();
    if (subscriber.state() == client::ConnectionState::kWaiting) {
      std::printf("%s\n", tools::waiting_line(subscriber.status()).c_str());
      std::fflush(stdout);
      continue;
    }
    const std::lock_guard lock(window.mutex);
    double mean = 0, worst = 0;
    for (double l : window.latency_ms)
      mean += l / double(window.latency_ms.size()), worst = std::max(worst, l);
    std::printf("%s: %llu fps, latency %.1f ms (max %.1f), %.2f Mbit/s, %llu lost, %llu rejected\n",
                client::to_string(subscriber.state()),
                static_cast<unsigned long long>(window.frames), mean, worst, window.bytes * 8e-6,
                static_cast<unsigned long long>(stats.frames_lost),
                static_cast<unsigned long long>(stats.decode_errors));
    std::fflush(stdout);
    window.latency_ms.clear();
    window.frames = window.bytes = 0;
  }
  write_latest();
  const client::SubscriberStats stats = subscriber.stats();
  std::printf("summary: %llu frames decoded, %llu lost, %llu rejected; images in %s\n",
              static_cast<unsigned long long>(stats.frames_decoded),
              static_cast<unsigned long long>(stats.frames_lost),
              static_cast<unsigned long long>(stats.decode_errors),
              fs::absolute(output).lexically_normal().c_str());
  if (timed_out) {
    std::fprintf(stderr, "omnisweep-view: timed out after %.1f s with %llu of %llu frames (%s)\n",
                 timeout_s, static_cast<unsigned long long>(stats.frames_decoded),
                 static_cast<unsigned long long>(want_frames),
                 client::to_string(subscriber.state()));
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return omnisweep::tools::run_tool("omnisweep-view", argc, argv, run);
}
