// The clock of every timestamp on the wire: nanoseconds since the Unix epoch (CLOCK_REALTIME),
// so capture times from the server and receive times at a client compare directly when both
// machines are synchronised (PTP or NTP).
#pragma once

#include <chrono>
#include <cstdint>

namespace omnisweep {

inline std::uint64_t wall_clock_ns() {
  return std::uint64_t(std::chrono::duration_cast<std::chrono::nanoseconds>(
                           std::chrono::system_clock::now().time_since_epoch())
                           .count());
}

}  // namespace omnisweep
