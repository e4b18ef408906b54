#include "omnisweep/wire/frame_stats.h"

#include <algorithm>

namespace omnisweep::wire {

double latency_ms(std::span<const std::uint64_t> capture_time_ns, std::uint64_t now_ns) {
  if (capture_time_ns.empty()) return 0;
  const std::uint64_t earliest = *std::min_element(capture_time_ns.begin(), capture_time_ns.end());
  return (double(now_ns) - double(earliest)) * 1e-6;
}

std::uint64_t GapCounter::see(std::uint64_t sequence_number) {
  std::uint64_t gap = 0;
  if (last_ && sequence_number > *last_ + 1) gap = sequence_number - *last_ - 1;
  last_ = sequence_number;
  lost_ += gap;
  return gap;
}

}  // namespace omnisweep::wire
