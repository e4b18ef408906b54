// Range weight of the inter-scale bilateral filter (ALGORITHM.md §4): g is the L1 difference of
// two 8-bit YCbCr guides summed over the channels; inv_two_sigma_sq = 1 / (2 sigma_I^2).
float range_weight(uint guide_a, uint guide_b, float inv_two_sigma_sq) {
  const vec3 d = abs(unpack_rgb(guide_a) - unpack_rgb(guide_b));
  const float g = d.x + d.y + d.z;
  return exp(-g * g * inv_two_sigma_sq) + 0.01;
}

// Rounds a weighted mean of guides back to 8 bits per channel.
uint round_guide(vec3 mean) { return pack_rgb(uvec3(clamp(floor(mean + 0.5), 0.0, 255.0))); }
