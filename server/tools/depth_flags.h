// Command-line flags shared by the programs that estimate distance: the parameters of the
// reference implementation with their defaults (DepthOptions), and comma-separated lists.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "omnisweep/options/split.h"
#include "server/depth/depth_options.h"

namespace omnisweep::tools {

// "a, b, c": the names of a table's entries (depth::kMethods, depth::kMatchingCostNames).
template <typename Table>
std::string joined_names(const Table& table) {
  std::string names;
  for (const auto& entry : table) names += (names.empty() ? "" : ", ") + std::string(entry.name);
  return names;
}

// Where a program keeps the stitcher's variants that a method sets (StitchOptions::plane_fill,
// StitchOptions::region_planes); null members: the program does not stitch.
struct StitchVariants {
  double* plane_fill = nullptr;
  bool* region_planes = nullptr;
};

// Sets `options` (and `stitch`'s variants) to the method's.
inline void apply_method(const depth::Method& method, depth::DepthOptions& options,
                         const StitchVariants& stitch) {
  depth::apply_method(method.name, options);
  if (stitch.plane_fill) *stitch.plane_fill = method.plane_fill;
  if (stitch.region_planes) *stitch.region_planes = method.region_planes;
}

// The variants beyond the paper's method (docs/accuracy.md): --method, --cost and the parameters
// of its features, the photometric correction, the cameras matched and the confident sigma. The
// default method (depth::kDefaultMethod) is applied here, before parsing; --method is defined
// before every flag it sets (--sigma-s, --plane-fill and --region-planes too, by the programs):
// CLI11 applies options in the order they are defined, so a variant's own flag overrides the
// method's setting of it wherever it stands.
inline void add_matching_cost_flags(CLI::App& app, depth::DepthOptions& options,
                                    StitchVariants stitch = {}) {
  const std::string methods = joined_names(depth::kMethods);
  std::string stands_for;
  for (const depth::Method& method : depth::kMethods) {
    const std::string flags = depth::method_flags(method);
    stands_for += std::string(stands_for.empty() ? "" : "; ") + std::string(method.name) + ": " +
                  (flags.empty() ? "ALGORITHM.md" : flags) +
                  (method.name == depth::kDefaultMethod ? ", the default" : "");
  }
  apply_method(*depth::method_named(depth::kDefaultMethod), options, stitch);
  app.add_option_function<std::string>(
      "--method",
      [&options, methods, stitch](const std::string& name) {
        const depth::Method* method = depth::method_named(name);
        if (!method)
          throw CLI::ValidationError("--method",
                                     "unknown method '" + name + "' (one of " + methods + ")");
        apply_method(*method, options, stitch);
      },
      "Variants at once (" + stands_for +
          "); a variant's own flag overrides it (docs/accuracy.md)");
  const std::string names = joined_names(depth::kMatchingCostNames);
  app.add_option_function<std::string>(
      "--cost",
      [&options](const std::string& name) {
        const auto cost = depth::matching_cost_named(name);
        if (!cost) throw CLI::ValidationError("--cost", "unknown matching cost '" + name + "'");
        options.cost = *cost;
      },
      "Matching cost: " + names + " (default ad, the paper's; docs/accuracy.md)");
  app.add_flag("--correct-photometry,!--no-correct-photometry", options.correct_photometry,
               "Estimate each camera's gain, colour cast and vignetting from what the cameras see "
               "in common, and undo them before matching and stitching");
  app.add_option("--match-cameras", options.match_cameras,
                 "Cameras each reference pixel is matched against: 1 (the paper's) or 2 (also the "
                 "next most discriminating camera, the costs averaged)")
      ->check(CLI::Range(1, 2));
  app.add_option("--second-camera-power", options.second_camera_power,
                 "With --match-cameras 2: the second camera's epipolar segment must be at least "
                 "this share of the first's")
      ->check(CLI::Range(0.01, 1.0));
  app.add_option("--feature-radius", options.feature_radius,
                 "Normalisation window radius of nad, pixels at 1024 px")
      ->check(CLI::Range(1, 16));
  app.add_option("--feature-epsilon", options.feature_epsilon,
                 "Added to the window's deviation by nad, 8-bit levels")
      ->check(CLI::PositiveNumber);
  app.add_option("--ratio-radius", options.ratio_radius,
                 "Reach of the neighbourhood mean of ratio, pixels at 1024 px (Gaussian sigma "
                 "half of it)")
      ->check(CLI::Range(4, 64));
  app.add_option("--ratio-epsilon", options.ratio_epsilon,
                 "Added to the neighbourhood mean by ratio, 8-bit levels")
      ->check(CLI::PositiveNumber);
  app.add_option("--census-radius", options.census_radius,
                 "Distance of the census neighbours, pixels at 1024 px")
      ->check(CLI::Range(1, 16));
  app.add_option("--census-scale", options.census_scale, "Cost of one differing census bit")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--confident-sigma-s", options.confident_sigma_s,
                 "Where the raw cost curves are confident, lower the ISB filter's spatial sigma "
                 "to this, at 1024 px (default 0: off, the paper's; docs/accuracy.md)")
      ->check(CLI::Range(0.0, 1e3));
  app.add_option("--match-blur", options.match_blur,
                 "Blur the matching images (not the colour) by a Gaussian of this sigma, pixels at "
                 "1024 px, before the sweep (default 0: off, the paper's; docs/accuracy.md)")
      ->check(CLI::Range(0.0, 2.5));
}

