// Helpers shared by the GoogleTest suites: where the shared data lives, scratch folders.
#pragma once

#include <filesystem>
#include <regex>
#include <string>

namespace omnisweep::testing {

// ../shared beside the checkout (OMNISWEEP_SHARED_DIR, set by ctest). The suites read the
// kaist-rig frame from there and never copy it.
std::filesystem::path shared_dir();
std::filesystem::path kaist_rig_dir();
// build/bin, where the omnisweep-* programs are (OMNISWEEP_BIN_DIR, set by ctest).
std::filesystem::path bin_dir();
// Where tests/mcap is installed with npm ci (the mcap_node_setup test), for node scripts.
std::filesystem::path mcap_node_dir();

// The message of the E that `f()` throws, or "no error" when it throws nothing (anything other
// than an E propagates and fails the test).
template <typename E, typename F>
std::string error_message(F&& f) {
  try {
    f();
  } catch (const E& e) {
    return e.what();
  }
  return "no error";
}

// A fresh, empty folder removed again when the object goes away.
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& prefix = "omnisweep-test");
  ~ScratchDir();
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

// Runs a shell command, returns its exit status and fills *output with stdout+stderr.
int run_command(const std::string& command, std::string* output);

// A program running in the background (a server), its stdout+stderr going to `log`. The
// destructor kills it (SIGKILL) if it still runs, so no test leaves a process behind.
class BackgroundProcess {
 public:
  BackgroundProcess(const std::string& command, const std::filesystem::path& log);
  ~BackgroundProcess();
  BackgroundProcess(const BackgroundProcess&) = delete;
  BackgroundProcess& operator=(const BackgroundProcess&) = delete;

  bool running();
  // Sends `signal` and waits up to `timeout_s`; returns the exit code (-1: did not exit,
  // -2: killed by a signal) and the seconds it took in *seconds.
  int stop(int signal, double timeout_s, double* seconds);
  std::string log() const;
  // Waits up to `timeout_s` for the log to hold `pattern`; false at the limit or once the process
  // has ended without it.
  bool wait_for_log(const std::regex& pattern, double timeout_s);
  // Sends `signal` without waiting (SIGSTOP / SIGCONT to freeze and resume it).
  void signal(int signal);

 private:
  int pid_ = -1;
  int status_ = 0;
  bool exited_ = false;
  std::filesystem::path log_;
};

}  // namespace omnisweep::testing
