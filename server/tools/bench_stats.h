// What the omnisweep-bench sections share to summarise repeated measurements.
#pragma once

#include <algorithm>
#include <vector>

namespace omnisweep::tools {

// The median of the values (the upper one of the middle two for an even count); 0 for none.
inline double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  const auto mid = values.begin() + std::ptrdiff_t(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

}  // namespace omnisweep::tools
