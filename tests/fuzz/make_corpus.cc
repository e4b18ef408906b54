// Writes the seed corpus of the fuzz targets (tests/fuzz/corpus/) from small procedural maps and
// images and the synthetic rig's calibration seed, so the seeds follow the payload formats:
//   build-robust/fuzz/omnisweep_fuzz_corpus tests/fuzz/corpus
// frame_decoder/{distance,jpeg,frame_cdr,confidence,confidence_cdr} (with the target's header
// bytes) and
// mcap_reader/{stream.mcap,cut_short.mcap}. Never from the kaist-rig data (not redistributable).
#include <cstdio>
#include <fstream>
#include <iostream>
#include <iterator>
#include <string>
#include <vector>

#include "omnisweep/codec/codec.h"
#include "omnisweep/record/stream_recording.h"
#include "omnisweep/rig/basalt_calibration.h"
#include "omnisweep/wire/wire.h"

namespace {

namespace fs = std::filesystem;
using namespace omnisweep;

void write_file(const fs::path& path, const std::vector<std::uint8_t>& bytes) {
  fs::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

// The target's header: path byte, then width - 1 and height - 1 (uint16 LE).
std::vector<std::uint8_t> header(std::uint8_t path, int w, int h) {
  return {path, std::uint8_t(w - 1), std::uint8_t((w - 1) >> 8), std::uint8_t(h - 1),
          std::uint8_t((h - 1) >> 8)};
}

// A small scene's distance: a floor ramp, a nearer box with sharp edges, a hole.
FloatImage distance_map(int w, int h, int frame) {
  FloatImage d(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float v = 1.0f + 8.0f * float(h - y) / float(h) + 0.02f * float((x * 7 + y * 3) % 5);
      if (x > w / 3 + frame && x < w / 2 + frame && y > h / 4 && y < 3 * h / 4) v = 0.7f;
      if (x < 3 && y < 3) v = 0.0f;  // no value
      d(x, y) = v;
    }
  return d;
}

Rgb8Image color_image(int w, int h, int frame) {
  Rgb8Image rgb(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c)
        rgb(x, y, c) = std::uint8_t((x * 5 + y * 3 + c * 80 + frame) % 256);
  return rgb;
}

msg::RgbdFrame frame_message(int w, int h, int frame) {
  const codec::DistanceParams params;
  msg::RgbdFrame m;
  m.sequence_number(std::uint64_t(frame));
  m.width(std::uint32_t(w));
  m.height(std::uint32_t(h));
  m.capture_time_ns({1, 2, 3, 4});
  m.color(wire::make_payload(
      codec::kJpeg, codec::make_color_codec(codec::kJpeg)->encode(color_image(w, h, frame))));
  m.distance(wire::make_payload(
      codec::kQinv16Zstd,
      codec::make_distance_codec(codec::kQinv16Zstd)->encode(distance_map(w, h, frame), params)));
  m.distance_params(wire::to_message(params));
  return m;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: " << argv[0] << " CORPUS_DIR (tests/fuzz/corpus)\n";
    return 2;
  }
  try {
    const fs::path root = argv[1];
    const codec::DistanceParams params;
    // Distance: header + levels - 2 (uint16 LE) + downsample index (0: 1), then the payload.
    std::vector<std::uint8_t> distance = header(0, 64, 32);
    distance.push_back(std::uint8_t((params.levels - 2) & 0xff));
    distance.push_back(std::uint8_t((params.levels - 2) >> 8));
    distance.push_back(0);
    const codec::Bytes payload =
        codec::make_distance_codec(codec::kQinv16Zstd)->encode(distance_map(64, 32, 0), params);
    distance.insert(distance.end(), payload.begin(), payload.end());
    write_file(root / "frame_decoder/distance", distance);

    std::vector<std::uint8_t> jpeg = header(1, 48, 32);
    const codec::Bytes jpeg_payload =
        codec::make_color_codec(codec::kJpeg)->encode(color_image(48, 32, 0));
    jpeg.insert(jpeg.end(), jpeg_payload.begin(), jpeg_payload.end());
    write_file(root / "frame_decoder/jpeg", jpeg);

    // Confidence: header, then a conf8-zstd payload of a ramp with a low-confidence hole.
    Gray8Image levels(64, 32);
    for (int y = 0; y < 32; ++y)
      for (int x = 0; x < 64; ++x)
        levels.data()[y * 64 + x] = std::uint8_t(x > 20 && x < 30 && y > 8 && y < 20 ? 3 : 4 * x);
    const codec::Bytes confidence_payload =
        codec::make_confidence_codec(codec::kConf8Zstd)->encode(levels);
    std::vector<std::uint8_t> confidence = header(3, 64, 32);
    confidence.insert(confidence.end(), confidence_payload.begin(), confidence_payload.end());
    write_file(root / "frame_decoder/confidence", confidence);

    // A recording: the description (the synthetic rig's calibration seed), three frames, status.
    std::ifstream calibration(root / "calibration/synthetic_ds.json");
    const std::string json((std::istreambuf_iterator<char>(calibration)), {});
    msg::StreamDescription description;
    wire::add_rig(parse_basalt_calibration(json, "synthetic_ds.json"), &description);
    description.references({2, 3});
    const fs::path mcap = root / "mcap_reader/stream.mcap";
    fs::create_directories(mcap.parent_path());
    {
      record::StreamRecorder recorder(mcap, "seed", {}, /*confidence=*/true);
      recorder.record(description, 1'000'000'000);
      for (int i = 0; i < 3; ++i) {
        msg::ConfidenceFrame c;
        c.sequence_number(std::uint64_t(i));
        c.width(64);
        c.height(32);
        c.confidence(wire::make_payload(codec::kConf8Zstd, confidence_payload));
        recorder.record(c, 1'100'000'000 + i * 100'000'000);
        recorder.record(frame_message(32, 16, i), 1'100'000'000 + i * 100'000'000);
      }
      msg::ServerStatus status;
      status.time_ns(1'400'000'000);
      recorder.record(status, 1'400'000'000);
      recorder.close();
    }
    std::ifstream in(mcap, std::ios::binary);
    const std::vector<std::uint8_t> stream((std::istreambuf_iterator<char>(in)), {});
    write_file(root / "mcap_reader/cut_short.mcap",
               std::vector<std::uint8_t>(stream.begin(), stream.begin() + stream.size() * 3 / 4));

    // The first recorded frame as CDR, as DDS and MCAP carry it.
    record::McapReader reader(mcap);
    std::vector<std::uint8_t> cdr;
    reader.read([&](const record::McapMessage& m) {
      if (record::recorded_topic(reader, *m.channel) != dds::TopicKind::kFrames) return true;
      cdr.assign(m.data.begin(), m.data.end());
      return false;
    });
    cdr.insert(cdr.begin(), 2);
    write_file(root / "frame_decoder/frame_cdr", cdr);
    reader.read([&](const record::McapMessage& m) {
      if (record::recorded_topic(reader, *m.channel) != dds::TopicKind::kConfidence) return true;
      cdr.assign(m.data.begin(), m.data.end());
      return false;
    });
    cdr.insert(cdr.begin(), 4);
    write_file(root / "frame_decoder/confidence_cdr", cdr);
    std::cout << "seed corpus written to " << root << "\n";
  } catch (const std::exception& e) {
    std::cerr << "omnisweep_fuzz_corpus: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
