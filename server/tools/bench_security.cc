#include "server/tools/bench_security.h"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <regex>
#include <stdexcept>
#include <thread>

#include "omnisweep/codec/codec.h"
#include "omnisweep/dds/stream_publisher.h"
#include "omnisweep/time/clock.h"
#include "omnisweep/wire/wire.h"
#include "server/synthetic/synthetic_rig.h"

namespace omnisweep::tools {
namespace {

namespace fs = std::filesystem;

struct Result {
  int published = 0, decoded = 0;
  double seconds = 0, latency_ms = 0;
};

msg::RgbdFrame encoded_frame() {
  const synthetic::SyntheticRig rig(synthetic::SyntheticRigOptions{.image_size = 64});
  const synthetic::RenderedImage pano = rig.render_panorama_at(0, rig.viewpoint(), 2048, 1024);
  const FloatImage distance = reciprocal_or_zero(pano.inverse_distance);
  const codec::DistanceParams params;
  msg::RgbdFrame frame;
  frame.width(2048);
  frame.height(1024);
  frame.color(
      wire::make_payload(codec::kJpeg, codec::make_color_codec(codec::kJpeg)->encode(pano.rgb)));
  frame.distance(
      wire::make_payload(codec::kQinv16Zstd,
                         codec::make_distance_codec(codec::kQinv16Zstd)->encode(distance, params)));
  frame.distance_params(wire::to_message(params));
  return frame;
}

Result stream(msg::RgbdFrame& frame, const std::string& subscriber_bin,
              const dds::ParticipantOptions& options, const std::string& viewer_dir) {
  constexpr int kFrames = 150;  // 5 s at 30 Hz
  dds::StreamPublisher publisher(options);
  const std::string command =
      subscriber_bin + " --domain " + std::to_string(options.domain) + " --topic-prefix " +
      options.topic_prefix + (viewer_dir.empty() ? "" : " --security " + viewer_dir) +
      " --profile reliable --quiet --frames " + std::to_string(kFrames) + " --timeout 40 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) throw std::runtime_error("cannot start " + subscriber_bin);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (publisher.frame_subscribers() < 1 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  Result r;
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < kFrames && publisher.frame_subscribers() > 0; ++i) {
    std::this_thread::sleep_until(start + std::chrono::microseconds(33333 * i));
    frame.sequence_number(i);
    const std::uint64_t now = wall_clock_ns();
    frame.capture_time_ns().assign(4, now);
    frame.publish_time_ns(now);
    publisher.publish(frame);
    ++r.published;
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::string out;
  char buffer[4096];
  while (fgets(buffer, sizeof(buffer), pipe)) out += buffer;
  pclose(pipe);
  std::smatch m;
  if (std::regex_search(
          out, m, std::regex(R"(summary: (\d+) frames decoded.*latency median ([0-9.]+) ms)"))) {
    r.decoded = std::stoi(m[1]);
    r.latency_ms = std::stod(m[2]);
  }
  return r;
}

}  // namespace

void security_section(const std::string& source_dir, bool json) {
  const fs::path script = fs::path(source_dir) / "deploy/security/make-credentials.sh";
  const fs::path subscriber = fs::canonical("/proc/self/exe").parent_path() / "omnisweep-subscribe";
  if (!fs::exists(script) || !fs::exists(subscriber)) {
    std::printf("\nSecurity: skipped (needs %s and %s)\n", script.c_str(), subscriber.c_str());
    return;
  }
  const fs::path dir =
      fs::temp_directory_path() / ("omnisweep-bench-creds-" + std::to_string(getpid()));
  if (std::system((script.string() + " " + dir.string() + " > /dev/null").c_str()) != 0)
    throw std::runtime_error("make-credentials.sh failed");
  msg::RgbdFrame frame = encoded_frame();
  const double kb = (frame.color().data().size() + frame.distance().data().size()) / 1024.0;
  dds::ParticipantOptions options;
  options.domain = 200 + getpid() % 30;
  options.name = "omnisweep-bench";
  options.topic_prefix = "bench" + std::to_string(getpid()) + "/plain";
  const Result plain = stream(frame, subscriber, options, "");
  options.topic_prefix = "bench" + std::to_string(getpid()) + "/secure";
  options.security_dir = (dir / "server").string();
  const Result secure = stream(frame, subscriber, options, (dir / "viewer").string());
  fs::remove_all(dir);

  if (json) {
    for (const auto& [name, r] : {std::pair{"plain", plain}, std::pair{"encrypted", secure}}) {
      std::printf(
          "{\"kind\": \"security\", \"mode\": \"%s\", \"published\": %d, \"decoded\": %d, "
          "\"fps\": %.2f, \"latency_ms\": %.2f, \"kb_per_frame\": %.0f}\n",
          name, r.published, r.decoded, r.decoded / r.seconds, r.latency_ms, kb);
    }
    return;
  }
  std::printf(
      "\nSecurity: %.0f KB frames (2048x1024, JPEG q90 + qinv16-zstd) at 30 Hz to an "
      "omnisweep-subscribe process (reliable), latency = publish to decoded there\n",
      kb);
  std::printf("%-12s %10s %10s %8s %12s\n", "mode", "published", "decoded", "fps", "latency ms");
  for (const auto& [name, r] : {std::pair{"plain", plain}, std::pair{"encrypted", secure}}) {
    std::printf("%-12s %10d %10d %8.1f %12.1f\n", name, r.published, r.decoded,
                r.decoded / r.seconds, r.latency_ms);
  }
}

}  // namespace omnisweep::tools
