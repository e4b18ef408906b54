// Flag checks shared by the omnisweep-* programs.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace omnisweep::tools {

// For options stored in unsigned integers: CLI11 2.1 converts "-5" to a huge unsigned number
// (2^64 - 5), which would silently mean "run forever"; this refuses it with a plain message.
inline CLI::Validator not_negative() {
  return CLI::Validator(
      [](std::string& value) {
        return value.find('-') == std::string::npos
                   ? std::string()
                   : "must be a whole number of 0 or more, got " + value;
      },
      "", "not negative");  // no text of its own in --help: the option already says UINT
}

}  // namespace omnisweep::tools
