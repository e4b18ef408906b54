// omnisweep-server: capture, estimate distance, stitch, compress and publish 360-degree RGB-D
// panoramas over DDS (docs/deploy.md, docs/wire-format.md). Runs until SIGINT / SIGTERM (or
// --frames N), and stops within a second.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstring>

#include "client_sdk/tools/cli_checks.h"
#include "client_sdk/tools/dds_flags.h"
#include "client_sdk/tools/ros2_flags.h"
#include "client_sdk/tools/tool_main.h"
#include "omnisweep/dataset/dataset.h"
#include "omnisweep/dds/stream_publisher.h"
#include "server/capture/frame_source.h"
#include "server/pipeline/rgbd_server.h"
#include "server/tools/depth_flags.h"
#include "server/tools/stitch_flags.h"
#include "server/tools/stop_signals.h"

namespace {

using namespace omnisweep;

int run(int argc, char** argv) {
  CLI::App app{
      "Capture, estimate distance, stitch and publish 360-degree RGB-D panoramas over DDS "
      "(Fast DDS). Stops on SIGINT / SIGTERM."};
  app.set_config("--config", "", "Read options from a TOML/INI file (keys are the long flags)");
  std::string source_spec = "synthetic", device, frame_profile = "omnisweep_frames";
  capture::SourceOptions source_options;
  pipeline::ServerOptions options;
  dds::ParticipantOptions dds_options;
  dds_options.name = "omnisweep-server";
  tools::PanoramaFlags panorama_flags{
      .panorama = {options.panorama_width, options.panorama_height}};
  bool light = false;
  app.add_option("--source", source_spec,
                 "synthetic (default), dataset:DIR, video:F0,F1,..., v4l2:/dev/videoN,... or "
                 "gst:PIPELINE|PIPELINE|...");
  app.add_option("--calibration", source_options.calibration,
                 "basalt calibration JSON (needed by video, v4l2 and gst sources)");
  app.add_option("--synthetic-poses", source_options.synthetic_poses,
                 "Distinct frames of the synthetic source (rendered once, then looped)")
      ->check(CLI::Range(1, 300));
  app.add_option("--camera-timeout", source_options.camera_timeout_s,
                 "Seconds without an image before a camera counts as not delivering")
      ->check(CLI::Range(0.1, 3600.0));
  app.add_flag("--exit-on-source-end", options.exit_on_source_end,
               "Exit (code 1) when the source stalls or ends, instead of reporting and retrying");
  app.add_option("--fps", options.fps, "Capture rate cap, frames per second")
      ->check(CLI::Range(0.01, 1000.0));
  tools::add_panorama_flags(app, panorama_flags);
  app.add_option("--jpeg-quality", options.jpeg_quality,
                 "Colour JPEG quality (the frame budget may lower it)")
      ->check(CLI::Range(1, 100));
  app.add_option("--max-frame-bytes", options.max_frame_bytes,
                 "Colour + distance bytes per frame: larger frames get a lower JPEG quality, down "
                 "to " +
                     std::to_string(pipeline::FrameBudget::kFloorQuality) +
                     " (0: no limit; --light: " + std::to_string(codec::kLightFrameBytes) + ")")
      ->check(tools::not_negative());
  app.add_option("--distance-levels", options.distance.levels,
                 "Quantisation levels of inverse distance (default 10000: error <= 9.04e-5 m^-1)")
      ->check(CLI::Range(2, 65535));
  app.add_option("--distance-downsample", options.distance.downsample,
                 "Send distance at 1/N resolution per axis (1, 2 or 4)")
      ->check(CLI::IsMember({1, 2, 4}));
  app.add_flag("--light", light,
               "Light setting for slow links: distance at 1/4 resolution over 2048 levels, JPEG "
               "quality 60 (about 170-225 KB per 2048x1024 frame)");
  tools::add_depth_flags(app, options.depth, device, {&options.plane_fill, &options.region_planes});
  tools::add_dds_flags(app, dds_options, "Topic prefix (several rigs on one network)");
  app.add_option("--frame-profile", frame_profile,
                 "data_writer profile of the frame topic (default omnisweep_frames)");
  app.add_option("--frames", options.max_frames, "Stop after publishing N frames (0: run on)")
      ->check(tools::not_negative());
  tools::add_plane_fill_flag(app, options.plane_fill);
  tools::add_region_planes_flag(app, options.region_planes);
  tools::add_edge_check_flag(app, options.edge_check);
  tools::add_membrane_fill_flag(app, options.membrane_fill);
  tools::add_temporal_flags(app, options.temporal);
  app.add_flag("--confidence", options.confidence,
               "Also publish each frame's distance confidence (8-bit, conf8-zstd) on "
               "<prefix>/confidence; subscribers that do not ask for it are unaffected");
  tools::Ros2Flags ros_flags;
  tools::add_ros2_flags(app, ros_flags,
                        "Do not publish the ROS 2 topics (docs/ros2.md); by default they exist and "
                        "cost nothing until a ROS reader matches one");
  tools::FoxgloveFlags foxglove_flags;
  tools::add_foxglove_flags(app, foxglove_flags);
  app.add_option("--dump", options.dump_dir,
                 "Write <seq>.jpg and <seq>_distance.f32 (float32 metres) of every frame here");
  app.add_option("--log-interval", options.log_interval_s,
                 "Seconds between status lines on stderr (0: none; given twice, the last counts)")
      ->check(CLI::Range(0.0, 86400.0))
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  CLI11_PARSE(app, argc, argv);
  options.panorama_width = panorama_flags.panorama[0];
  options.panorama_height = panorama_flags.panorama[1];
  if (const auto rgb = panorama_flags.rgb()) options.rgb_resolution = *rgb;
  options.viewpoint = panorama_flags.centre();
  options.ros2 = tools::ros2_options(app, ros_flags, dds_options.topic_prefix);
  options.foxglove = tools::foxglove_options(app, foxglove_flags, options.ros2.has_value());
  if (light) {
    options.distance.levels = codec::kLightDistance.levels;
    options.distance.downsample = codec::kLightDistance.downsample;
    options.jpeg_quality = codec::kLightJpegQuality;
    if (app.count("--max-frame-bytes") == 0) options.max_frame_bytes = codec::kLightFrameBytes;
  }

  // Before any thread starts (Fast DDS, the GPU driver, the stages), so every thread inherits
  // the mask and the watcher alone takes SIGINT / SIGTERM, during the start-up too.
  tools::StopSignals signals("omnisweep-server");
  // A signal during the start-up: what was built is torn down in order, and nothing starts.
  auto stopped_in_start_up = [&] {
    if (signals.received() == 0) return false;
    std::fprintf(stderr, "omnisweep-server: %s, stopping before the first frame\n",
                 strsignal(signals.received()));
    return true;
  };

  auto source = capture::open_source(source_spec, source_options);
  if (stopped_in_start_up()) return 0;
  if (const DatasetHints* hints = source->hints()) {  // where no flag gives them
    if (!hints->references.empty() && app.count("--references") == 0)
      options.depth.references = hints->references;
    if (hints->min_distance && app.count("--min-dist") == 0)
      options.depth.min_distance = *hints->min_distance;
    if (hints->max_distance && app.count("--max-dist") == 0)
      options.depth.max_distance = *hints->max_distance;
    if (hints->viewpoint && !options.viewpoint) options.viewpoint = *hints->viewpoint;
  }
  std::fprintf(stderr, "omnisweep-server: source: %s\n", source->description().c_str());
  gpu::Context context(tools::context_options(device));
  if (stopped_in_start_up()) return 0;
  auto publisher =
      std::make_unique<dds::StreamPublisher>(dds_options, frame_profile, options.confidence);
  auto server =
      std::make_unique<pipeline::RgbdServer>(std::move(source), context, *publisher, options);
  if (stopped_in_start_up()) return 0;  // server, publisher, context: torn down in that order
  std::fprintf(stderr,
               "omnisweep-server: device %s; publishing %dx%d panoramas on domain %d, topics "
               "%s/{description,rgbd,status}\n",
               context.info().name.c_str(), options.panorama_width, options.panorama_height,
               dds_options.domain, dds_options.topic_prefix.c_str());
  if (options.ros2) {
    std::fprintf(stderr,
                 "omnisweep-server: ROS 2 topics %s/{color/image_raw/compressed,distance/image_raw,"
                 "distance/image_raw/compressedDepth,points}, /tf_static, /diagnostics (frames "
                 "%s_*)\n",
                 options.ros2->ros_namespace == "/" ? "" : options.ros2->ros_namespace.c_str(),
                 options.ros2->frame_prefix.c_str());
  }
  if (server->foxglove_port()) {
    std::fprintf(stderr, "omnisweep-server: Foxglove WebSocket server on ws://%s:%d\n",
                 options.foxglove->address.c_str(), server->foxglove_port());
  }
  server->start();
  signals.started();

  int signal = 0;
  while (!server->finished() && (signal = signals.wait_for(0.05)) == 0) {
  }
  if (signal != 0) std::fprintf(stderr, "omnisweep-server: %s, stopping\n", strsignal(signal));
  server->request_stop();
  const std::string error = server->error();
  const int code = error.empty() ? 0 : 1;
  if (!error.empty()) std::fprintf(stderr, "omnisweep-server: %s\n", error.c_str());
  std::fprintf(stderr, "omnisweep-server: %llu frames published\n",
               static_cast<unsigned long long>(server->frames_published()));
  if (!server->wait_stopped(0.7)) {
    // A stage is inside a long GPU submission (seconds per frame on a CPU Vulkan driver), which
    // cannot be interrupted. Leave the DDS domain properly, then exit without waiting for it:
    // the operating system reclaims the device.
    if (server->publisher_released()) publisher.reset();
    std::fprintf(stderr, "omnisweep-server: a stage is still busy on the GPU; exiting now\n");
    std::fflush(stderr);
    std::_Exit(code);
  }
  server.reset();
  publisher.reset();
  return code;
}

}  // namespace

int main(int argc, char** argv) {
  return omnisweep::tools::run_tool("omnisweep-server", argc, argv, run);
}
