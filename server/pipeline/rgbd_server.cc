#include "server/pipeline/rgbd_server.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "omnisweep/foxglove/ros_channels.h"
#include "omnisweep/wire/wire.h"
#include "server/depth/depth_estimator.h"
#include "server/depth/depth_inputs.h"
#include "server/depth/photometric_model.h"
#include "server/pipeline/bounded_queue.h"
#include "server/pipeline/gpu_frame.h"
#include "server/pipeline/server_status.h"

namespace omnisweep::pipeline {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

msg::Vector3 to_vector(const Eigen::Vector3d& v) {
  msg::Vector3 m;
  m.x(v.x());
  m.y(v.y());
  m.z(v.z());
  return m;
}

}  // namespace

void ServerOptions::check() const {
  if (!(fps > 0 && fps <= 1000)) throw std::invalid_argument("fps must be in (0, 1000]");
  if (panorama_width < 8 || panorama_height < 4 || panorama_width != 2 * panorama_height)
    throw std::invalid_argument("panorama resolution must be W x W/2 with W >= 8");
  if (jpeg_quality < 1 || jpeg_quality > 100)
    throw std::invalid_argument("JPEG quality must be 1-100");
  distance.check();
  if (ros2) ros2->check();
  if (foxglove && !ros2)
    throw std::invalid_argument("the Foxglove server serves the ROS 2 topics; it needs them on");
  if (foxglove) foxglove->check();
}

// One frame on its way through the pipeline.
struct RgbdServer::Job {
  std::uint64_t sequence = 0;
  std::vector<std::uint64_t> capture_time_ns;
  std::uint64_t processing_start_ns = 0;
  std::vector<Rgb8Image> images;  // full resolution
  stitch::Panorama panorama;
  msg::RgbdFrame message;
  std::optional<msg::ConfidenceFrame> confidence;  // ServerOptions::confidence
  Rgb8Image ros_color;  // the panorama's colour, kept for the ROS point cloud when it has readers
};

struct RgbdServer::Stages {
  Rig matching_rig, color_rig;
  std::vector<std::optional<Gray8Image>> masks;
  depth::DepthEstimator estimator;
  stitch::Stitcher stitcher;
  GpuFrame gpu_frame;                                     // the two, one submission per frame
  std::optional<depth::PhotometricCorrector> photometry;  // DepthOptions::correct_photometry
  std::unique_ptr<codec::DistanceCodec> distance_codec;
  std::unique_ptr<codec::ConfidenceCodec> confidence_codec;
  FrameBudget budget;  // the colour codec, at the quality the frame budget allows
  msg::StreamDescription description;
  BoundedQueue<std::shared_ptr<Job>> to_depth{1}, to_encode{2}, to_publish{2}, to_ros{1};

  Stages(gpu::Context& context, const capture::FrameSource& source, const ServerOptions& o)
      : matching_rig(source.rig().resized(o.depth.matching_width, o.depth.matching_height)),
        color_rig(o.rgb_resolution
                      ? source.rig().resized(o.rgb_resolution->first, o.rgb_resolution->second)
                      : source.rig()),
        masks(depth::matching_masks(source.masks(), o.depth)),
        estimator(context, matching_rig, masks, o.depth),
        stitcher(context, matching_rig, color_rig, o.depth.references, masks,
                 stitch::StitchOptions{.panorama_width = o.panorama_width,
                                       .panorama_height = o.panorama_height,
                                       .viewpoint = o.viewpoint,
                                       .min_distance = o.depth.min_distance,
                                       .max_distance = o.depth.max_distance,
                                       .plane_fill = o.plane_fill,
                                       .region_planes = o.region_planes,
                                       .edge_check = o.edge_check,
                                       .membrane_fill = o.membrane_fill,
                                       .temporal = o.temporal}),
        gpu_frame(context, estimator, stitcher),
        distance_codec(codec::make_distance_codec(codec::kQinv16Zstd)),
        confidence_codec(codec::make_confidence_codec(codec::kConf8Zstd)),
        budget(o.jpeg_quality, o.max_frame_bytes) {
    if (o.depth.correct_photometry)
      photometry.emplace(matching_rig, masks, /*refresh_every=*/30,  // about once a second
                         /*refit_in_background=*/true);
  }
};

