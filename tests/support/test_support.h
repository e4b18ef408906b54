// Helpers shared by the GoogleTest suites: where the shared data lives, scratch folders.
#pragma once

#include <filesystem>
#include <string>

namespace omnisweep::testing {

// ../shared beside the checkout (OMNISWEEP_SHARED_DIR, set by ctest). The suites read the
// kaist-rig frame from there and never copy it.
std::filesystem::path shared_dir();
std::filesystem::path kaist_rig_dir();
// build/bin, where the omnisweep-* programs are (OMNISWEEP_BIN_DIR, set by ctest).
std::filesystem::path bin_dir();

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

}  // namespace omnisweep::testing
