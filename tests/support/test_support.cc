#include "tests/support/test_support.h"

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <thread>

extern char** environ;

namespace omnisweep::testing {
namespace fs = std::filesystem;

namespace {
fs::path from_env(const char* name, const char* fallback) {
  const char* value = std::getenv(name);
  return fs::path(value && *value ? value : fallback);
}
}  // namespace

fs::path shared_dir() { return from_env("OMNISWEEP_SHARED_DIR", OMNISWEEP_DEFAULT_SHARED_DIR); }

fs::path kaist_rig_dir() {
  fs::path dir = shared_dir() / "data" / "kaist-rig";
  if (!fs::exists(dir / "calibration.json")) {
    throw std::runtime_error(dir.string() +
                             ": the kaist-rig data is missing; the suite expects ../shared beside "
                             "the checkout (or OMNISWEEP_SHARED_DIR)");
  }
  return dir;
}

fs::path bin_dir() { return from_env("OMNISWEEP_BIN_DIR", OMNISWEEP_DEFAULT_BIN_DIR); }

fs::path mcap_node_dir() {
  return from_env("OMNISWEEP_MCAP_NODE_DIR", OMNISWEEP_DEFAULT_MCAP_NODE_DIR);
}

ScratchDir::ScratchDir(const std::string& prefix) {
  std::random_device rd;
  for (int attempt = 0; attempt < 100; ++attempt) {
    const fs::path candidate =
        fs::temp_directory_path() /
        (prefix + "-" + std::to_string(::getpid()) + "-" + std::to_string(rd()));
    if (fs::create_directory(candidate)) {
      path_ = candidate;
      return;
    }
  }
  throw std::runtime_error("cannot create a scratch folder in " +
                           fs::temp_directory_path().string());
}

ScratchDir::~ScratchDir() {
  std::error_code ec;
  fs::remove_all(path_, ec);
}

int run_command(const std::string& command, std::string* output) {
  output->clear();
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return -1;
  std::array<char, 4096> buffer{};
  std::size_t n;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0)
    output->append(buffer.data(), n);
  const int status = ::pclose(pipe);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

BackgroundProcess::BackgroundProcess(const std::string& command, const std::filesystem::path& log)
    : log_(log) {
  const std::string shell = "exec " + command + " > '" + log.string() + "' 2>&1";
  const char* argv[] = {"/bin/sh", "-c", shell.c_str(), nullptr};
  if (posix_spawn(&pid_, "/bin/sh", nullptr, nullptr, const_cast<char* const*>(argv), environ) !=
      0) {
    pid_ = -1;
    exited_ = true;
  }
}

BackgroundProcess::~BackgroundProcess() {
  if (!exited_ && pid_ > 0) {
    ::kill(pid_, SIGKILL);
    ::waitpid(pid_, &status_, 0);
  }
}

void BackgroundProcess::signal(int signal) {
  if (!exited_ && pid_ > 0) ::kill(pid_, signal);
}

bool BackgroundProcess::running() {
  if (exited_) return false;
  if (::waitpid(pid_, &status_, WNOHANG) == pid_) exited_ = true;
  return !exited_;
}

int BackgroundProcess::stop(int signal, double timeout_s, double* seconds) {
  const auto start = std::chrono::steady_clock::now();
  if (running()) ::kill(pid_, signal);
  while (!exited_) {
    if (::waitpid(pid_, &status_, WNOHANG) == pid_) {
      exited_ = true;
      break;
    }
    if (std::chrono::steady_clock::now() - start > std::chrono::duration<double>(timeout_s)) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  if (seconds)
    *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!exited_) return -1;
  return WIFEXITED(status_) ? WEXITSTATUS(status_) : -2;
}

std::string BackgroundProcess::log() const {
  std::ifstream in(log_);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

bool BackgroundProcess::wait_for_log(const std::regex& pattern, double timeout_s) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  for (;;) {
    const bool was_running = running();  // before the read, so its last lines are read too
    if (std::regex_search(log(), pattern)) return true;
    if (!was_running || std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
}

}  // namespace omnisweep::testing
