// omnisweep-process as a user runs it: on a small synthetic dataset with ground truth, with
// --evaluate --json, with --temporal on a static rig with sensor noise, and on bad input.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <regex>
#include <sstream>

#include "server/synthetic/synthetic_dataset.h"
#include "tests/support/test_support.h"

namespace omnisweep {
namespace {

namespace fs = std::filesystem;
using testing::run_command;
using testing::ScratchDir;

const std::string kSmall =
    " --matching-resolution 128 128 --panorama-resolution 256 128 --candidates 16";

void write_small_dataset(const fs::path& dir, bool with_ground_truth) {
  synthetic::SyntheticRigOptions options;
  options.image_size = 160;
  const synthetic::SyntheticRig rig(options);
  synthetic::write_synthetic_dataset(
      rig, dir, {.first_frame = 0, .num_frames = 2, .panorama_width = 256, .panorama_height = 128});
  if (!with_ground_truth) fs::remove_all(dir / "gt");
}

// The summary line's value of `key` (a number) in omnisweep-process --json's output.
double summary_value(const std::string& out, const std::string& key) {
  std::smatch m;
  const std::regex pattern("\\{[^\\n]*\"summary\": true[^\\n]*\"" + key + "\": ([0-9.]+)");
  if (!std::regex_search(out, m, pattern)) return -1;
  return std::stod(m[1]);
}

TEST(ProcessCli, WritesPanoramasAndEvaluatesAsJson) {
  ScratchDir dir;
  write_small_dataset(dir.path() / "data", true);
  std::string out;
  const std::string cmd = (testing::bin_dir() / "omnisweep-process").string() + " --dataset " +
                          (dir.path() / "data").string() + " --output " +
                          (dir.path() / "out").string() + " --evaluate --json" + kSmall;
  ASSERT_EQ(run_command(cmd, &out), 0) << out;
  std::istringstream lines(out);
  std::string line;
  int frames = 0;
  bool summary = false;
  for (const char* name : {"0", "1"}) {
    EXPECT_TRUE(fs::exists(dir.path() / "out" / (std::string("rgb_") + name + ".png")));
    EXPECT_TRUE(fs::exists(dir.path() / "out" / (std::string("inv_distance_") + name + ".exr")));
    EXPECT_TRUE(fs::exists(dir.path() / "out" / (std::string("inv_distance_") + name + ".png")));
  }
  while (std::getline(lines, line)) {
    if (line.empty() || line[0] != '{') continue;  // progress and device lines (stderr)
    for (const char* key :
         {"\"mae\"", "\"rmse\"", "\"bad_0_1\"", "\"bad_0_4\"", "\"psnr\"", "\"ssim\"", "\"ms\""}) {
      EXPECT_NE(line.find(key), std::string::npos) << key << " missing in " << line;
    }
    if (line.find("\"summary\": true") != std::string::npos) {
      summary = true;
      EXPECT_NE(line.find("\"frames\": 2"), std::string::npos) << line;
    } else {
      ++frames;
      std::smatch m;
      ASSERT_TRUE(std::regex_search(line, m, std::regex("\"mae\": ([0-9.]+)"))) << line;
      EXPECT_LT(std::stod(m[1]), 0.2) << line;  // a 128 px, 16-candidate run is coarse but sane
    }
  }
  EXPECT_EQ(frames, 2);
  EXPECT_TRUE(summary);
}

// The default method's stream through the stitcher's temporal filter: a static rig whose sensor
// noise changes every frame flickers at least 2x less with --temporal, and no less accurately.
TEST(ProcessCli, TemporalFilterStillsAStaticNoisyRig) {
  ScratchDir dir;
  synthetic::SyntheticRigOptions options;
  options.image_size = 160;
  options.static_rig = true;
  options.photometric.noise_sigma = 3;
  synthetic::write_synthetic_dataset(
      synthetic::SyntheticRig(options), dir.path() / "data",
      {.first_frame = 0, .num_frames = 5, .panorama_width = 256, .panorama_height = 128});
  double flicker[2], mae[2];
  for (const bool temporal : {false, true}) {
    std::string out;
    const fs::path output = dir.path() / (temporal ? "temporal" : "plain");
    ASSERT_EQ(run_command((testing::bin_dir() / "omnisweep-process").string() + " --dataset " +
                              (dir.path() / "data").string() + " --output " + output.string() +
                              " --evaluate --json" + kSmall + (temporal ? " --temporal" : ""),
                          &out),
              0)
        << out;
    flicker[temporal] = summary_value(out, "flicker");
    mae[temporal] = summary_value(out, "mae");
    ASSERT_GT(flicker[temporal], 0) << out;
    ASSERT_GT(mae[temporal], 0) << out;
  }
  std::cout << "flicker " << flicker[0] << " -> " << flicker[1] << " with --temporal, MAE "
            << mae[0] << " -> " << mae[1] << "\n";
  EXPECT_LT(flicker[1], 0.5 * flicker[0]);
  EXPECT_LE(mae[1], mae[0] * 1.02);
}

TEST(ProcessCli, BadInputGetsAClearError) {
  ScratchDir dir;
  const std::string tool = (testing::bin_dir() / "omnisweep-process").string();
  std::string out;
  EXPECT_NE(run_command(tool + " --dataset " + (dir.path() / "missing").string() + " --output " +
                            dir.path().string(),
                        &out),
            0);
  EXPECT_NE(out.find("missing: dataset folder does not exist"), std::string::npos) << out;

  write_small_dataset(dir.path() / "data", false);
  EXPECT_NE(run_command(tool + " --dataset " + (dir.path() / "data").string() + " --output " +
                            (dir.path() / "out").string() + " --evaluate" + kSmall,
                        &out),
            0);
  EXPECT_NE(out.find("--evaluate needs ground truth"), std::string::npos) << out;

  EXPECT_NE(run_command(tool + " --dataset " + (dir.path() / "data").string() + " --output " +
                            (dir.path() / "out").string() + " --references 2 7" + kSmall,
                        &out),
            0);
  EXPECT_NE(out.find("camera 7 does not exist"), std::string::npos) << out;

  EXPECT_NE(run_command(tool + " --dataset " + (dir.path() / "data").string() + " --output " +
                            (dir.path() / "out").string() + " --panorama-resolution 300 100" +
                            kSmall.substr(0, 30),
                        &out),
            0);
  EXPECT_NE(out.find("width must be twice the height"), std::string::npos) << out;

  EXPECT_NE(run_command(tool + " --dataset " + (dir.path() / "data").string() + " --output " +
                            (dir.path() / "out").string() + " --method best" + kSmall,
                        &out),
            0);
  EXPECT_NE(out.find("unknown method 'best' (one of paper, recommended, accurate)"),
            std::string::npos)
      << out;

  // A frame with a broken image is skipped, named, and the run fails; the other frame is written.
  std::ofstream(dir.path() / "data" / "cam1" / "1.png", std::ios::trunc) << "broken";
  EXPECT_NE(run_command(tool + " --dataset " + (dir.path() / "data").string() + " --output " +
                            (dir.path() / "out2").string() + kSmall,
                        &out),
            0);
  EXPECT_NE(out.find("skipped frame 1"), std::string::npos) << out;
  EXPECT_NE(out.find("cam1/1.png"), std::string::npos) << out;
  EXPECT_TRUE(fs::exists(dir.path() / "out2" / "rgb_0.png"));
}

}  // namespace
}  // namespace omnisweep