// The matching variants (add_matching_cost_flags, with `stitch`), --references, --candidates,
// --min-dist, --max-dist, --sigma-i, --sigma-s, --matching-resolution W H, --float32-costs,
// --max-group (written into the options) and --vk-device (into `device`).
inline void add_depth_flags(CLI::App& app, depth::DepthOptions& options, std::string& device,
                            StitchVariants stitch = {}) {
  add_matching_cost_flags(app, options, stitch);
  app.add_option("--references", options.references,
                 "Reference cameras (default: a dataset's dataset.json, else 2 3; at most 8)")
      ->expected(1, 16);
  app.add_option("--candidates", options.num_candidates, "Number of candidate distances")
      ->check(CLI::Range(2, 512));
  app.add_option("--min-dist", options.min_distance, "Nearest candidate distance, metres")
      ->check(CLI::PositiveNumber);
  app.add_option("--max-dist", options.max_distance, "Farthest candidate distance, metres")
      ->check(CLI::PositiveNumber);
  app.add_option("--sigma-i", options.sigma_i, "Range sigma of the ISB filter")
      ->check(CLI::PositiveNumber);
  app.add_option("--sigma-s", options.sigma_s,
                 "Spatial sigma of the ISB filter at 1024 px (the paper's: 25)")
      ->check(CLI::PositiveNumber);
  app.add_option_function<std::vector<int>>(
         "--matching-resolution",
         [&options](const std::vector<int>& size) {
           options.matching_width = size[0];
           options.matching_height = size[1];
         },
         "Width and height images are matched at (default 1024 1024)")
      ->expected(2)
      ->check(CLI::Range(8, 8192));
  app.add_flag_function(
      "--float32-costs", [&options](std::int64_t) { options.half_costs = false; },
      "Store the cost volume as 32-bit floats (default: 16-bit where the device supports it)");
  app.add_option("--max-group", options.max_group,
                 "At most this many references per dispatch, each with its cost volume in "
                 "memory (default 0: all)")
      ->check(CLI::Range(0, 8));
  app.add_option("--coarse-agreement", options.coarse_agreement,
                 "Lower the confidence where the distance disagrees with its 8x8 block's filtered "
                 "winner: tolerance in m^-1 (default 0.03; 0 turns it off; docs/accuracy.md)")
      ->check(CLI::Range(0.0, 1e3));
  app.add_option("--raw-agreement", options.raw_agreement,
                 "Lower the confidence where the pixel's own raw cost curve puts the surface "
                 "nearer than the filtered distance, so the stitcher's fills replace it: "
                 "tolerance, e.g. 0.2 "
                 "(default 0: off; docs/accuracy.md)")
      ->check(CLI::Range(0.0, 1e3));
  app.add_option(
      "--vk-device", device,
      "Vulkan device: index or name substring (default: OMNISWEEP_VK_DEVICE, else the best)");
}

// "a,b,c" -> {"a", "b", "c"}; empty items are left out.
inline std::vector<std::string> split_list(const std::string& list) {
  return split(list, ',', EmptyItems::kDrop);
}

}  // namespace omnisweep::tools
