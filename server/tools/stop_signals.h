// SIGINT / SIGTERM for a long-running tool: blocked in every thread and taken by one watcher
// thread, so a stop request is seen at any moment, start-up included (while the GPU pipelines
// are built), not only once the main loop waits for it. A second signal exits at once.
#pragma once

#include <memory>
#include <string>

namespace omnisweep::tools {

class StopSignals {
 public:
  // Blocks SIGINT and SIGTERM in the calling thread (and so in every thread it starts later) and
  // starts the watcher. Construct it first in main, before any library starts a thread. `tool`
  // names the program in its messages.
  explicit StopSignals(std::string tool);
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

  // The first signal received (SIGINT or SIGTERM), 0 while none has come.
  int received() const;
  // Waits up to `seconds` for a signal; returns received().
  int wait_for(double seconds);
  // The start-up is over (the stages run): from now on a first signal is not announced as one
  // that waits for the start-up.
  void started();

 private:
  struct State;  // shared with the watcher, which outlives this object (it is never joined)
  static void watch(State& state);
  std::shared_ptr<State> state_;
};

}  // namespace omnisweep::tools
