#include "tests/support/test_support.h"

#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>

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
  const fs::path dir = shared_dir() / "data" / "kaist-rig";
  if (!fs::exists(dir / "calibration.json")) {
    throw std::runtime_error(dir.string() +
                             ": the kaist-rig data is missing; the suite expects ../shared beside "
                             "the checkout (or OMNISWEEP_SHARED_DIR)");
  }
  return dir;
}

fs::path bin_dir() { return from_env("OMNISWEEP_BIN_DIR", OMNISWEEP_DEFAULT_BIN_DIR); }

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

}  // namespace omnisweep::testing