RgbdServer::RgbdServer(std::unique_ptr<capture::FrameSource> source, gpu::Context& context,
                       dds::StreamPublisher& publisher, const ServerOptions& options)
    : source_(std::move(source)), context_(&context), publisher_(&publisher), options_(options) {
  options_.check();
  options_.depth.check(source_->rig().num_cameras());
  options_.distance.min_distance = float(options_.depth.min_distance);
  options_.distance.max_distance = float(options_.depth.max_distance);
  options_.distance.check();
  stages_ = std::make_unique<Stages>(context, *source_, options_);
  color_quality_ = options_.jpeg_quality;
  msg::StreamDescription& d = stages_->description;
  wire::add_rig(source_->rig(), &d);
  d.revision(wall_clock_ns());
  d.references(std::vector<std::int32_t>(options_.depth.references.begin(),
                                         options_.depth.references.end()));
  d.panorama_width(std::uint32_t(options_.panorama_width));
  d.panorama_height(std::uint32_t(options_.panorama_height));
  d.viewpoint(to_vector(stages_->stitcher.viewpoint()));
  d.color_codec(stages_->budget.codec_name());
  d.distance_codec(stages_->distance_codec->name());
  d.distance_params(wire::to_message(options_.distance));
  d.target_fps(float(options_.fps));
  if (!options_.dump_dir.empty()) std::filesystem::create_directories(options_.dump_dir);
  if (options_.ros2)
    ros_ = std::make_unique<ros2::RosPublisher>(publisher.participant(), *options_.ros2);
  std::vector<std::string> stage_names = {"capture", "depth", "stitch", "encode", "publish"};
  if (ros_) stage_names.emplace_back("ros");
  board_ = std::make_unique<StatusBoard>(std::move(stage_names));
  board_->set_cameras(source_->camera_status());
  if (options_.foxglove) {
    foxglove_ = std::make_unique<foxglove::FoxgloveServer>(
        *options_.foxglove, foxglove::ros_channels(options_.ros2->ros_namespace));
  }
}

int RgbdServer::foxglove_port() const { return foxglove_ ? foxglove_->port() : 0; }

bool RgbdServer::ros_wanted() const {
  return ros_ && (ros_->wants_frames() || (foxglove_ && foxglove::wanted(*foxglove_).any()));
}

RgbdServer::~RgbdServer() {
  request_stop();
  for (auto& t : threads_)
    if (t.joinable()) t.join();
}

void RgbdServer::start() {
  publisher_->publish(stages_->description);
  if (ros_) {
    std::vector<Rigid3d> rig_from_cam;
    for (const auto& camera : source_->rig().cameras) rig_from_cam.push_back(camera.rig_from_cam);
    const std::uint64_t now = wall_clock_ns();
    const auto tf = ros_->publish_static(now, rig_from_cam, stages_->stitcher.viewpoint());
    if (foxglove_)
      foxglove::publish(*foxglove_, dds::TopicKind::kRosTfStatic, now, ros2::to_cdr(tf));
  } else {
    ros_ended_ = true;
  }
  auto spawn = [&](void (RgbdServer::*loop)(), const char* stage,
                   std::atomic<bool>* ended = nullptr) {
    ++running_threads_;
    threads_.emplace_back([this, loop, stage, ended] {
      try {
        (this->*loop)();
      } catch (const std::exception& e) {
        fail(stage, e.what());
      }
      if (ended) *ended = true;
      {
        const std::lock_guard lock(done_mutex_);
        --running_threads_;
      }
      done_.notify_all();
    });
  };
  spawn(&RgbdServer::capture_loop, "capture");
  spawn(&RgbdServer::gpu_loop, "depth");
  spawn(&RgbdServer::encode_loop, "encode");
  spawn(&RgbdServer::publish_loop, "publish", &publish_ended_);
  if (ros_) spawn(&RgbdServer::ros_loop, "ros", &ros_ended_);
  spawn(&RgbdServer::status_loop, "status", &status_ended_);
}

void RgbdServer::request_stop() {
  stop_ = true;
  stages_->to_depth.close();
  stages_->to_encode.close();
  stages_->to_publish.close();
  stages_->to_ros.close();
  done_.notify_all();
}

bool RgbdServer::wait_stopped(double timeout_s) {
  std::unique_lock lock(done_mutex_);
  return done_.wait_for(lock, std::chrono::duration<double>(timeout_s),
                        [&] { return running_threads_ == 0; });
}

std::string RgbdServer::error() const { return board_->error(); }

void RgbdServer::fail(const std::string& stage, const std::string& what) {
  board_->fail(stage + ": " + what);
  finished_ = true;
  request_stop();
}

