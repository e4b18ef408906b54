#include "server/depth/depth_options.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace omnisweep::depth {

std::string_view name_of(MatchingCost cost) {
  for (const auto& entry : kMatchingCostNames)
    if (entry.cost == cost) return entry.name;
  return "?";
}

std::optional<MatchingCost> matching_cost_named(std::string_view name) {
  for (const auto& entry : kMatchingCostNames)
    if (entry.name == name) return entry.cost;
  return std::nullopt;
}

const Method* method_named(std::string_view name) {
  for (const Method& method : kMethods)
    if (method.name == name) return &method;
  return nullptr;
}

bool apply_method(std::string_view name, DepthOptions& options) {
  const Method* method = method_named(name);
  if (!method) return false;
  options.cost = method->cost;
  options.correct_photometry = method->correct_photometry;
  options.match_cameras = method->match_cameras;
  options.confident_sigma_s = method->confident_sigma_s;
  options.sigma_s = method->sigma_s;
  return true;
}

std::string method_flags(const Method& method) {
  std::ostringstream flags;
  if (method.cost != MatchingCost::kAbsoluteDifference) flags << " --cost " << name_of(method.cost);
  if (method.correct_photometry) flags << " --correct-photometry";
  if (method.match_cameras != 1) flags << " --match-cameras " << method.match_cameras;
  if (method.confident_sigma_s > 0) flags << " --confident-sigma-s " << method.confident_sigma_s;
  if (method.sigma_s != DepthOptions{}.sigma_s) flags << " --sigma-s " << method.sigma_s;
  if (method.plane_fill > 0) flags << " --plane-fill " << method.plane_fill;
  if (method.region_planes) flags << " --region-planes";
  return flags.str().empty() ? "" : flags.str().substr(1);
}

void DepthOptions::check(int num_cameras) const {
  auto fail = [](const std::string& what) { throw std::invalid_argument(what); };
  if (references.empty()) fail("references: at least one reference camera is needed");
  if (references.size() > kMaxReferences) {
    fail("references: " + std::to_string(references.size()) + " given, at most " +
         std::to_string(kMaxReferences) + " are supported");
  }
  for (std::size_t i = 0; i < references.size(); ++i) {
    const int r = references[i];
    if (r < 0 || r >= num_cameras) {
      fail("references: camera " + std::to_string(r) + " does not exist (the rig has " +
           std::to_string(num_cameras) + " cameras)");
    }
    if (std::count(references.begin(), references.end(), r) > 1)
      fail("references: camera " + std::to_string(r) + " is listed twice");
  }
  if (num_cameras < 2) fail("a rig needs at least 2 cameras to match");
  if (max_group < 0) fail("max-group: " + std::to_string(max_group) + " must be 0 (all) or more");
  if (num_candidates < 2 || num_candidates > 512) {
    fail("candidates: " + std::to_string(num_candidates) + " must be within [2, 512]");
  }
  if (!(min_distance > 0) || !std::isfinite(min_distance))
    fail("min-dist: must be a positive number of metres");
  if (!(max_distance > min_distance) || !std::isfinite(max_distance))
    fail("max-dist: must be finite and larger than min-dist");
  if (!(sigma_i > 0) || !std::isfinite(sigma_i)) fail("sigma-i: must be positive");
  if (!(sigma_s > 0) || !std::isfinite(sigma_s)) fail("sigma-s: must be positive");
  if (!(confident_sigma_s >= 0) || !std::isfinite(confident_sigma_s))
    fail("confident-sigma-s: " + std::to_string(confident_sigma_s) +
         " must be 0 (off) or a positive number of pixels");
  if (!(match_blur >= 0) || !std::isfinite(match_blur))
    fail("match-blur: " + std::to_string(match_blur) +
         " must be 0 (off) or a positive number of pixels");
  if (match_blur > 0 && match_blur_radius(scaled_match_blur()) > kMatchBlurMaxRadius) {
    fail("match-blur: " + std::to_string(match_blur) + " pixels at 1024 px is " +
         std::to_string(scaled_match_blur()) + " at the matching width " +
         std::to_string(matching_width) + ", whose taps would reach past the " +
         std::to_string(kMatchBlurMaxRadius) + " pixels supported");
  }
  if (!matching_cost_named(name_of(cost))) fail("cost: not a matching cost");
  if (feature_radius < 1 || feature_radius > 16)
    fail("feature-radius: " + std::to_string(feature_radius) + " must be within [1, 16]");
  if (!(feature_epsilon > 0) || !std::isfinite(feature_epsilon))
    fail("feature-epsilon: " + std::to_string(feature_epsilon) + " must be positive");
  if (ratio_radius < 4 || ratio_radius > 64)
    fail("ratio-radius: " + std::to_string(ratio_radius) + " must be within [4, 64]");
  if (!(ratio_epsilon > 0) || !std::isfinite(ratio_epsilon))
    fail("ratio-epsilon: " + std::to_string(ratio_epsilon) + " must be positive");
  if (census_radius < 1 || census_radius > 16)
    fail("census-radius: " + std::to_string(census_radius) + " must be within [1, 16]");
  if (!(census_scale >= 0) || !std::isfinite(census_scale))
    fail("census-scale: " + std::to_string(census_scale) + " must be 0 or more");
  if (match_cameras < 1 || match_cameras > 2)
    fail("match-cameras: " + std::to_string(match_cameras) + " must be 1 or 2");
  if (!(coarse_agreement >= 0) || !std::isfinite(coarse_agreement))
    fail("coarse-agreement: " + std::to_string(coarse_agreement) +
         " must be 0 (off) or a positive tolerance in m^-1");
  if (!(raw_agreement >= 0) || !std::isfinite(raw_agreement))
    fail("raw-agreement: " + std::to_string(raw_agreement) +
         " must be 0 (off) or a positive tolerance");
  if (!(second_camera_power > 0 && second_camera_power <= 1))
    fail("second-camera-power: " + std::to_string(second_camera_power) + " must be within (0, 1]");
  if (matching_width < 8 || matching_height < 8 || matching_width > 8192 ||
      matching_height > 8192) {
    fail("matching-resolution: " + std::to_string(matching_width) + "x" +
         std::to_string(matching_height) + " must be within [8, 8192] pixels");
  }
}

}  // namespace omnisweep::depth
