#include "omnisweep/gpu/command_log.h"

#include <algorithm>

namespace omnisweep::gpu {

CommandLog::StageCounts& CommandLog::counts_of(const std::string& stage) {
  auto it = std::find_if(stages_.begin(), stages_.end(),
                         [&](const StageCounts& s) { return s.name == stage; });
  if (it != stages_.end()) return *it;
  stages_.push_back({.name = stage});
  return stages_.back();
}

void CommandLog::add_dispatch(DispatchRecord record) {
  const std::lock_guard lock(mutex_);
  counts_of(record.stage);
  dispatches_.push_back(std::move(record));
}

void CommandLog::add_barrier(const std::string& stage) {
  const std::lock_guard lock(mutex_);
  ++counts_of(stage).barriers;
}

void CommandLog::add_round_trip(const std::string& stage) {
  const std::lock_guard lock(mutex_);
  ++counts_of(stage).round_trips;
}

void CommandLog::add_transfer(std::uint64_t bytes, bool upload) {
  const std::lock_guard lock(mutex_);
  counts_of(kTransferStage);
  (upload ? upload_bytes_ : download_bytes_) += bytes;
}

void CommandLog::clear() {
  const std::lock_guard lock(mutex_);
  dispatches_.clear();
  stages_.clear();
  upload_bytes_ = download_bytes_ = 0;
}

std::vector<DispatchRecord> CommandLog::dispatches() const {
  const std::lock_guard lock(mutex_);
  return dispatches_;
}

std::vector<std::string> CommandLog::stages() const {
  const std::lock_guard lock(mutex_);
  std::vector<std::string> out;
  for (const auto& s : stages_) out.push_back(s.name);
  return out;
}

CommandTotals CommandLog::totals(const std::string& stage) const {
  const std::lock_guard lock(mutex_);
  CommandTotals t;
  for (const auto& d : dispatches_) {
    if (!stage.empty() && d.stage != stage) continue;
    ++t.dispatches;
    t.bound_bytes += d.bound_bytes;
    t.invocations += d.invocations;
  }
  for (const auto& s : stages_) {
    if (!stage.empty() && s.name != stage) continue;
    t.barriers += s.barriers;
    t.round_trips += s.round_trips;
  }
  if (stage.empty() || stage == kTransferStage) {
    t.upload_bytes = upload_bytes_;
    t.download_bytes = download_bytes_;
  }
  return t;
}

}  // namespace omnisweep::gpu
