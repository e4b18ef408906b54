// The wire format through a real CDR serialisation (what DDS sends), and bad messages.
#include "omnisweep/wire/wire.h"

#include <fastcdr/Cdr.h>
#include <fastcdr/FastBuffer.h>
#include <gtest/gtest.h>

#include "omnisweep/rig/basalt_calibration.h"
#include "omnisweep/wire/frame_stats.h"
#include "tests/support/status_fixture.h"
#include "tests/support/test_support.h"

namespace omnisweep::wire {
namespace {

template <typename T>
T cdr_round_trip(const T& message) {
  std::vector<char> storage(T::getCdrSerializedSize(message) + 64);
  eprosima::fastcdr::FastBuffer buffer(storage.data(), storage.size());
  eprosima::fastcdr::Cdr writer(buffer);
  message.serialize(writer);
  T back;
  eprosima::fastcdr::FastBuffer read_buffer(storage.data(), writer.getSerializedDataLength());
  eprosima::fastcdr::Cdr reader(read_buffer);
  back.deserialize(reader);
  return back;
}

msg::RgbdFrame make_frame(int w, int h) {
  Rgb8Image rgb(w, h);
  FloatImage distance(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      for (int c = 0; c < 3; ++c) rgb(x, y, c) = std::uint8_t((x * 3 + y * 5 + c * 70) % 256);
      distance(x, y) = 0.6f + 0.01f * float(x + y);
    }
  const codec::DistanceParams params;
  msg::RgbdFrame frame;
  frame.sequence_number(42);
  frame.width(std::uint32_t(w));
  frame.height(std::uint32_t(h));
  frame.capture_time_ns({1, 2, 3, 4});
  frame.color(make_payload(codec::kJpeg, codec::make_color_codec(codec::kJpeg)->encode(rgb)));
  frame.distance(
      make_payload(codec::kQinv16Zstd,
                   codec::make_distance_codec(codec::kQinv16Zstd)->encode(distance, params)));
  frame.distance_params(to_message(params));
  return frame;
}

TEST(Wire, FrameSurvivesCdrAndDecodes) {
  const msg::RgbdFrame sent = make_frame(256, 128);
  const msg::RgbdFrame received = cdr_round_trip(sent);
  EXPECT_EQ(received.sequence_number(), 42u);
  EXPECT_EQ(received.capture_time_ns().size(), 4u);
  EXPECT_EQ(received.color().data(), sent.color().data());  // JPEG bytes identical
  const DecodedFrame frame = decode_frame(received);
  EXPECT_EQ(frame.rgb.width(), 256);
  EXPECT_NEAR(1.0 / frame.distance(10, 20), 1.0 / (0.6 + 0.3),
              codec::DistanceParams().max_quantisation_error() * 1.01);
}

TEST(Wire, CorruptOrMismatchedFramesAreErrors) {
  msg::RgbdFrame frame = make_frame(64, 32);
  frame.color().data()[100] ^= 0x10;
  EXPECT_THROW(decode_frame(frame), WireError);  // CRC mismatch
  frame = make_frame(64, 32);
  frame.width(128);
  frame.height(64);
  EXPECT_ANY_THROW(decode_frame(frame));  // payloads of another size
  frame = make_frame(64, 32);
  frame.width(100);
  EXPECT_THROW(decode_frame(frame), WireError);  // not 2:1
  frame = make_frame(64, 32);
  frame.distance().codec("lz4");
  EXPECT_THROW(decode_frame(frame), codec::CodecError);
  frame = make_frame(64, 32);
  frame.distance_params().levels(1);
  EXPECT_THROW(decode_frame(frame), WireError);
}

TEST(Wire, DescriptionCarriesTheRig) {
  const Rig rig = read_basalt_calibration(testing::kaist_rig_dir() / "calibration.json");
  msg::StreamDescription description;
  add_rig(rig, &description);
  description.references({2, 3});
  const Rig back = rig_from_description(cdr_round_trip(description));
  ASSERT_EQ(back.num_cameras(), 4);
  EXPECT_EQ(back.cameras[2].model.params(), rig.cameras[2].model.params());
  EXPECT_TRUE(back.cameras[3].rig_from_cam.translation == rig.cameras[3].rig_from_cam.translation);

  msg::StreamDescription bad = description;
  bad.cameras()[1].params()[5] = 1.5;  // alpha
  try {
    rig_from_description(bad);
    FAIL();
  } catch (const WireError& e) {
    EXPECT_STREQ(e.what(), "description.cameras[1].params.alpha: must be within [0, 1]");
  }
  bad = description;
  bad.cameras()[0].camera_type("fisheye");
  EXPECT_THROW(rig_from_description(bad), WireError);
  bad = description;
  bad.cameras().resize(1);
  EXPECT_THROW(rig_from_description(bad), WireError);
}

TEST(Wire, ServerStatesRoundTripTheirWireText) {
  for (const ServerState state :
       {ServerState::kStarting, ServerState::kRunning, ServerState::kSourceStalled,
        ServerState::kSourceEnded, ServerState::kStopping, ServerState::kFailed})
    EXPECT_EQ(parse_server_state(to_string(state)), state) << to_string(state);
  EXPECT_EQ(to_string(ServerState::kSourceStalled), "source stalled");
  EXPECT_EQ(parse_server_state("paused"), std::nullopt);  // a newer server's state
}

TEST(Wire, StatusBecomesPlainValues) {
  msg::ServerStatus m = testing::status_message("source stalled", 3, 120.5f, 9);
  m.time_ns(42);
  m.fps_in(4);
  m.matched_subscribers(2);
  m.color_quality(80);
  m.frames_over_budget(3);
  const StatusReport r = from_message(m);
  EXPECT_EQ(r.time_ns, 42u);
  EXPECT_EQ(r.state, "source stalled");
  EXPECT_EQ(r.known_state, ServerState::kSourceStalled);
  EXPECT_EQ(r.fps_in, 4.0);
  EXPECT_EQ(r.fps_out, 3.0);
  ASSERT_EQ(r.stage_ms.size(), 1u);
  EXPECT_EQ(r.stage_ms[0], (std::pair<std::string, double>{"depth", 120.5}));
  EXPECT_EQ(r.dropped.at("encoder busy"), 9u);
  EXPECT_EQ(r.matched_subscribers, 2);
  ASSERT_EQ(r.cameras.size(), 1u);
  EXPECT_EQ(r.cameras[0].camera, 1);
  EXPECT_FALSE(r.cameras[0].delivering);
  EXPECT_EQ(r.cameras[0].message, "no image for 2 s");
  EXPECT_EQ(r.color_quality, 80);
  EXPECT_EQ(r.frames_over_budget, 3u);
  m.state("paused");  // a newer server's state: kept as text
  EXPECT_EQ(from_message(m).known_state, std::nullopt);
  EXPECT_EQ(from_message(m).state, "paused");
}

TEST(Wire, LatencyIsFromTheEarliestCamerasCapture) {
  const std::vector<std::uint64_t> captured = {5'000'000, 2'000'000, 9'000'000, 3'000'000};
  EXPECT_DOUBLE_EQ(latency_ms(captured, 12'000'000), 10.0);
  EXPECT_EQ(latency_ms({}, 12'000'000), 0.0);
}

TEST(Wire, GapCounterCountsLostFramesAndRestarts) {
  GapCounter gaps;
  EXPECT_EQ(gaps.see(7), 0u);  // the first frame seen: nothing before it is counted
  EXPECT_EQ(gaps.see(8), 0u);
  EXPECT_EQ(gaps.see(11), 2u);  // 9 and 10 lost
  EXPECT_EQ(gaps.see(0), 0u);   // the server restarted
  EXPECT_EQ(gaps.see(2), 1u);
  EXPECT_EQ(gaps.see(2), 0u);  // a repeat counts nothing
  EXPECT_EQ(gaps.lost(), 3u);
}

}  // namespace
}  // namespace omnisweep::wire
