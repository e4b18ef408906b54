#include "server/tools/bench_record.h"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <random>

#include "omnisweep/record/stream_recording.h"
#include "omnisweep/time/clock.h"

namespace omnisweep::tools {

void record_section(bool json) {
  constexpr int kFrames = 300;
  // Payload sizes of the default stream on the synthetic rig (docs/performance.md): JPEG q90
  // 255 KB, distance 597 KB. Random bytes: nothing downstream compresses them again.
  std::mt19937 random(7);
  msg::RgbdFrame frame;
  frame.width(2048);
  frame.height(1024);
  frame.capture_time_ns().assign(4, 0);
  std::vector<std::uint8_t> color(std::size_t(255) * 1024), distance(std::size_t(597) * 1024);
  for (auto& b : color) b = std::uint8_t(random());
  for (auto& b : distance) b = std::uint8_t(random());
  frame.color().codec(std::string(codec::kJpeg));
  frame.color().data(color);
  frame.distance().codec(std::string(codec::kQinv16Zstd));
  frame.distance().data(distance);

  const std::filesystem::path file = std::filesystem::temp_directory_path() /
                                     ("omnisweep-bench-" + std::to_string(getpid()) + ".mcap");
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  {
    record::StreamRecorder recorder(file, "bench");
    for (int i = 0; i < kFrames; ++i) {
      frame.sequence_number(i);
      const std::uint64_t now = wall_clock_ns();
      recorder.record(frame, now);
      recorder.flush_due(now);
    }
    recorder.close();  // includes fsync
  }
  const double write_s = std::chrono::duration<double>(Clock::now() - start).count();
  const double megabytes = double(std::filesystem::file_size(file)) * 1e-6;

  const auto read_start = Clock::now();
  record::McapReader reader(file);
  msg::RgbdFrame back;
  std::uint64_t decoded = 0;
  reader.read([&](const record::McapMessage& m) {
    record::decode_message(m.data, back);
    decoded += back.sequence_number() < kFrames;
    return true;
  });
  const double read_s = std::chrono::duration<double>(Clock::now() - read_start).count();
  std::filesystem::remove(file);

  if (json) {
    std::printf(
        "{\"kind\": \"record\", \"frames\": %d, \"mb\": %.1f, \"write_mb_s\": %.1f, "
        "\"write_fps\": %.1f, \"read_mb_s\": %.1f, \"read_fps\": %.1f}\n",
        kFrames, megabytes, megabytes / write_s, kFrames / write_s, megabytes / read_s,
        decoded / read_s);
    return;
  }
  std::printf("\nRecording: %d frames of 852 KB payloads (the default 2048x1024 stream) to MCAP\n",
              kFrames);
  std::printf(
      "  write (CDR serialisation, chunks, indexes, fsync at close): %.1f MB in %.2f s = "
      "%.0f MB/s, %.0f frames/s\n",
      megabytes, write_s, megabytes / write_s, kFrames / write_s);
  std::printf("  read back (McapReader, CDR decode): %.0f MB/s, %.0f frames/s\n",
              megabytes / read_s, decoded / read_s);
}

}  // namespace omnisweep::tools
