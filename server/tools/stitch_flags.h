// Command-line flags shared by the programs that stitch panoramas (omnisweep-process,
// omnisweep-server): the panorama's size, colour resolution and centre, the plane fill, the region
// planes, the edge check and the temporal filter.
#pragma once

#include <CLI/CLI.hpp>
#include <Eigen/Core>
#include <optional>
#include <utility>
#include <vector>

#include "server/stitch/temporal_filter.h"

namespace omnisweep::tools {

// --panorama-resolution W H, --rgb-resolution W H and --viewpoint X Y Z.
struct PanoramaFlags {
  std::vector<int> panorama{};        // width, height
  std::vector<int> rgb_resolution{};  // empty: the images' own
  std::vector<double> viewpoint{};    // empty: dataset.json's, else the mean of the references

  std::optional<std::pair<int, int>> rgb() const {
    if (rgb_resolution.empty()) return std::nullopt;
    return std::pair{rgb_resolution[0], rgb_resolution[1]};
  }
  std::optional<Eigen::Vector3d> centre() const {
    if (viewpoint.empty()) return std::nullopt;
    return Eigen::Vector3d(viewpoint[0], viewpoint[1], viewpoint[2]);
  }
};

// The flags into `flags`; `flags.panorama` holds the default size when called.
inline void add_panorama_flags(CLI::App& app, PanoramaFlags& flags) {
  app.add_option("--panorama-resolution", flags.panorama, "Panorama width and height (2:1)")
      ->expected(2)
      ->check(CLI::Range(8, 16384));
  app.add_option("--rgb-resolution", flags.rgb_resolution,
                 "Width and height colour is sampled at (default: the images')")
      ->expected(2)
      ->check(CLI::Range(8, 16384));
  app.add_option("--viewpoint", flags.viewpoint,
                 "Panorama centre x y z in the rig frame, metres (default: dataset.json's, else "
                 "the mean of the references)")
      ->expected(3);
}

// --plane-fill C into `plane_fill` (StitchOptions::plane_fill).
inline void add_plane_fill_flag(CLI::App& app, double& plane_fill) {
  app.add_option("--plane-fill", plane_fill,
                 "Replace distances less confident than C (0-1; 0.05 measured best, 0: off; "
                 "default: the --method's) by a plane fitted to the confident pixels around them "
                 "of like colour (docs/accuracy.md)")
      ->check(CLI::Range(0.0, 0.99));
}

// --region-planes into `region_planes` (StitchOptions::region_planes, stitch/region_planes.h).
inline void add_region_planes_flag(CLI::App& app, bool& region_planes) {
  app.add_flag("--region-planes,!--no-region-planes", region_planes,
               "Replace the distances of each unconfident region (confidence below 0.05) by the "
               "planes RANSAC finds among the confident pixels on its rim and in its holes, where "
               "they surround the pixel (after the plane fill; default: the --method's; "
               "docs/accuracy.md)");
}

// --membrane-fill into `membrane_fill` (StitchOptions::membrane_fill, stitch/membrane_fill.h).
inline void add_membrane_fill_flag(CLI::App& app, bool& membrane_fill) {
  app.add_flag("--membrane-fill,!--no-membrane-fill", membrane_fill,
               "Solve the inverse distance of each large unconfident region (confidence below "
               "0.1) from the confident distances around it, exact where they lie on one plane "
               "(on the GPU, after the fills and the edge check; default off; docs/accuracy.md)");
}

// --edge-check into `edge_check` (StitchOptions::edge_check, stitch/edge_check.h).
inline void add_edge_check_flag(CLI::App& app, bool& edge_check) {
  app.add_flag("--edge-check,!--no-edge-check", edge_check,
               "Lower the confidence (times 0.1) within about 24 pixels of a depth step that has "
               "no colour step, where the filter carried a distance across a plain surface; the "
               "distances do not change (after the fills; default off; docs/accuracy.md)");
}

// --temporal (the filter with its defaults) and --temporal-frames N, into `temporal`.
inline void add_temporal_flags(CLI::App& app, std::optional<stitch::TemporalOptions>& temporal) {
  app.add_flag_function(
      "--temporal",
      [&temporal](std::int64_t) {
        if (!temporal) temporal.emplace();
      },
      "Filter the distance over time: each pixel the mean of its frames since it last changed, "
      "restarting where colour or distance moves (an unconfident distance's jump once the next "
      "frame confirms it; docs/accuracy.md)");
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
