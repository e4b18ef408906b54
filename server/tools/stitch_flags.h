// Command-line flags shared by the programs that stitch panoramas (omnisweep-process,
// omnisweep-server): the temporal filter.
#pragma once

#include <CLI/CLI.hpp>
#include <optional>

#include "server/stitch/temporal_filter.h"

namespace omnisweep::tools {

// --temporal (the filter with its defaults) and --temporal-frames N, into `temporal`.
inline void add_temporal_flags(CLI::App& app, std::optional<stitch::TemporalOptions>& temporal) {
  app.add_flag_function(
      "--temporal",
      [&temporal](std::int64_t) {
        if (!temporal) temporal.emplace();
      },
      "Filter the distance over time: each pixel the mean of its frames since it last changed, "
      "restarting where colour or distance moves (docs/accuracy.md)");
  app.add_option_function<int>(
         "--temporal-frames",
         [&temporal](int frames) {
           if (!temporal) temporal.emplace();
           temporal->max_frames = frames;
         },
         "With --temporal: frames in the mean at most (default 8)")
      ->check(CLI::Range(1, 1000));
}

}  // namespace omnisweep::tools
