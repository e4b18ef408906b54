// omnisweep-server's ROS 2 topics as ROS tools see them, on loopback: every topic carries the
// stream (the JPEG bytes themselves, compressedDepth and the 32FC1 image decoding to the
// stream's distances, points on its distance map, the rig's transforms, diagnostics with the
// fps), Cyclone DDS (an independent implementation, types from its own idlc) receives the
// images, recordings hold the ROS topics as rosbag2 writes them (read by Foxglove's own readers
// under Node) and play replays them, --no-ros2 leaves no rt/ topic, and bad ROS flags are
// refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/domain/DomainParticipantListener.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <thread>

#include "omnisweep/codec/codec.h"
#include "omnisweep/dds/stream_subscriber.h"
#include "omnisweep/geometry/equirectangular.h"
#include "omnisweep/record/stream_recording.h"
#include "omnisweep/ros2/ros_messages.h"
#include "omnisweep/ros2/ros_publisher.h"
#include "omnisweep/wire/wire.h"
#include "tests/support/stream_fixture.h"

namespace omnisweep {
namespace {

namespace fs = std::filesystem;
namespace fdds = eprosima::fastdds::dds;
using dds::TopicKind;
using testing::BackgroundProcess;
using testing::run_command;
using Clock = std::chrono::steady_clock;

// The stream as its own subscribers get it: every frame's payloads by capture stamp.
class StreamFrames {
 public:
  explicit StreamFrames(const dds::ParticipantOptions& options)
      : subscriber_(options, "reliable", keep_frames()) {}
  std::optional<msg::RgbdFrame> at(std::uint64_t stamp) const {
    const std::lock_guard lock(mutex_);
    const auto it = frames_.find(stamp);
    if (it == frames_.end()) return std::nullopt;
    return it->second;
  }
  bool has(std::uint64_t stamp) const {
    const std::lock_guard lock(mutex_);
    return frames_.count(stamp) != 0;
  }
  std::size_t size() const {
    const std::lock_guard lock(mutex_);
    return frames_.size();
  }
  // A frame sent before this reader matched never reaches it (VOLATILE), and in the sanitizer
  // build it can match seconds after the server starts: waits for its first frame (until
  // `deadline`, while the server runs), after which it receives every frame a client then sees.
  bool wait_for_first(Clock::time_point deadline, BackgroundProcess& server) const {
    while (size() == 0 && Clock::now() < deadline && server.running())
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    return size() > 0;
  }
  // The reader can lag a client by seconds in the sanitizer build: waits (at most 60 s) until it
  // holds every one of `stamps`.
  void wait_for(const std::set<std::uint64_t>& stamps) const {
    const auto deadline = Clock::now() + std::chrono::seconds(60);
    while (!std::all_of(stamps.begin(), stamps.end(), [&](std::uint64_t t) { return has(t); }) &&
           Clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }

 private:
  dds::StreamCallbacks keep_frames() {
    dds::StreamCallbacks callbacks;
    callbacks.frame = [this](const msg::RgbdFrame& f) {
      const std::lock_guard lock(mutex_);
      const auto& t = f.capture_time_ns();
      frames_[*std::min_element(t.begin(), t.end())] = f;
    };
    return callbacks;
  }

  mutable std::mutex mutex_;
  std::map<std::uint64_t, msg::RgbdFrame> frames_;
  dds::StreamSubscriber subscriber_;
};

// The stream's distance map of a frame, as every subscriber decodes it.
FloatImage stream_distance(const msg::RgbdFrame& frame) {
  const auto codec = codec::make_distance_codec(frame.distance().codec());
  return codec->decode(frame.distance().data(), int(frame.width()), int(frame.height()),
                       wire::from_message(frame.distance_params()));
}

// Readers of every ROS topic, as ROS tools make them (the QoS profiles of kTopics).
class RosReaders {
 public:
  RosReaders(const dds::ParticipantOptions& options, const std::string& ros_namespace)
      : participant_(options) {
    ros2::add_ros_topics(participant_, ros_namespace);
    fdds::Subscriber& subscriber = participant_.subscriber();
    for (const dds::TopicSpec& spec : dds::kTopics) {
      if (dds::is_stream_topic(spec.kind)) continue;
      fdds::DataReaderQos qos;
      EXPECT_EQ(subscriber.get_datareader_qos_from_profile(std::string(spec.reader_profile), qos),
                eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK);
      readers_[std::size_t(spec.kind)] =
          subscriber.create_datareader(&participant_.topic(spec.kind), qos);
    }
  }
  ~RosReaders() {
    for (auto* reader : readers_)
      if (reader) participant_.subscriber().delete_datareader(reader);
  }
  // The next sample of `kind`, if one waits.
  template <typename Message>
  std::optional<Message> take(TopicKind kind) {
    Message m;
    fdds::SampleInfo info;
    if (readers_[std::size_t(kind)]->take_next_sample(&m, &info) ==
            eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK &&
        info.valid_data)
      return m;
    return std::nullopt;
  }

