// The error an options struct's check() throws (COLMAP's Check()): "<owner>.<field> = <value>:
// must be <allowed>", the value in its shortest form ("0.5", not "0.500000"). Header-only, so
// every module's options use it without a dependency.
#pragma once

#include <charconv>
#include <stdexcept>
#include <string>
#include <string_view>

namespace omnisweep {

inline std::invalid_argument option_error(std::string_view owner, std::string_view field,
                                          double value, std::string_view allowed) {
  char text[32];
  const char* end = std::to_chars(text, text + sizeof(text), value).ptr;
  return std::invalid_argument(std::string(owner) + "." + std::string(field) + " = " +
                               std::string(text, std::size_t(end - text)) + ": must be " +
                               std::string(allowed));
}

}  // namespace omnisweep
