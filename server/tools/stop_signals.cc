#include "server/tools/stop_signals.h"

#include <pthread.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <thread>

namespace omnisweep::tools {

struct StopSignals::State {
  std::string tool;
  sigset_t set;
  std::atomic<int> received{0};
  std::atomic<bool> started{false};
  std::mutex mutex;
  std::condition_variable signalled;
};

StopSignals::StopSignals(std::string tool) : state_(std::make_shared<State>()) {
  state_->tool = std::move(tool);
  sigemptyset(&state_->set);
  sigaddset(&state_->set, SIGINT);
  sigaddset(&state_->set, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &state_->set, nullptr);
  // Detached: it waits in sigwait for as long as the process lives, with its own share of the
  // state.
  std::thread([state = state_] { watch(*state); }).detach();
}

int StopSignals::received() const { return state_->received.load(); }

void StopSignals::started() { state_->started = true; }

int StopSignals::wait_for(double seconds) {
  std::unique_lock lock(state_->mutex);
  state_->signalled.wait_for(lock, std::chrono::duration<double>(seconds),
                             [&] { return state_->received.load() != 0; });
  return state_->received.load();
}

void StopSignals::watch(State& s) {
  for (;;) {
    int signal = 0;
    if (sigwait(&s.set, &signal) != 0) continue;
    int none = 0;
    if (!s.received.compare_exchange_strong(none, signal)) {
      // The second: the user will not wait for the first stop (a start-up building GPU
      // pipelines, a stage inside a long GPU submission).
      std::fprintf(stderr, "%s: %s again, exiting now\n", s.tool.c_str(), strsignal(signal));
      std::fflush(stderr);
      std::_Exit(128 + signal);
    }
    if (!s.started) {
      std::fprintf(stderr,
                   "%s: %s during start-up; stopping once the GPU pipelines are built (send it "
                   "again to exit at once)\n",
                   s.tool.c_str(), strsignal(signal));
    }
    std::lock_guard lock(s.mutex);
    s.signalled.notify_all();
  }
}

}  // namespace omnisweep::tools
