#include "tests/support/stream_fixture.h"

#include <unistd.h>

#include "server/synthetic/synthetic_dataset.h"

namespace omnisweep::testing {

namespace {

const char* const kSmall =
    " --matching-resolution 128 128 --panorama-resolution 256 128 --candidates 16"
    " --log-interval 0";

}  // namespace

void StreamTest::SetUp() {
  synthetic::SyntheticRigOptions options;
  options.image_size = 160;
  const synthetic::SyntheticRig rig(options);
  synthetic::write_synthetic_dataset(
      rig, dir_.path() / "data",
      {.first_frame = 0, .num_frames = 3, .panorama_width = 64, .panorama_height = 32});
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  domain_ = 1 + getpid() % 200;
  topic_prefix_ = "test" + std::to_string(getpid()) + "/" + info->name();
}

std::string StreamTest::server_command(const std::string& extra, double fps) const {
  return tool_command("server", " --source dataset:" + (dir_.path() / "data").string() + kSmall +
                                    " --fps " + std::to_string(fps) + extra);
}

std::string StreamTest::tool_command(const std::string& tool, const std::string& extra) const {
  return (bin_dir() / ("omnisweep-" + tool)).string() + " --domain " + std::to_string(domain_) +
         " --topic-prefix " + topic_prefix_ + extra;
}

dds::ParticipantOptions StreamTest::participant_options() const {
  dds::ParticipantOptions options;
  options.domain = domain_;
  options.topic_prefix = topic_prefix_;
  options.name = "omnisweep-test";
  return options;
}

}  // namespace omnisweep::testing
