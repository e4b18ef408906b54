// A fixture for tests that run omnisweep-server and clients as separate processes on loopback:
// a small synthetic dataset (3 frames of 160x160 fisheyes) to serve, and a DDS domain and topic
// prefix of this process and test's own, so suites running side by side never see each other.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "omnisweep/dds/participant.h"
#include "tests/support/test_support.h"

namespace omnisweep::testing {

class StreamTest : public ::testing::Test {
 protected:
  void SetUp() override;

  // omnisweep-server on the dataset at test settings (128^2 matching, 256x128 panoramas, `fps`
  // frames per second, 5 unless a test needs capture faster than depth).
  std::string server_command(const std::string& extra = "", double fps = 5) const;
  // build/bin/omnisweep-<tool> with this test's domain and topic prefix, then `extra`.
  std::string tool_command(const std::string& tool, const std::string& extra) const;
  // The same domain and prefix for an in-process participant.
  dds::ParticipantOptions participant_options() const;

  ScratchDir dir_;
  int domain_ = 0;
  std::string topic_prefix_;
};

}  // namespace omnisweep::testing
