// Parses JSON into nlohmann::json while tracking where in the document the parser is, so that
// syntax errors and number overflows (1e999, NaN) are reported with the field they occur in,
// e.g. "value0.intrinsics[2].intrinsics.fx". nlohmann's own DOM parser reports only offsets.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace omnisweep::json_detail {

struct ParseFailure {
  std::string path;     // JSON path of the value being read, "" at the top level
  int line = 0;         // 1-based
  int column = 0;       // 1-based
  std::string message;  // the parser's reason, without nlohmann's "[json.exception...]" prefix
};

// Returns false and fills *failure when the text is not valid JSON with finite numbers.
bool parse_with_path(std::string_view text, nlohmann::json* out, ParseFailure* failure);

// "a.b[3].c" style path helpers used by readers to name fields in messages.
std::string join_path(const std::string& parent, const std::string& key);
std::string index_path(const std::string& parent, std::size_t index);

}  // namespace omnisweep::json_detail
