#include "server/tools/bench_ros2.h"

#include <unistd.h>

#include <cstdio>
#include <string>
#include <vector>

#include "omnisweep/codec/codec.h"
#include "omnisweep/dds/stream_publisher.h"
#include "omnisweep/ros2/ros_messages.h"
#include "omnisweep/ros2/ros_publisher.h"
#include "server/tools/bench_codecs.h"
#include "server/tools/bench_stats.h"

namespace omnisweep::tools {
namespace {

constexpr int kRuns = 15;

}  // namespace

void ros2_section(gpu::Context& context, bool json) {
  const stitch::Panorama panorama = synthetic_panorama(context);
  const codec::DistanceParams params;
  const codec::Bytes jpeg = codec::make_color_codec(codec::kJpeg)->encode(panorama.rgb);
  const codec::Bytes distance =
      codec::make_distance_codec(codec::kQinv16Zstd)->encode(panorama.distance, params);
  ros2::FrameInputs frame;
  frame.stamp_ns = 1;
  frame.width = panorama.rgb.width();
  frame.height = panorama.rgb.height();
  frame.jpeg = jpeg;
  frame.distance = distance;
  frame.distance_params = params;
  frame.color = &panorama.rgb;  // the server keeps the panorama's colour for the points
  const ros2::RosOptions options;
  ros2::FrameConverter converter(options);

  struct Row {
    const char* topic;
    ros2::WantedTopics wanted;
  };
  const Row rows[] = {
      {"color/image_raw/compressed", {.color = true}},
      {"distance/image_raw/compressedDepth", {.compressed_depth = true}},
      {"distance/image_raw", {.distance = true}},
      {"points (512x256)", {.points = true}},
      {"all four", {true, true, true, true}},
  };
  if (!json) {
    std::printf(
        "\nROS 2 topics of a 2048x1024 frame (synthetic rig; median of %d): CPU per frame with "
        "one subscriber (message made from the stream's payloads and serialised), bytes\n",
        kRuns);
    std::printf("%-38s %10s %10s %12s\n", "topic", "wall ms", "cpu ms", "bytes");
  }
  for (const Row& row : rows) {
    std::vector<Cost> costs;
    costs.reserve(kRuns);
    std::size_t bytes = 0;
    for (int i = 0; i < kRuns; ++i) {
      costs.push_back(cost_of([&] {
        const ros2::FrameMessages m = converter.convert(frame, row.wanted);
        bytes = 0;
        if (m.color) bytes += ros2::to_cdr(*m.color).size();
        if (m.compressed_depth) bytes += ros2::to_cdr(*m.compressed_depth).size();
        if (m.distance) bytes += ros2::to_cdr(*m.distance).size();
        if (m.points) bytes += ros2::to_cdr(*m.points).size();
      }));
    }
    const Cost c = median(costs);
    if (json)
      std::printf(
          "{\"kind\": \"ros2\", \"topic\": \"%s\", \"wall_ms\": %.3f, \"cpu_ms\": %.3f, "
          "\"bytes\": %zu}\n",
          row.topic, c.wall_ms, c.cpu_ms, bytes);
    else
      std::printf("%-38s %10.2f %10.2f %12zu\n", row.topic, c.wall_ms, c.cpu_ms, bytes);
  }
  msg::ServerStatus status;
  status.state("running");
  const std::size_t tf_bytes =
      ros2::to_cdr(ros2::static_transforms(1, options, {Rigid3d(), Rigid3d(), Rigid3d(), Rigid3d()},
                                           Eigen::Vector3d::Zero()))
          .size();
  const std::size_t diagnostics_bytes =
      ros2::to_cdr(ros2::diagnostics(1, "omnisweep-server: /omnisweep", "omnisweep", status))
          .size();

  // No subscriber: publish_frame on a participant where nothing reads.
  dds::ParticipantOptions participant;
  participant.domain = 200 + int(getpid() % 30);
  participant.topic_prefix = "bench" + std::to_string(getpid());
  participant.name = "omnisweep-bench";
  dds::StreamPublisher publisher(participant);
  ros2::RosPublisher ros(publisher.participant(), options);
  std::vector<Cost> idle;
  idle.reserve(1000);
  for (int i = 0; i < 1000; ++i)
    idle.push_back(cost_of([&] {
      if (ros.wants_frames()) ros.publish_frame(frame);
    }));
  const Cost none = median(idle);
  if (json) {
    std::printf(
        "{\"kind\": \"ros2\", \"topic\": \"no subscriber\", \"wall_ms\": %.6f, \"cpu_ms\": "
        "%.6f}\n{\"kind\": \"ros2\", \"topic\": \"tf_static\", \"bytes\": %zu}\n{\"kind\": "
        "\"ros2\", \"topic\": \"diagnostics\", \"bytes\": %zu}\n",
        none.wall_ms, none.cpu_ms, tf_bytes, diagnostics_bytes);
  } else {
    std::printf("%-38s %10.4f %10.4f %12s\n", "no subscriber (matched-reader check)", none.wall_ms,
                none.cpu_ms, "-");
    std::printf("%-38s %10s %10s %12zu\n", "/tf_static (4 cameras, once)", "-", "-", tf_bytes);
    std::printf("%-38s %10s %10s %12zu\n", "/diagnostics (1 Hz, no drops)", "-", "-",
                diagnostics_bytes);
  }
}

}  // namespace omnisweep::tools
