// What the GPU was asked to do, as the runtime recorded it: every dispatch with the bytes its
// bindings span, every barrier, every submit the host waited on (a host round trip) and every
// host transfer. Attach one to a Context (Context::set_command_log) and Sequence, Buffer and
// Image fill it; omnisweep-bench's cost model reads it, so the model counts the command stream
// the estimator and the stitcher really record, not a hand-typed list. Thread-safe.
#pragma once

#include <array>
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

namespace omnisweep::gpu {

struct DispatchRecord {
  std::string kernel;
  std::string stage;  // the Sequence stage open when it was recorded ("" outside stages)
  std::array<std::uint32_t, 3> groups = {0, 0, 0};
  std::uint64_t invocations = 0;  // workgroups x local size
  // Bytes of the buffers and images bound (each binding's whole range; a buffer bound twice,
  // such as written as a storage buffer and read as a texel buffer, once): what the dispatch may
  // read or write through global memory.
  std::uint64_t bound_bytes = 0;
};

struct CommandTotals {
  std::uint64_t dispatches = 0;
  std::uint64_t barriers = 0;
  std::uint64_t round_trips = 0;  // submits the host waited for, transfers included
  std::uint64_t bound_bytes = 0;
  std::uint64_t invocations = 0;
  std::uint64_t upload_bytes = 0, download_bytes = 0;
};

class CommandLog {
 public:
  // Stage under which host transfers (Buffer and Image upload / download) are counted.
  static constexpr const char* kTransferStage = "transfer";

  void add_dispatch(DispatchRecord record);
  void add_barrier(const std::string& stage);
  void add_round_trip(const std::string& stage);
  void add_transfer(std::uint64_t bytes, bool upload);
  void clear();

  std::vector<DispatchRecord> dispatches() const;
  // Stages in the order they first appear.
  std::vector<std::string> stages() const;
  // Totals of one stage, or of everything with an empty name.
  CommandTotals totals(const std::string& stage = {}) const;

 private:
  struct StageCounts {
    std::string name;
    std::uint64_t barriers = 0, round_trips = 0;
  };
  StageCounts& counts_of(const std::string& stage);  // with mutex_ held

  mutable std::mutex mutex_;
  std::vector<DispatchRecord> dispatches_;
  std::vector<StageCounts> stages_;
  std::uint64_t upload_bytes_ = 0, download_bytes_ = 0;
};

}  // namespace omnisweep::gpu
