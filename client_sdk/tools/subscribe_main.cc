// omnisweep-subscribe: a minimal subscriber of an omnisweep stream. Prints, once a second, the
// frame rate, end-to-end latency (wire::latency_ms: the earliest camera's capture to decoded here),
// bitrate and lost frames; prints the calibration when it arrives and the server's status. Exits 0
// once the conditions given (--frames N, --statuses N, --description) are met, 1 if --timeout
// passes first. With --dump DIR it writes each frame's colour payload as received (<seq>.jpg) and
// its decoded distance (<seq>_distance.f32, float32 metres, row-major).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <thread>

#include "client_sdk/tools/cli_checks.h"
#include "client_sdk/tools/dds_flags.h"
#include "client_sdk/tools/status_line.h"
#include "client_sdk/tools/tool_main.h"
#include "omnisweep/dds/stream_subscriber.h"
#include "omnisweep/time/clock.h"
#include "omnisweep/wire/frame_stats.h"
#include "omnisweep/wire/wire.h"

namespace {

using namespace omnisweep;

std::atomic<bool> g_stop{false};
void on_signal(int) { g_stop = true; }

struct Window {
  std::mutex mutex;
  std::vector<double> latency_ms;
  std::uint64_t bytes = 0, frames = 0, lost = 0, errors = 0;
  wire::GapCounter gaps;  // over the whole run; `lost` is this window's share
};

int run(int argc, char** argv) {
  CLI::App app{"Subscribe to an omnisweep stream and report frame rate, latency and bitrate."};
  dds::ParticipantOptions options;
  options.name = "omnisweep-subscribe";
  std::string profile = "live", dump_dir;
  std::uint64_t want_frames = 0, want_statuses = 0;
  bool want_description = false, quiet = false;
  double timeout_s = 60;
  tools::add_dds_flags(app, options);
  app.add_option("--profile", profile, "Frame QoS: live (newest frames) or reliable (every frame)");
  app.add_option("--frames", want_frames, "Exit 0 after this many decoded frames")
      ->check(tools::not_negative());
  app.add_option("--statuses", want_statuses, "Exit 0 after this many status messages")
      ->check(tools::not_negative());
  app.add_flag("--description", want_description, "Exit 0 only once the calibration arrived");
  app.add_option("--timeout", timeout_s, "Exit 1 if the conditions are not met by then (s)")
      ->check(CLI::Range(0.1, 1e6));
  app.add_option("--dump", dump_dir, "Write <seq>.jpg and <seq>_distance.f32 of every frame");
  app.add_flag("--quiet", quiet, "Only the final summary");
  bool status_only = false;
  app.add_flag("--status-only", status_only,
               "Read only the status topic (an identity permitted nothing else)");
  CLI11_PARSE(app, argc, argv);
  if (!dump_dir.empty()) std::filesystem::create_directories(dump_dir);
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);

  const auto start = std::chrono::steady_clock::now();
  Window window;
  std::atomic<std::uint64_t> decoded{0}, statuses{0};
  std::atomic<bool> described{false};
  dds::StreamCallbacks callbacks;
  callbacks.description = [&](const msg::StreamDescription& d) {
    try {
      const Rig rig = wire::rig_from_description(d);
      std::printf("description: revision %llu, %d cameras, references",
                  static_cast<unsigned long long>(d.revision()), rig.num_cameras());
      for (int r : d.references()) std::printf(" %d", r);
      std::printf(", panorama %ux%u, viewpoint %.3f %.3f %.3f m, codecs %s + %s\n",
                  d.panorama_width(), d.panorama_height(), d.viewpoint().x(), d.viewpoint().y(),
                  d.viewpoint().z(), d.color_codec().c_str(), d.distance_codec().c_str());
      described = true;
    } catch (const std::exception& e) {
      std::printf("bad description: %s\n", e.what());
    }
    std::fflush(stdout);
  };
  callbacks.frame = [&](const msg::RgbdFrame& frame) {
    if (want_frames && decoded >= want_frames) return;  // done: the summary counts exactly N
    {
      const std::lock_guard lock(window.mutex);
      window.lost += window.gaps.see(frame.sequence_number());
    }
    try {
      const wire::DecodedFrame decodedFrame = wire::decode_frame(frame);
      const std::uint64_t t = wall_clock_ns();
      if (!dump_dir.empty()) {
        const std::string base =
            (std::filesystem::path(dump_dir) / std::to_string(frame.sequence_number())).string();
        const auto& color = frame.color().data();
        std::ofstream(base + ".jpg", std::ios::binary)
            .write(reinterpret_cast<const char*>(color.data()), std::streamsize(color.size()));
        std::ofstream(base + "_distance.f32", std::ios::binary)
            .write(reinterpret_cast<const char*>(decodedFrame.distance.data()),
                   std::streamsize(decodedFrame.distance.size() * sizeof(float)));
      }
      const std::lock_guard lock(window.mutex);
      window.latency_ms.push_back(wire::latency_ms(frame.capture_time_ns(), t));
      window.bytes += frame.color().data().size() + frame.distance().data().size();
      ++window.frames;
      ++decoded;
    } catch (const std::exception& e) {
      const std::lock_guard lock(window.mutex);
      ++window.errors;
      std::printf("frame %llu rejected: %s\n",
                  static_cast<unsigned long long>(frame.sequence_number()), e.what());
    }
  };
  callbacks.status = [&](const msg::ServerStatus& s) {
    ++statuses;
    if (quiet) return;
    std::printf("status at %.3f s: %s, %.1f fps in, %.1f fps out, %d subscribers, ms:",
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
                s.state().c_str(), s.fps_in(), s.fps_out(), s.matched_subscribers());
    for (const auto& t : s.stage_ms()) std::printf(" %s %.1f", t.stage().c_str(), t.ms());
    std::printf(", colour quality %d", s.color_quality());
    if (s.frames_over_budget())
      std::printf(", %llu frames over budget",
                  static_cast<unsigned long long>(s.frames_over_budget()));
    for (const auto& d : s.dropped())
      std::printf(", dropped (%s) %llu", d.reason().c_str(),
                  static_cast<unsigned long long>(d.count()));
    std::printf("\n");
    std::fflush(stdout);
  };
  dds::StreamSubscriber subscriber(
      options, profile, std::move(callbacks),
      status_only ? std::vector<dds::TopicKind>{dds::TopicKind::kStatus}
                  : std::vector<dds::TopicKind>{dds::TopicKind::kDescription,
                                                dds::TopicKind::kStatus, dds::TopicKind::kFrames});

