// What receivers measure about a stream's frames, defined once for the SDK, the tools and the
// bench: latency and frames lost. No DDS types, so apps may include it.
#pragma once

#include <cstdint>
#include <optional>
#include <span>

namespace omnisweep::wire {

// A frame's end-to-end latency, the one definition (docs/wire-format.md): from the capture of its
// earliest camera image (the oldest data it shows) to `now_ns` (when the receiver has decoded
// it), both on the wall clock, in milliseconds; 0 for a frame without capture times.
double latency_ms(std::span<const std::uint64_t> capture_time_ns, std::uint64_t now_ns);

// Frames lost, from the sequence numbers of the frames received (consecutive per server run).
// A number more than one past the previous counts the gap as lost; a lower or equal one (the
// server restarted) counts nothing and becomes the new start.
class GapCounter {
 public:
  // Takes the next received frame's number; returns the frames lost just before it.
  std::uint64_t see(std::uint64_t sequence_number);
  std::uint64_t lost() const { return lost_; }

 private:
  std::optional<std::uint64_t> last_;
  std::uint64_t lost_ = 0;
};

}  // namespace omnisweep::wire
