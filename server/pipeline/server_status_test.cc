// The server's status on its own: stage means per window carried over empty windows, frames in
// and out, drops, the state's transitions, camera fps, and the log line.
#include "server/pipeline/server_status.h"

#include <gtest/gtest.h>

namespace omnisweep::pipeline {
namespace {

std::vector<capture::CameraStatus> cameras(std::uint64_t frames) {
  return {{.delivering = true, .frames = frames, .last_frame_ns = 5, .message = ""},
          {.delivering = false, .frames = 0, .last_frame_ns = 0, .message = "silent"}};
}

float stage_ms(const msg::ServerStatus& s, const std::string& stage) {
  for (const auto& t : s.stage_ms())
    if (t.stage() == stage) return t.ms();
  ADD_FAILURE() << "no stage " << stage;
  return -1;
}

TEST(StatusBoard, StageMeansPerWindowCarryOverEmptyWindows) {
  StatusBoard board({"capture", "depth"});
  board.add_stage_time("depth", 10);
  board.add_stage_time("depth", 30);
  msg::ServerStatus s = board.take(1, {});
  ASSERT_EQ(s.stage_ms().size(), 2u);
  EXPECT_EQ(s.stage_ms()[0].stage(), "capture");
  EXPECT_EQ(stage_ms(s, "capture"), 0.0f);  // never ran
  EXPECT_EQ(stage_ms(s, "depth"), 20.0f);
  s = board.take(2, {});  // no frame this window: the latest mean
  EXPECT_EQ(stage_ms(s, "depth"), 20.0f);
  board.add_stage_time("depth", 50);
  EXPECT_EQ(stage_ms(board.take(3, {}), "depth"), 50.0f);
}

TEST(StatusBoard, CountsFramesDropsAndCameraFpsPerWindow) {
  StatusBoard board({"capture"});
  board.set_cameras(cameras(0));
  for (int i = 0; i < 3; ++i) board.count_captured(cameras(std::uint64_t(i) + 1));
  board.count_published();
  board.count_drop("encoder busy");
  board.count_drop("encoder busy");
  board.count_drop("network busy");
  msg::ServerStatus s =
      board.take(7, {.matched_subscribers = 2, .color_quality = 85, .frames_over_budget = 1});
  EXPECT_EQ(s.time_ns(), 7u);
  EXPECT_EQ(s.fps_in(), 3.0f);
  EXPECT_EQ(s.fps_out(), 1.0f);
  EXPECT_EQ(s.matched_subscribers(), 2);
  EXPECT_EQ(s.color_quality(), 85);
  EXPECT_EQ(s.frames_over_budget(), 1u);
  ASSERT_EQ(s.dropped().size(), 2u);
  EXPECT_EQ(s.dropped()[0].reason(), "encoder busy");
  EXPECT_EQ(s.dropped()[0].count(), 2u);
  ASSERT_EQ(s.cameras().size(), 2u);
  EXPECT_TRUE(s.cameras()[0].delivering());
  EXPECT_EQ(s.cameras()[0].fps(), 0.0f);  // the first window has no count to start from
  EXPECT_EQ(s.cameras()[1].message(), "silent");
  for (int i = 3; i < 8; ++i) board.count_captured(cameras(std::uint64_t(i) + 1));
  s = board.take(8, {});
  EXPECT_EQ(s.fps_in(), 5.0f);
  EXPECT_EQ(s.fps_out(), 0.0f);
  EXPECT_EQ(s.cameras()[0].fps(), 5.0f);
  EXPECT_EQ(s.dropped()[0].count(), 2u);  // drops are totals, not per window
}

TEST(StatusBoard, StateFollowsTheSourceAndThePublisher) {
  StatusBoard board({"capture"});
  EXPECT_EQ(board.state(), wire::ServerState::kStarting);
  board.source_stalled(cameras(0));
  EXPECT_EQ(board.state(), wire::ServerState::kSourceStalled);
  board.count_captured(cameras(1));  // delivering again, nothing published yet
  EXPECT_EQ(board.state(), wire::ServerState::kStarting);
  board.count_published();
  EXPECT_EQ(board.state(), wire::ServerState::kRunning);
  board.source_stalled(cameras(1));
  board.count_captured(cameras(2));
  EXPECT_EQ(board.state(), wire::ServerState::kRunning);
  EXPECT_EQ(board.take(1, {.stopping = true}).state(), "stopping");
  board.source_ended();
  EXPECT_EQ(board.take(2, {}).state(), "source ended");
  board.fail("depth: out of memory");
  board.fail("encode: later");  // the first error wins
  EXPECT_EQ(board.state(), wire::ServerState::kFailed);
  EXPECT_EQ(board.error(), "depth: out of memory");
  board.source_stalled(cameras(2));
  EXPECT_EQ(board.state(), wire::ServerState::kFailed);
}

TEST(StatusBoard, LogLineSaysWhatTheStatusSays) {
  StatusBoard board({"capture", "depth"});
  board.add_stage_time("depth", 12.4);
  board.count_drop("depth busy");
  board.count_published();
  const msg::ServerStatus s = board.take(1, {.matched_subscribers = 1, .color_quality = 90});
  EXPECT_EQ(status_log_line(s, 42, ", Foxglove: 0 clients"),
            "running, 0 fps in, 1 fps out, ms: capture 0 depth 12, 1 dropped, 1 subscribers, 42 "
            "published, colour quality 90, Foxglove: 0 clients");
}

}  // namespace
}  // namespace omnisweep::pipeline
