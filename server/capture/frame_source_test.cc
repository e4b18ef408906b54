// The capture sources on their own, without the server: a dataset source loops its frames at the
// calibration's size, a synthetic source renders its poses, video files that do not open and bad
// specs are errors naming what is wrong, and the options check themselves.
#include "server/capture/frame_source.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "omnisweep/dataset/dataset.h"
#include "omnisweep/options/split.h"
#include "server/synthetic/synthetic_dataset.h"
#include "tests/support/test_support.h"

namespace omnisweep::capture {
namespace {

std::string error_of(const std::string& spec, const SourceOptions& options = {}) {
  return omnisweep::testing::error_message<std::exception>([&] { open_source(spec, options); });
}

TEST(SourceOptions, BadOptionsAreNamed) {
  SourceOptions options;
  options.synthetic_poses = 0;
  EXPECT_EQ(omnisweep::testing::error_message<std::invalid_argument>([&] { options.check(); }),
            "SourceOptions.synthetic_poses = 0: must be within [1, 100000]");
  options = {};
  options.camera_timeout_s = -1;
  EXPECT_NE(error_of("synthetic", options).find("SourceOptions.camera_timeout_s = -1"),
            std::string::npos);
}

TEST(FrameSource, BadSpecsAreNamed) {
  EXPECT_NE(error_of("webcam").find("unknown source \"webcam\""), std::string::npos)
      << error_of("webcam");
  EXPECT_NE(error_of("video:a.mp4,,b.mp4").find("camera 1 is empty"), std::string::npos)
      << error_of("video:a.mp4,,b.mp4");
  EXPECT_NE(error_of("dataset:/nonexistent/omnisweep").find("/nonexistent/omnisweep"),
            std::string::npos)
      << error_of("dataset:/nonexistent/omnisweep");
  // Video needs a calibration, and a file that opens.
  EXPECT_NE(error_of("video:/nonexistent.mp4").find("calibration"), std::string::npos)
      << error_of("video:/nonexistent.mp4");
}

TEST(FrameSource, SpecsParseToTheirKind) {
  EXPECT_EQ(parse_source_spec("synthetic").kind, SourceKind::kSynthetic);
  const SourceSpec dataset = parse_source_spec("dataset:/data/hall");
  EXPECT_EQ(dataset.kind, SourceKind::kDataset);
  EXPECT_EQ(dataset.location, "/data/hall");
  const SourceSpec video = parse_source_spec("video:a.mp4,b.mp4");
  EXPECT_EQ(video.kind, SourceKind::kVideo);
  EXPECT_EQ(video.cameras, (std::vector<std::string>{"a.mp4", "b.mp4"}));
  EXPECT_EQ(parse_source_spec("v4l2:/dev/video0").kind, SourceKind::kV4l2);
  // GStreamer pipelines hold commas, so they are split at '|'.
  const SourceSpec gst = parse_source_spec("gst:videotestsrc ! video/x-raw,width=64 ! appsink|x");
  EXPECT_EQ(gst.kind, SourceKind::kGst);
  EXPECT_EQ(gst.cameras.size(), 2u);
  // Every kind's name is the prefix that parses back to it.
  for (const SourceKind kind :
       {SourceKind::kDataset, SourceKind::kVideo, SourceKind::kV4l2, SourceKind::kGst})
    EXPECT_EQ(parse_source_spec(std::string(to_string(kind)) + ":x").kind, kind);
  EXPECT_EQ(to_string(SourceKind::kV4l2), "v4l2");
  EXPECT_THROW(parse_source_spec("dataset:"), SourceError);
  EXPECT_THROW(parse_source_spec("synthetic:x"), SourceError);
}

TEST(FrameSource, DatasetSourceLoopsItsFramesAtTheCalibrationsSize) {
  const omnisweep::testing::ScratchDir dir;
  synthetic::SyntheticRigOptions rig_options;
  rig_options.image_size = 48;
  const synthetic::SyntheticRig rig(rig_options);
  synthetic::write_synthetic_dataset(
      rig, dir.path(),
      {.first_frame = 0, .num_frames = 2, .panorama_width = 32, .panorama_height = 16});
  const auto source = open_source("dataset:" + dir.path().string(), {});
  EXPECT_FALSE(source->live());
  ASSERT_EQ(source->rig().num_cameras(), 4);
  EXPECT_EQ(source->masks().size(), 4u);
  ASSERT_NE(source->hints(), nullptr);  // synth writes dataset.json
  std::vector<Rgb8Image> first_camera;
  for (int i = 0; i < 5; ++i) {  // 2 frames, looped
    const auto frame = source->next();
    ASSERT_TRUE(frame) << "a dataset source loops; it never ends";
    ASSERT_EQ(frame->images.size(), 4u);
    ASSERT_EQ(frame->capture_time_ns.size(), 4u);
    EXPECT_EQ(frame->images[0].width(), 48);
    EXPECT_EQ(frame->images[0].height(), 48);
    first_camera.push_back(frame->images[0].clone());
  }
  auto same = [](const Rgb8Image& a, const Rgb8Image& b) {
    return std::equal(a.pixels().begin(), a.pixels().end(), b.pixels().begin());
  };
  EXPECT_TRUE(same(first_camera[0], first_camera[2]));  // frame 0 again after frame 1
  EXPECT_TRUE(same(first_camera[1], first_camera[3]));
  for (const CameraStatus& s : source->camera_status()) {
    EXPECT_TRUE(s.delivering);
    EXPECT_EQ(s.frames, 5u);
  }
}

TEST(FrameSource, SyntheticSourceRendersItsPoses) {
  SourceOptions options;
  options.synthetic_poses = 2;
  const auto source = open_source("synthetic", options);
  EXPECT_EQ(source->rig().num_cameras(), 4);
  const auto frame = source->next();
  ASSERT_TRUE(frame);
  EXPECT_EQ(int(frame->images.size()), source->rig().num_cameras());
  EXPECT_EQ(frame->images[0].width(), source->rig().cameras[0].width);
}

// The one splitter of lists in flags and source specs.
TEST(Split, KeepsOrDropsEmptyItems) {
  EXPECT_EQ(split("a,,b", ','), (std::vector<std::string>{"a", "", "b"}));
  EXPECT_EQ(split("a,,b", ',', EmptyItems::kDrop), (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(split("", ','), (std::vector<std::string>{""}));
  EXPECT_TRUE(split("", ',', EmptyItems::kDrop).empty());
  EXPECT_EQ(split("x|y", '|'), (std::vector<std::string>{"x", "y"}));
}

}  // namespace
}  // namespace omnisweep::capture
