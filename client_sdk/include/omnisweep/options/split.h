// Splitting a flag's list ("a,b,c", a gst source's "PIPE|PIPE"): the one splitter the programs
// and the capture sources share. Header-only, like option_error.h.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace omnisweep {

enum class EmptyItems { kKeep, kDrop };

// The items of `text` between `separator`s. kKeep keeps empty items ("a,,b" gives three, so a
// caller can refuse them); kDrop leaves them out ("a,,b" gives two, "" gives none).
inline std::vector<std::string> split(std::string_view text, char separator,
                                      EmptyItems empty = EmptyItems::kKeep) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (true) {
    const std::size_t end = text.find(separator, start);
    const std::string_view item = text.substr(start, end - start);
    if (!item.empty() || empty == EmptyItems::kKeep) out.emplace_back(item);
    if (end == std::string_view::npos) break;
    start = end + 1;
  }
  return out;
}

}  // namespace omnisweep