  auto next_report = start + std::chrono::seconds(1);
  std::vector<double> all_latency;
  std::uint64_t total_bytes = 0, total_lost = 0;
  auto done = [&] {
    return (want_frames == 0 || decoded >= want_frames) &&
           (want_statuses == 0 || statuses >= want_statuses) && (!want_description || described) &&
           (want_frames || want_statuses || want_description);
  };
  bool timed_out = false;
  while (!g_stop && !done()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    const auto now = std::chrono::steady_clock::now();
    if (now - start > std::chrono::duration<double>(timeout_s)) {
      timed_out = true;
      break;
    }
    if (now < next_report) continue;
    next_report += std::chrono::seconds(1);
    const std::lock_guard lock(window.mutex);
    std::vector<double> l = window.latency_ms;
    std::sort(l.begin(), l.end());
    if (!quiet && decoded == 0 && subscriber.matched_servers() > 0 && !status_only) {
      std::printf("%s\n", tools::waiting_line(wire::from_message(subscriber.status())).c_str());
      std::fflush(stdout);
    } else if (!quiet) {
      std::printf(
          "%llu fps, latency median %.1f ms (max %.1f), %.2f Mbit/s, %llu lost, %d server(s)\n",
          static_cast<unsigned long long>(window.frames), l.empty() ? 0.0 : l[l.size() / 2],
          l.empty() ? 0.0 : l.back(), window.bytes * 8e-6,
          static_cast<unsigned long long>(window.lost), subscriber.matched_servers());
      std::fflush(stdout);
    }
    all_latency.insert(all_latency.end(), l.begin(), l.end());
    total_bytes += window.bytes;
    total_lost += window.lost;
    window.latency_ms.clear();
    window.bytes = window.frames = window.lost = 0;
  }
  {
    const std::lock_guard lock(window.mutex);
    all_latency.insert(all_latency.end(), window.latency_ms.begin(), window.latency_ms.end());
    total_bytes += window.bytes;
    total_lost += window.lost;
  }
  std::sort(all_latency.begin(), all_latency.end());
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf(
      "summary: %llu frames decoded, %llu lost, %llu rejected, %llu status messages, latency "
      "median %.1f ms, %.0f KB per frame, calibration %s, %.1f s\n",
      static_cast<unsigned long long>(decoded.load()), static_cast<unsigned long long>(total_lost),
      static_cast<unsigned long long>(window.errors),
      static_cast<unsigned long long>(statuses.load()),
      all_latency.empty() ? 0.0 : all_latency[all_latency.size() / 2],
      decoded ? total_bytes / 1024.0 / double(decoded) : 0.0, described ? "received" : "missing",
      seconds);
  if (timed_out) {
    std::fprintf(
        stderr,
        "omnisweep-subscribe: timed out after %.1f s (frames %llu/%llu, statuses %llu/%llu, "
        "calibration %s)\n",
        timeout_s, static_cast<unsigned long long>(decoded.load()),
        static_cast<unsigned long long>(want_frames),
        static_cast<unsigned long long>(statuses.load()),
        static_cast<unsigned long long>(want_statuses), described ? "received" : "missing");
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return omnisweep::tools::run_tool("omnisweep-subscribe", argc, argv, run);
}
