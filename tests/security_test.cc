// DDS Security end to end (ctest label: security): credentials made by
// deploy/security/make-credentials.sh, a server that requires them, and clients with the right
// identity, none, one from another CA, and one permitted only the status topic.
#include <gtest/gtest.h>

#include "tests/support/stream_fixture.h"

namespace omnisweep {
namespace {

namespace fs = std::filesystem;
using testing::BackgroundProcess;
using testing::run_command;

class SecurityTest : public testing::StreamTest {
 protected:
  void SetUp() override {
    StreamTest::SetUp();
    const std::string script =
        std::string(OMNISWEEP_SOURCE_DIR) + "/deploy/security/make-credentials.sh";
    std::string out;
    ASSERT_EQ(run_command(script + " " + (dir_.path() / "creds").string(), &out), 0) << out;
    ASSERT_EQ(
        run_command(script + " " + (dir_.path() / "other").string() + " intruder:viewer", &out), 0)
        << out;
  }
  std::string subscribe(const std::string& identity, const std::string& extra) const {
    return tool_command("subscribe", (identity.empty() ? "" : " --security " + identity) + extra);
  }
  fs::path creds(const std::string& name) const { return dir_.path() / "creds" / name; }
};

TEST_F(SecurityTest, OnlyAuthorisedClientsReadTheStream) {
  BackgroundProcess server(server_command(" --security " + creds("server").string()),
                           dir_.path() / "server.log");
  std::string out;
  // The viewer identity: frames, the calibration and status arrive (encrypted on the wire).
  ASSERT_EQ(
      run_command(subscribe(creds("viewer").string(), " --frames 3 --description --timeout 60"),
                  &out),
      0)
      << out << server.log();
  EXPECT_NE(out.find("summary: 3 frames decoded"), std::string::npos) << out;

  // No security, or a certificate from another CA: authentication fails, nothing arrives.
  for (const std::string& identity : {std::string(), (dir_.path() / "other/intruder").string()}) {
    EXPECT_EQ(run_command(subscribe(identity, " --frames 1 --timeout 5"), &out), 1) << out;
    EXPECT_NE(out.find("summary: 0 frames decoded"), std::string::npos) << identity << ": " << out;
    EXPECT_NE(out.find("calibration missing"), std::string::npos) << identity << ": " << out;
  }

  // Permitted only the status topic: status arrives, a frame reader is refused.
  EXPECT_EQ(
      run_command(subscribe(creds("status").string(), " --status-only --statuses 2 --timeout 30"),
                  &out),
      0)
      << out;
  EXPECT_NE(run_command(subscribe(creds("status").string(), " --frames 1 --timeout 5"), &out), 0)
      << out;
  EXPECT_NE(out.find("do not allow subscribing"), std::string::npos) << out;
  EXPECT_EQ(out.find("frames decoded"), std::string::npos) << out;
}

TEST_F(SecurityTest, BadCredentialsAreRefusedClearly) {
  std::string out;
  EXPECT_NE(run_command(server_command(" --security " + (dir_.path() / "missing").string()), &out),
            0);
  EXPECT_NE(out.find("has no identity_ca.pem"), std::string::npos) << out;
  // A server with a viewer identity may not publish: it says so and exits.
  EXPECT_NE(run_command(server_command(" --frames 1 --security " + creds("viewer").string()), &out),
            0);
  EXPECT_NE(out.find("do not allow publishing"), std::string::npos) << out;
}

}  // namespace
}  // namespace omnisweep
