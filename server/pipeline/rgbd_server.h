// The server's pipeline: capture -> depth -> stitch -> encode -> publish, each stage on its
// own thread, joined by bounded queues that drop the oldest frame (counted, by reason) when the
// next stage is busy, so latency does not grow when compute is slower than the cameras. Depth
// and stitch share one GPU context. A status thread publishes ServerStatus once a second.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "omnisweep/codec/codec.h"
#include "omnisweep/dds/stream_publisher.h"
#include "omnisweep/foxglove/foxglove_server.h"
#include "omnisweep/gpu/context.h"
#include "omnisweep/ros2/ros_publisher.h"
#include "server/capture/frame_source.h"
#include "server/depth/depth_options.h"
#include "server/pipeline/frame_budget.h"
#include "server/stitch/stitcher.h"

namespace omnisweep::pipeline {

struct ServerOptions {
  depth::DepthOptions depth;
  int panorama_width = 2048;
  int panorama_height = 1024;
  std::optional<Eigen::Vector3d> viewpoint;           // rig frame; default: mean of the references
  std::optional<std::pair<int, int>> rgb_resolution;  // colour sampling size; default: images'
  double fps = 30.0;                                  // capture cap, frames per second
  int jpeg_quality = 90;                              // the highest; the frame budget may lower it
  // Colour + distance payload bytes per frame: a frame that would be larger gets a lower JPEG
  // quality, down to FrameBudget::kFloorQuality (0: no budget).
  std::size_t max_frame_bytes = 1000000;
  codec::DistanceParams distance;  // min/max distance are taken from `depth`
  std::uint64_t max_frames = 0;    // stop after publishing this many (0: until stopped)
  std::string dump_dir;  // when set: <seq>.jpg and <seq>_distance.f32 of every published frame
  // Also publish each frame's distance confidence on <prefix>/confidence ("conf8-zstd"), just
  // before the frame; the publisher must have been made with its confidence topic.
  bool confidence = false;
  // ROS 2 topics beside the stream's (docs/ros2.md); none when unset. A frame topic costs
  // nothing until a reader matches it; the conversion runs on a thread of its own ("ros"),
  // which drops frames ("ros busy") rather than slow the stream.
  std::optional<ros2::RosOptions> ros2;
  // A Foxglove WebSocket server for the ROS 2 topics (needs `ros2`); none when unset.
  std::optional<foxglove::FoxgloveOptions> foxglove;
  // The plane fill's confidence (StitchOptions::plane_fill, stitch/plane_fill.h); 0: off.
  double plane_fill = 0.0;
  // The region planes (StitchOptions::region_planes, stitch/region_planes.h); off by default.
  bool region_planes = false;
  // The edge check (StitchOptions::edge_check, stitch/edge_check.h); off by default.
  bool edge_check = false;
  // The membrane fill (StitchOptions::membrane_fill, stitch/membrane_fill.h); off by default.
  bool membrane_fill = false;
  // A temporal filter on the distance (stitch/temporal_filter.h); none by default.
  std::optional<stitch::TemporalOptions> temporal;
  bool exit_on_source_end = false;  // else a stalled or ended source is reported and retried
  double log_interval_s = 10.0;     // a status line on stderr this often (0: never)

  void check() const;  // throws std::invalid_argument naming the bad option
};

class StatusBoard;

class RgbdServer {
 public:
  RgbdServer(std::unique_ptr<capture::FrameSource> source, gpu::Context& context,
             dds::StreamPublisher& publisher, const ServerOptions& options);
  ~RgbdServer();  // stops and joins
  RgbdServer(const RgbdServer&) = delete;
  RgbdServer& operator=(const RgbdServer&) = delete;

  void start();
  void request_stop();
  // Waits until every stage thread has ended or `timeout_s` passed; true when all ended.
  bool wait_stopped(double timeout_s);
  // True once max_frames were published, a stage failed, or the source ended (when configured).
  bool finished() const { return finished_; }
  // The error that ended the server, if any.
  std::string error() const;
  std::uint64_t frames_published() const { return published_; }
  // The Foxglove server's port (ServerOptions::foxglove), 0 without one.
  int foxglove_port() const;
  // True once the threads that use the publisher (publish, status, ros) have ended.
  bool publisher_released() const { return publish_ended_ && status_ended_ && ros_ended_; }

 private:
  struct Job;
  void capture_loop();
  void gpu_loop();
  void encode_loop();
  void publish_loop();
  void ros_loop();
  void status_loop();
  void fail(const std::string& stage, const std::string& what);

  std::unique_ptr<capture::FrameSource> source_;
  gpu::Context* context_;
  dds::StreamPublisher* publisher_;
  ServerOptions options_;
  struct Stages;
  std::unique_ptr<Stages> stages_;
  std::unique_ptr<ros2::RosPublisher> ros_;             // ServerOptions::ros2
  std::unique_ptr<foxglove::FoxgloveServer> foxglove_;  // ServerOptions::foxglove
  bool ros_wanted() const;  // some DDS reader or Foxglove client reads a frame topic

  std::atomic<bool> stop_{false};
  std::atomic<bool> finished_{false};
  std::atomic<std::uint64_t> published_{0};
  std::atomic<int> color_quality_{0};                 // of the last frame encoded
  std::atomic<std::uint64_t> frames_over_budget_{0};  // even at the floor quality
  std::vector<std::thread> threads_;
  std::atomic<int> running_threads_{0};
  std::atomic<bool> publish_ended_{false}, status_ended_{false}, ros_ended_{false};
  std::mutex done_mutex_;
  std::condition_variable done_;

  std::unique_ptr<StatusBoard> board_;  // the status: stage times, drops, state, cameras
};

}  // namespace omnisweep::pipeline
