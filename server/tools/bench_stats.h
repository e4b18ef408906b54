// What the omnisweep-bench sections share to summarise repeated measurements.
#pragma once

#include <time.h>

#include <algorithm>
#include <chrono>
#include <vector>

namespace omnisweep::tools {

// The median of the values (the upper one of the middle two for an even count); 0 for none.
inline double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  const auto mid = values.begin() + std::ptrdiff_t(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

// Wall and CPU time of one call. CPU time is the whole process's (every thread's), so work
// spread over threads is charged for all of it.
struct Cost {
  double wall_ms = 0, cpu_ms = 0;
};
inline double process_cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}
template <typename F>
Cost cost_of(F&& f) {
  const auto start = std::chrono::steady_clock::now();
  const double cpu = process_cpu_ms();
  f();
  return {
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count(),
      process_cpu_ms() - cpu};
}
// Median wall time and median CPU time (each over all the runs).
inline Cost median(const std::vector<Cost>& costs) {
  std::vector<double> wall, cpu;
  for (const Cost& c : costs) {
    wall.push_back(c.wall_ms);
    cpu.push_back(c.cpu_ms);
  }
  return {median(wall), median(cpu)};
}

}  // namespace omnisweep::tools