void RgbdServer::capture_loop() {
  const auto period = std::chrono::duration_cast<Clock::duration>(
      std::chrono::duration<double>(1.0 / options_.fps));
  auto next_tick = Clock::now();
  std::uint64_t sequence = 0;
  const bool live = source_->live();
  while (!stop_) {
    std::this_thread::sleep_until(next_tick);
    // A source that can wait is read once depth has room for its frame (none is made only to be
    // dropped, and its reads leave the CPU to depth); live cameras are drained at --fps.
    if (!live && !stages_->to_depth.wait_for_room()) break;
    next_tick = std::max(next_tick + period, Clock::now());
    const auto start = Clock::now();
    std::optional<capture::CapturedFrame> frame;
    try {
      frame = source_->next();
    } catch (const capture::SourceError& e) {
      board_->source_stalled(source_->camera_status());
      std::fprintf(stderr, "omnisweep-server: source stalled: %s\n", e.what());
      if (options_.exit_on_source_end) throw;
      for (int i = 0; i < 10 && !stop_; ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
      continue;
    }
    if (!frame) {
      std::fprintf(stderr, "omnisweep-server: the source ended\n");
      if (options_.exit_on_source_end) {
        finished_ = true;
        request_stop();
        return;
      }
      board_->source_ended();
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      continue;
    }
    board_->add_stage_time("capture", ms_since(start));
    board_->count_captured(source_->camera_status());
    auto job = std::make_shared<Job>();
    job->sequence = sequence++;
    job->capture_time_ns = std::move(frame->capture_time_ns);
    job->images = std::move(frame->images);
    if (stages_->to_depth.push(std::move(job))) board_->count_drop("depth busy");
  }
}

// Depth and stitching of a frame in one GPU submission (GpuFrame): the camera images go up, the
// panorama comes down, and the depth maps never leave the GPU. The wire's "depth" stage is the
// frame's time up to the panorama but the stitcher's GPU time, which is "stitch".
void RgbdServer::gpu_loop() {
  while (auto item = stages_->to_depth.pop()) {
    Job& job = **item;
    const auto start = Clock::now();
    job.processing_start_ns = wall_clock_ns();
    std::vector<Rgb8Image> images = depth::matching_images(job.images, options_.depth);
    std::vector<Rgb8Image> color =
        depth::reference_color_images(job.images, stages_->color_rig, options_.depth.references);
    const depth::PhotometryFit* photometry =
        stages_->photometry ? &stages_->photometry->fit(views(images)) : nullptr;
    job.panorama = stages_->gpu_frame.run(views(images), views(color), photometry);
    job.images.clear();
    double stitch_ms = 0;
    for (const auto& [stage, ms] : job.panorama.stage_ms)
      if (stage == "warp" || stage == "merge") stitch_ms += ms;
    board_->add_stage_time("depth", ms_since(start) - stitch_ms);
    board_->add_stage_time("stitch", stitch_ms);
    // Behind a source that waits, a stage waits for the next one too: no frame is computed only
    // to be dropped. Behind live cameras the newest frame replaces a waiting one.
    if (!source_->live() && !stages_->to_encode.wait_for_room()) break;
    if (stages_->to_encode.push(std::move(*item))) board_->count_drop("encoder busy");
  }
}

void RgbdServer::encode_loop() {
  while (auto item = stages_->to_encode.pop()) {
    Job& job = **item;
    const auto start = Clock::now();
    const codec::Bytes distance =
        stages_->distance_codec->encode(job.panorama.distance, options_.distance);
    const int quality_before = stages_->budget.quality();
    FrameBudget::Color encoded = stages_->budget.encode(job.panorama.rgb, distance.size());
    const codec::Bytes& color = encoded.bytes;
    color_quality_ = encoded.quality;
    if (encoded.over_budget) ++frames_over_budget_;
    if (encoded.quality != quality_before) {
      std::fprintf(stderr,
                   "omnisweep-server: colour JPEG quality %d -> %d (frame of %zu bytes, budget "
                   "%zu)%s\n",
                   quality_before, encoded.quality, color.size() + distance.size(),
                   options_.max_frame_bytes,
                   encoded.over_budget ? ": over budget even at the lowest quality" : "");
    }
    msg::RgbdFrame& m = job.message;
    m.sequence_number(job.sequence);
    m.description_revision(stages_->description.revision());
    m.capture_time_ns(job.capture_time_ns);
    m.processing_start_ns(job.processing_start_ns);
    m.processing_end_ns(wall_clock_ns());
    m.viewpoint(stages_->description.viewpoint());
    m.width(std::uint32_t(job.panorama.rgb.width()));
    m.height(std::uint32_t(job.panorama.rgb.height()));
    m.color(wire::make_payload(stages_->budget.codec_name(), color));
    m.distance(wire::make_payload(stages_->distance_codec->name(), distance));
    m.distance_params(wire::to_message(options_.distance));
    if (options_.confidence) {
      msg::ConfidenceFrame c;
      c.sequence_number(job.sequence);
      c.description_revision(stages_->description.revision());
      c.width(m.width());
      c.height(m.height());
      c.confidence(wire::make_payload(
          stages_->confidence_codec->name(),
          stages_->confidence_codec->encode(codec::confidence_levels(job.panorama.confidence))));
      job.confidence = std::move(c);
    }
    if (!options_.dump_dir.empty()) {
      const std::filesystem::path base =
          std::filesystem::path(options_.dump_dir) / std::to_string(job.sequence);
      std::ofstream(base.string() + ".jpg", std::ios::binary)
          .write(reinterpret_cast<const char*>(color.data()), std::streamsize(color.size()));
      std::ofstream(base.string() + "_distance.f32", std::ios::binary)
          .write(reinterpret_cast<const char*>(job.panorama.distance.data()),
                 std::streamsize(job.panorama.distance.size() * sizeof(float)));
    }
    if (ros_ && (ros_->readers(dds::TopicKind::kRosPoints) > 0 ||
                 (foxglove_ && foxglove::wanted(*foxglove_).points)))
      job.ros_color = std::move(job.panorama.rgb);
    job.panorama = {};
    board_->add_stage_time("encode", ms_since(start));
    if (stages_->to_publish.push(std::move(*item))) board_->count_drop("network busy");
  }
}

void RgbdServer::publish_loop() {
  while (auto item = stages_->to_publish.pop()) {
    const auto start = Clock::now();
    // The confidence first, so that a subscriber holds it when its frame arrives.
    if ((*item)->confidence) publisher_->publish(*(*item)->confidence);
    (*item)->message.publish_time_ns(wall_clock_ns());
    publisher_->publish((*item)->message);
    board_->add_stage_time("publish", ms_since(start));
    board_->count_published();
    if (ros_wanted() && stages_->to_ros.push(std::move(*item))) board_->count_drop("ros busy");
    if (++published_ == options_.max_frames && options_.max_frames > 0) {
      finished_ = true;
      done_.notify_all();
    }
  }
}

// The ROS 2 frame topics that have readers (RosPublisher converts only those), from the
// payloads as published: the same JPEG bytes, the same distance levels.
void RgbdServer::ros_loop() {
  while (auto item = stages_->to_ros.pop()) {
    const Job& job = **item;
    const msg::RgbdFrame& m = job.message;
    const auto start = Clock::now();
    // What any receiver of the frame would take from it (ros2::frame_inputs, CRCs checked).
    ros2::FrameInputs frame = ros2::frame_inputs(m);
    if (!job.ros_color.empty()) frame.color = &job.ros_color;
    const ros2::FrameMessages messages =
        ros_->publish_frame(frame, foxglove_ ? foxglove::wanted(*foxglove_) : ros2::WantedTopics{});
    if (foxglove_) foxglove::publish(*foxglove_, messages);
    board_->add_stage_time("ros", ms_since(start));
  }
}

void RgbdServer::status_loop() {
  auto next = Clock::now();
  double since_log = 0;
  while (!stop_) {
    next += std::chrono::seconds(1);
    {
      std::unique_lock lock(done_mutex_);
      done_.wait_until(lock, next, [&] { return bool(stop_); });
    }
    if (stop_) break;
    msg::ServerStatus status =
        board_->take(wall_clock_ns(), {.stopping = stop_,
                                       .matched_subscribers = publisher_->frame_subscribers(),
                                       .color_quality = color_quality_,
                                       .frames_over_budget = frames_over_budget_});
    publisher_->publish(status);
    if (ros_) {
      const auto diagnostics = ros_->publish_diagnostics(status.time_ns(), status);
      if (foxglove_)
        foxglove::publish(*foxglove_, dds::TopicKind::kRosDiagnostics, status.time_ns(),
                          ros2::to_cdr(diagnostics));
    }
    since_log += 1.0;
    if (options_.log_interval_s > 0 && since_log >= options_.log_interval_s) {
      since_log = 0;
      std::string foxglove;
      if (foxglove_) {
        const foxglove::FoxgloveStats f = foxglove_->stats();
        foxglove = ", Foxglove: " + std::to_string(f.clients) + " clients, " +
                   std::to_string(f.sent) + " sent, " + std::to_string(f.dropped) +
                   " dropped by slow clients, " + std::to_string(f.refused) + " bad requests";
      }
      std::fprintf(stderr, "omnisweep-server: %s\n",
                   status_log_line(status, published_, foxglove).c_str());
    }
  }
}

}  // namespace omnisweep::pipeline