 private:
  dds::Participant participant_;
  std::array<fdds::DataReader*, dds::kTopics.size()> readers_{};
};

class Ros2Test : public testing::StreamTest {
 protected:
  std::string ros_namespace() const { return ros2::namespace_for_prefix(topic_prefix_); }
};

TEST_F(Ros2Test, EveryTopicCarriesTheStream) {
  StreamFrames stream(participant_options());
  RosReaders ros(participant_options(), ros_namespace());
  BackgroundProcess server(server_command(" --ros-points 64 32"), dir_.path() / "server.log");
  std::map<std::uint64_t, sensor_msgs::msg::CompressedImage> colors, depths;
  std::map<std::uint64_t, sensor_msgs::msg::Image> distances;
  std::map<std::uint64_t, sensor_msgs::msg::PointCloud2> points;
  std::optional<tf2_msgs::msg::TFMessage> tf;
  std::optional<diagnostic_msgs::msg::DiagnosticArray> diagnostics;
  // The test's stream reader and the ROS readers match the server's writers at their own pace
  // (seconds apart in the sanitizer build), and a frame sent before a reader matched never
  // reaches it (VOLATILE): collect until 3 frames of each ROS topic are also in the stream.
  const auto deadline = Clock::now() + std::chrono::seconds(120);
  const auto in_stream = [&](const auto& messages) {
    return std::count_if(messages.begin(), messages.end(),
                         [&](const auto& m) { return stream.has(m.first); });
  };
  const auto enough = [&] {
    return in_stream(colors) >= 3 && in_stream(depths) >= 3 && in_stream(distances) >= 3 &&
           in_stream(points) >= 3 && tf && diagnostics;
  };
  while (!enough() && Clock::now() < deadline) {
    bool any = false;
    if (auto m = ros.take<sensor_msgs::msg::CompressedImage>(TopicKind::kRosColor))
      any = true, colors[ros2::stamp_ns(m->header().stamp())] = *m;
    if (auto m = ros.take<sensor_msgs::msg::CompressedImage>(TopicKind::kRosCompressedDepth))
      any = true, depths[ros2::stamp_ns(m->header().stamp())] = *m;
    if (auto m = ros.take<sensor_msgs::msg::Image>(TopicKind::kRosDistance))
      any = true, distances[ros2::stamp_ns(m->header().stamp())] = *m;
    if (auto m = ros.take<sensor_msgs::msg::PointCloud2>(TopicKind::kRosPoints))
      any = true, points[ros2::stamp_ns(m->header().stamp())] = *m;
    if (auto m = ros.take<tf2_msgs::msg::TFMessage>(TopicKind::kRosTfStatic)) any = true, tf = m;
    if (auto m = ros.take<diagnostic_msgs::msg::DiagnosticArray>(TopicKind::kRosDiagnostics))
      any = true, diagnostics = m;
    if (!any) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_TRUE(enough()) << colors.size() << " colour, " << depths.size() << " compressedDepth, "
                        << distances.size() << " distance, " << points.size() << " points, tf "
                        << bool(tf) << ", diagnostics " << bool(diagnostics) << ", "
                        << stream.size() << " stream frames\n"
                        << server.log();
  const std::string panorama_frame =
      ros2::frame_prefix_for_namespace(ros_namespace()) + "_panorama";
  const std::string rig_frame = ros2::frame_prefix_for_namespace(ros_namespace()) + "_rig";

  int checked = 0;
  for (const auto& [stamp, m] : colors) {
    const auto frame = stream.at(stamp);
    if (!frame) continue;
    EXPECT_EQ(m.format(), "rgb8; jpeg compressed bgr8");
    EXPECT_EQ(m.header().frame_id(), panorama_frame);
    EXPECT_EQ(m.data(), frame->color().data()) << "the JPEG is the stream's own bytes";
    ++checked;
  }
  EXPECT_GE(checked, 2);
  checked = 0;
  for (const auto& [stamp, m] : distances) {
    const auto frame = stream.at(stamp);
    if (!frame) continue;
    const FloatImage want = stream_distance(*frame);
    ASSERT_EQ(m.width(), 256u);
    ASSERT_EQ(m.height(), 128u);
    EXPECT_EQ(m.encoding(), "32FC1");
    const float* got = reinterpret_cast<const float*>(m.data().data());
    for (std::size_t i = 0; i < want.size(); ++i) {
      if (want.data()[i] == 0.0f)
        ASSERT_TRUE(std::isnan(got[i])) << i;
      else
        ASSERT_EQ(got[i], want.data()[i]) << i;
    }
    ++checked;
  }
  EXPECT_GE(checked, 2);
  checked = 0;
  for (const auto& [stamp, m] : depths) {
    const auto frame = stream.at(stamp);
    if (!frame) continue;
    const FloatImage want = stream_distance(*frame);
    const FloatImage got = ros2::decode_compressed_depth(m);
    ASSERT_EQ(got.width(), 256);
    const double bound = wire::from_message(frame->distance_params()).max_quantisation_error();
    for (std::size_t i = 0; i < want.size(); ++i) {
      if (want.data()[i] == 0.0f) {
        ASSERT_TRUE(std::isnan(got.data()[i])) << i;
        continue;
      }
      // The same level through compressed_depth_image_transport's float A / (v - B).
      ASSERT_NEAR(1.0 / got.data()[i], 1.0 / want.data()[i], 0.05 * bound) << i;
    }
    ++checked;
  }
  EXPECT_GE(checked, 2);
  checked = 0;
  for (const auto& [stamp, m] : points) {
    const auto frame = stream.at(stamp);
    if (!frame) continue;
    const FloatImage want = stream_distance(*frame);
    const Eigen::Vector3d viewpoint(frame->viewpoint().x(), frame->viewpoint().y(),
                                    frame->viewpoint().z());
    EXPECT_EQ(m.header().frame_id(), rig_frame);
    ASSERT_EQ(m.width(), 64u);
    ASSERT_EQ(m.height(), 32u);
    int on_map = 0;
    for (std::size_t i = 0; i < std::size_t(64 * 32); ++i) {
      const float* p = reinterpret_cast<const float*>(m.data().data()) + 4 * i;
      if (std::isnan(p[0])) continue;
      const Eigen::Vector3d ray = Eigen::Vector3d(p[0], p[1], p[2]) - viewpoint;
      const Eigen::Vector2d pixel = equirect_pixel<double>(ray, 256, 128);
      const int x = int(std::lround(pixel.x())), y = int(std::lround(pixel.y()));
      ASSERT_NEAR(ray.norm(), want(x, y), 1e-4 * want(x, y)) << "point " << i;
      ++on_map;
    }
    EXPECT_GT(on_map, 64 * 32 / 2);
    ++checked;
  }
  EXPECT_GE(checked, 2);

  ASSERT_EQ(tf->transforms().size(), 5u);  // the panorama and 4 cameras
  EXPECT_EQ(tf->transforms()[0].header().frame_id(), rig_frame);
  EXPECT_EQ(tf->transforms()[0].child_frame_id(), panorama_frame);
  std::map<std::string, std::string> values;
  for (const auto& kv : diagnostics->status().at(0).values()) values[kv.key()] = kv.value();
  EXPECT_EQ(values.count("fps"), 1u);
  EXPECT_NE(diagnostics->status()[0].name().find(ros_namespace()), std::string::npos);
  std::cout << "ROS readers got " << colors.size() << " colour, " << depths.size()
            << " compressedDepth, " << distances.size() << " 32FC1, " << points.size()
            << " point clouds; compressedDepth " << depths.begin()->second.data().size()
            << " bytes, colour " << colors.begin()->second.data().size() << " bytes\n";
  double seconds = 0;
  EXPECT_EQ(server.stop(SIGTERM, 5, &seconds), 0) << server.log();
}

// Every topic a participant announces on the domain.
class TopicCollector : public fdds::DomainParticipantListener {
 public:
  void on_publisher_discovery(fdds::DomainParticipant*,
                              eprosima::fastrtps::rtps::WriterDiscoveryInfo&& info) override {
    const std::lock_guard lock(mutex_);
    topics_.insert(info.info.topicName().to_string());
  }
  std::set<std::string> topics() const {
    const std::lock_guard lock(mutex_);
    return topics_;
  }

 private:
  mutable std::mutex mutex_;
  std::set<std::string> topics_;
};

// Every topic announced on the domain once the server has published a frame (its writers, ROS
// ones included, are all made before its first frame): collected until `enough` holds (at most
// 30 s after that frame, since discovery of the server's writers can lag the stream on a slow,
// busy machine), then for `settle` more, for any writer announced alongside.
template <typename Enough>
std::set<std::string> topics_announced(int domain, const StreamFrames& stream,
                                       BackgroundProcess& server, const Enough& enough,
                                       std::chrono::milliseconds settle) {
  TopicCollector collector;
  auto* factory = fdds::DomainParticipantFactory::get_instance();
  fdds::DomainParticipant* participant = factory->create_participant(
      domain, fdds::PARTICIPANT_QOS_DEFAULT, &collector, fdds::StatusMask::none());
  auto deadline = Clock::now() + std::chrono::seconds(120);
  while (stream.size() == 0 && Clock::now() < deadline && server.running())
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  deadline = std::min(deadline, Clock::now() + std::chrono::seconds(30));
  while (!enough(collector.topics()) && Clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  std::this_thread::sleep_for(settle);
  factory->delete_participant(participant);
  return collector.topics();
}

std::set<std::string> rt_topics(const std::set<std::string>& topics) {
  std::set<std::string> rt;
  for (const std::string& t : topics)
    if (t.rfind("rt/", 0) == 0) rt.insert(t);
  return rt;
}

TEST_F(Ros2Test, NoRos2LeavesNoRtTopicAndTheDefaultHasThemAll) {
  const std::string ns = "rt" + ros_namespace();
  const std::set<std::string> all = {ns + "/color/image_raw/compressed",
                                     ns + "/distance/image_raw/compressedDepth",
                                     ns + "/distance/image_raw",
                                     ns + "/points",
                                     "rt/tf_static",
                                     "rt/diagnostics"};
  for (const bool ros : {false, true}) {
    StreamFrames stream(participant_options());
    BackgroundProcess server(server_command(ros ? "" : " --no-ros2"), dir_.path() / "server.log");
    const std::set<std::string> topics = topics_announced(
        domain_, stream, server,
        [&](const std::set<std::string>& seen) {
          return seen.count(topic_prefix_ + "/rgbd") > 0 && (!ros || rt_topics(seen) == all);
        },
        // Without ROS: a second more after the stream's own topic, for any rt/ writer.
        std::chrono::milliseconds(ros ? 0 : 1000));
    ASSERT_GT(stream.size(), 0u) << server.log();
    ASSERT_TRUE(topics.count(topic_prefix_ + "/rgbd")) << server.log();
    const std::set<std::string> rt = rt_topics(topics);
    if (!ros) {
      EXPECT_TRUE(rt.empty()) << *rt.begin();
    } else {
      EXPECT_EQ(rt, all);
    }
    double seconds = 0;
    EXPECT_EQ(server.stop(SIGTERM, 5, &seconds), 0) << server.log();
  }
}

TEST_F(Ros2Test, BadRosFlagsAreRefused) {
  const std::pair<const char*, const char*> cases[] = {
      {" --ros-namespace rig", "RosOptions.ros_namespace = \"rig\": must be a fully qualified"},
      {" --ros-namespace /rig-1", "character '-' is not allowed"},
      {" --ros-namespace /2rig", "must not start with a digit"},
      {" --ros-namespace /a//b", "must not contain \"//\""},
      {" --ros-frame-prefix a.b", "RosOptions.frame_prefix = \"a.b\""},
      {" --ros-points 100 20", "RosOptions.points = 100x20: must be W x W/2"},
      {" --no-ros2 --ros-namespace /x", "--no-ros2 turns the ROS 2 topics off"},
  };
  for (const auto& [flags, message] : cases) {
    std::string out;
    EXPECT_EQ(run_command(server_command(flags), &out), 1) << flags;
    EXPECT_NE(out.find(message), std::string::npos) << flags << ":\n" << out;
  }
}

// omnisweep-record writes the ROS 2 topics as rosbag2 does; Foxglove's readers (@mcap/core,
// @foxglove/rosmsg, rosmsg2-serialization under the recorded, Humble and Jazzy definitions)
// decode every message to the recorded stream's own images; omnisweep-play replays them on DDS.
TEST_F(Ros2Test, RecordingHoldsTheRosTopicsFoxgloveReadsAndPlayReplays) {
  if (!OMNISWEEP_HAVE_NODE) GTEST_SKIP() << "Node.js was not found when the build was configured";
  const fs::path node_dir = testing::mcap_node_dir();
  ASSERT_TRUE(fs::exists(node_dir / "node_modules/@foxglove/rosmsg2-serialization"))
      << "the mcap_node_setup test installs the Node packages in " << node_dir;
  const fs::path file = dir_.path() / "ros.mcap";
  {
    BackgroundProcess server(server_command(" --no-ros2"), dir_.path() / "server.log");
    std::string out;
    ASSERT_EQ(run_command(tool_command("record", " --output " + file.string() +
                                                     " --frames 8 --ros2-raw --ros-points 64 32"),
                          &out),
              0)
        << out << server.log();
    double seconds = 0;
    EXPECT_EQ(server.stop(SIGTERM, 5, &seconds), 0) << server.log();
  }
  // The stream's frames as recorded, by capture stamp.
  std::map<std::uint64_t, msg::RgbdFrame> frames;
  record::McapReader reader(file);
  reader.read([&](const record::McapMessage& m) {
    if (record::recorded_topic(reader, *m.channel) == TopicKind::kFrames) {
      msg::RgbdFrame f;
      record::decode_message(m.data, f);
      frames[*std::min_element(f.capture_time_ns().begin(), f.capture_time_ns().end())] = f;
    }
    return true;
  });
  ASSERT_EQ(frames.size(), 8u);

  std::string out;
  ASSERT_EQ(
      run_command("node " + (node_dir / "read_ros2.mjs").string() + " " + file.string(), &out), 0)
      << out;
  const auto json = nlohmann::json::parse(out.substr(out.find('{')));
  EXPECT_EQ(json["profile"], "ros2");
  const std::string ns = ros_namespace();
  std::map<std::string, std::string> types;
  for (const auto& c : json["channels"]) {
    types[c["topic"]] = c["schemaName"];
    EXPECT_EQ(c["messageEncoding"], "cdr");
    EXPECT_NE(c["offeredQos"].get<std::string>().find("reliability: 1"), std::string::npos);
  }
  EXPECT_EQ(types,
            (std::map<std::string, std::string>{
                {ns + "/color/image_raw/compressed", "sensor_msgs/msg/CompressedImage"},
                {ns + "/distance/image_raw/compressedDepth", "sensor_msgs/msg/CompressedImage"},
                {ns + "/distance/image_raw", "sensor_msgs/msg/Image"},
                {ns + "/points", "sensor_msgs/msg/PointCloud2"},
                {"/tf_static", "tf2_msgs/msg/TFMessage"},
                {"/diagnostics", "diagnostic_msgs/msg/DiagnosticArray"}}));
  std::map<std::string, int> counts;
  for (const auto& m : json["messages"]) {
    const std::string topic = m["topic"];
    ++counts[topic];
    if (topic == "/tf_static") {
      EXPECT_EQ(m["children"].size(), 5u);
      continue;
    }
    if (topic == "/diagnostics") {
      EXPECT_FALSE(m["fps"].is_null());
      continue;
    }
    const auto frame = frames.find(std::stoull(m["stamp"].get<std::string>()));
    ASSERT_NE(frame, frames.end()) << m.dump();
    if (topic == ns + "/color/image_raw/compressed") {
      EXPECT_EQ(m["crc32"], frame->second.color().crc32()) << "the JPEG is the stream's bytes";
      EXPECT_EQ(m["bytes"], frame->second.color().data().size());
      EXPECT_EQ(m["width"], 256);
      EXPECT_EQ(m["height"], 128);
    } else if (topic == ns + "/distance/image_raw/compressedDepth") {
      const FloatImage want = stream_distance(frame->second);
      const double bound =
          wire::from_message(frame->second.distance_params()).max_quantisation_error();
      EXPECT_EQ(m["width"], 256);
      ASSERT_GT(m["samples"].size(), 300u);
      for (const auto& sample : m["samples"]) {
        const float stream = want.data()[sample[0].get<std::size_t>()];
        if (stream == 0.0f) {
          EXPECT_TRUE(sample[1].is_null());
        } else {
          ASSERT_NEAR(1.0 / sample[1].get<double>(), 1.0 / stream, 0.05 * bound) << sample;
        }
      }
    } else if (topic == ns + "/distance/image_raw") {
      EXPECT_EQ(m["bytes"], 256 * 128 * 4);
    } else if (topic == ns + "/points") {
      EXPECT_EQ(m["width"], 64);
      EXPECT_EQ(m["bytes"], 64 * 32 * 16);
    }
  }
  EXPECT_EQ(counts[ns + "/color/image_raw/compressed"], 8);
  EXPECT_EQ(counts[ns + "/distance/image_raw/compressedDepth"], 8);
  EXPECT_EQ(counts["/tf_static"], 1);
  EXPECT_GE(counts["/diagnostics"], 1);
  std::cout << "Foxglove's readers decoded " << json["messages"].size()
            << " ROS messages under the recorded, Humble and Jazzy definitions\n";

  // omnisweep-play replays the recorded ROS topics on DDS. It loops, so every recorded frame
  // arrives however long the reader takes to match (playback at 4x is over in 0.4 s).
  RosReaders ros(participant_options(), ns);
  BackgroundProcess play(tool_command("play", " " + file.string() + " --rate 4 --loop"),
                         dir_.path() / "play.log");
  std::set<std::uint64_t> replayed;
  const auto deadline = Clock::now() + std::chrono::seconds(60);
  while (replayed.size() < frames.size() && Clock::now() < deadline) {
    if (auto m = ros.take<sensor_msgs::msg::CompressedImage>(TopicKind::kRosColor)) {
      const std::uint64_t stamp = ros2::stamp_ns(m->header().stamp());
      ASSERT_TRUE(frames.count(stamp));
      EXPECT_EQ(m->data(), frames[stamp].color().data());
      replayed.insert(stamp);
    } else {
      ASSERT_TRUE(play.running()) << play.log();
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }
  EXPECT_EQ(replayed.size(), frames.size()) << play.log();
  double seconds = 0;
  play.stop(SIGTERM, 5, &seconds);
}

// Foxglove's own client (@foxglove/ws-protocol under Node) on a running server: every channel is
// advertised and decodes under the sent schema and Humble's and Jazzy's definitions to the
// stream's images; bad client messages get error statuses on a connection that lives on; a
// stalled client loses messages while another keeps receiving.
TEST_F(Ros2Test, FoxgloveClientsSeeTheStreamLive) {
  if (!OMNISWEEP_HAVE_NODE) GTEST_SKIP() << "Node.js was not found when the build was configured";
  const fs::path node_dir = testing::mcap_node_dir();
  ASSERT_TRUE(fs::exists(node_dir / "node_modules/@foxglove/ws-protocol"))
      << "the mcap_node_setup test installs the Node packages in " << node_dir;
  StreamFrames stream(participant_options());
  BackgroundProcess server(
      server_command(" --foxglove-port 0 --foxglove-address 127.0.0.1 --foxglove-client-queue "
                     "65536 --ros-points 64 32 --log-interval 1"),
      dir_.path() / "server.log");
  const std::regex address("ws://127\\.0\\.0\\.1:([0-9]+)");
  const auto deadline = Clock::now() + std::chrono::seconds(120);
  ASSERT_TRUE(server.wait_for_log(address, 120)) << server.log();
  std::string log = server.log();
  std::smatch match;
  ASSERT_TRUE(std::regex_search(log, match, address)) << log;
  ASSERT_TRUE(stream.wait_for_first(deadline, server)) << server.log();
  const std::string url = "ws://127.0.0.1:" + match[1].str();
  const std::string client = "node " + (node_dir / "foxglove_client.mjs").string() + " ";

  std::string out;
  ASSERT_EQ(run_command(client + "collect " + url + " 3", &out), 0) << out << server.log();
  const auto json = nlohmann::json::parse(out.substr(out.find('{')));
  EXPECT_EQ(json["serverInfo"]["name"], "omnisweep");
  EXPECT_EQ(json["channels"].size(), 6u);
  const std::string ns = ros_namespace();
  // The frames the client saw, once the test's own stream reader holds them all, are compared.
  std::set<std::uint64_t> seen;
  for (const auto& m : json["messages"]) {
    const std::string topic = m["topic"];
    if (topic != "/tf_static" && topic != "/diagnostics")
      seen.insert(std::stoull(m["stamp"].get<std::string>()));
  }
  stream.wait_for(seen);
  std::map<std::string, int> checked;
  std::size_t bytes = 0;
  for (const auto& m : json["messages"]) {
    const std::string topic = m["topic"];
    if (m.contains("bytes")) bytes += m["bytes"].get<std::size_t>();
    if (topic == "/tf_static") {
      EXPECT_EQ(m["children"].size(), 5u);
      ++checked[topic];
      continue;
    }
    if (topic == "/diagnostics") {
      EXPECT_FALSE(m["fps"].is_null());
      ++checked[topic];
      continue;
    }
    const auto frame = stream.at(std::stoull(m["stamp"].get<std::string>()));
    if (!frame) continue;
    EXPECT_EQ(m["timestamp"], m["stamp"]);  // the message time is the capture time
    const FloatImage want = stream_distance(*frame);
    if (topic == ns + "/color/image_raw/compressed") {
      EXPECT_EQ(m["crc32"], frame->color().crc32()) << "the JPEG is the stream's bytes";
      EXPECT_EQ(m["width"], 256);
    } else if (topic == ns + "/distance/image_raw/compressedDepth") {
      const double bound = wire::from_message(frame->distance_params()).max_quantisation_error();
      for (const auto& sample : m["samples"]) {
        const float stream_value = want.data()[sample[0].get<std::size_t>()];
        if (stream_value == 0.0f)
          EXPECT_TRUE(sample[1].is_null());
        else
          ASSERT_NEAR(1.0 / sample[1].get<double>(), 1.0 / stream_value, 0.05 * bound);
      }
    } else if (topic == ns + "/distance/image_raw") {
      EXPECT_EQ(m["bytes"], 256 * 128 * 4);
    } else if (topic == ns + "/points") {
      const Eigen::Vector3d viewpoint(frame->viewpoint().x(), frame->viewpoint().y(),
                                      frame->viewpoint().z());
      int on_map = 0;
      for (const auto& p : m["points"]) {
        if (p.is_null()) continue;
        const Eigen::Vector3d ray =
            Eigen::Vector3d(p[0].get<double>(), p[1].get<double>(), p[2].get<double>()) - viewpoint;
        const Eigen::Vector2d pixel = equirect_pixel<double>(ray, 256, 128);
        const float d = want(int(std::lround(pixel.x())) % 256, int(std::lround(pixel.y())));
        ASSERT_NEAR(ray.norm(), d, 1e-4 * d);
        ++on_map;
      }
      EXPECT_GT(on_map, 20);
    }
    ++checked[topic];
  }
  for (const char* topic : {"/color/image_raw/compressed", "/distance/image_raw/compressedDepth",
                            "/distance/image_raw", "/points"})
    EXPECT_GE(checked[ns + topic], 2) << topic;
  EXPECT_EQ(checked["/tf_static"], 1);
  EXPECT_GE(checked["/diagnostics"], 1);
  std::cout << "Foxglove client: " << json["messages"].size() << " messages, " << bytes
            << " bytes of images and points, each checked against the stream\n";

  ASSERT_EQ(run_command(client + "abuse " + url, &out), 0) << out;
  const auto abuse = nlohmann::json::parse(out.substr(out.find('{')));
  EXPECT_EQ(abuse["refused"], "HTTP 400");  // no Foxglove subprotocol
  std::vector<std::string> statuses;
  for (const auto& status : abuse["statuses"]) {
    EXPECT_EQ(status["level"], 2);
    statuses.push_back(status["message"]);
  }
  EXPECT_EQ(statuses,
            (std::vector<std::string>{
                "not valid JSON", "op \"getParameters\" is not supported (subscribe, unsubscribe)",
                "channel 99999 is not advertised", "no subscription 42",
                "message of 200068 bytes; the limit is 65536",
                "binary client messages are not supported", "JSON nested deeper than 16 levels"}));
  EXPECT_TRUE(abuse["gotMessage"]) << "the connection serves a subscription after all that";

  ASSERT_EQ(run_command(client + "stall " + url + " 25", &out), 0) << out << server.log();
  const auto stall = nlohmann::json::parse(out.substr(out.find('{')));
  EXPECT_EQ(stall["live"], 25);
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));  // a status line after it
  log = server.log();
  const std::regex dropped("([0-9]+) dropped by slow clients");
  std::uint64_t drops = 0;
  for (auto it = std::sregex_iterator(log.begin(), log.end(), dropped);
       it != std::sregex_iterator(); ++it)
    drops = std::stoull((*it)[1].str());
  EXPECT_GT(drops, 0u) << "the stalled client lost messages\n" << log;
  std::cout << "stalled client: the other received " << stall["live"] << " colour images in "
            << stall["seconds"] << " s; " << drops << " messages dropped for the stalled one\n";
  double seconds = 0;
  EXPECT_EQ(server.stop(SIGTERM, 5, &seconds), 0) << server.log();
}

#ifdef OMNISWEEP_CYCLONE_SUBSCRIBER
std::string read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Cyclone DDS, another vendor's DDS with types from its own idlc run on idl/ros2/ros2_msgs.idl,
// subscribes to the colour and the 32FC1 topics: what it receives equals the stream.
TEST_F(Ros2Test, CycloneDdsReceivesTheStreamsImages) {
  StreamFrames stream(participant_options());
  BackgroundProcess server(server_command(), dir_.path() / "server.log");
  const fs::path out = dir_.path() / "cyclone";
  fs::create_directories(out);
  ASSERT_TRUE(stream.wait_for_first(Clock::now() + std::chrono::seconds(120), server))
      << server.log();
  std::string log;
  ASSERT_EQ(run_command(std::string(OMNISWEEP_CYCLONE_SUBSCRIBER) + " " + std::to_string(domain_) +
                            " " + ros_namespace() + " " + out.string() + " 3 120",
                        &log),
            0)
      << log << server.log();
  // <kind>_<sec>_<nanosec>: the capture stamp of each image Cyclone DDS wrote.
  const auto stamp_of = [](const fs::path& path) {
    const std::string name = path.stem().string();
    const auto first = name.find('_'), second = name.rfind('_');
    return std::stoull(name.substr(first + 1, second - first - 1)) * 1'000'000'000ull +
           std::stoull(name.substr(second + 1));
  };
  std::set<std::uint64_t> written;
  for (const auto& entry : fs::directory_iterator(out)) written.insert(stamp_of(entry.path()));
  stream.wait_for(written);
  int colors = 0, distances = 0;
  std::size_t bytes = 0;
  for (const auto& entry : fs::directory_iterator(out)) {
    const std::string name = entry.path().stem().string();
    const auto frame = stream.at(stamp_of(entry.path()));
    if (!frame) continue;  // a frame the stream's reader was not yet matched for
    const std::string got = read_bytes(entry.path());
    bytes += got.size();
    if (name.rfind("color", 0) == 0) {
      EXPECT_EQ(got, std::string(frame->color().data().begin(), frame->color().data().end()))
          << name;
      ++colors;
    } else {
      const FloatImage want = stream_distance(*frame);
      ASSERT_EQ(got.size(), want.size() * 4) << name;
      const float* v = reinterpret_cast<const float*>(got.data());
      for (std::size_t i = 0; i < want.size(); ++i) {
        if (want.data()[i] == 0.0f)
          ASSERT_TRUE(std::isnan(v[i])) << name << " " << i;
        else
          ASSERT_EQ(v[i], want.data()[i]) << name << " " << i;
      }
      ++distances;
    }
  }
  std::cout << "Cyclone DDS received and matched " << colors << " colour and " << distances
            << " distance images equal to the stream's (" << bytes << " bytes)\n"
            << log;
  EXPECT_GE(colors, 2);
  EXPECT_GE(distances, 2);
  double seconds = 0;
  EXPECT_EQ(server.stop(SIGTERM, 5, &seconds), 0) << server.log();
}
#endif

}  // namespace
}  // namespace omnisweep
