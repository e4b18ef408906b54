// Range weight of the inter-scale bilateral filter (ALGORITHM.md §4): g is the L1 difference of
// two 8-bit YCbCr guides summed over the channels; inv_two_sigma_sq = 1 / (2 sigma_I^2).
float range_weight(uint guide_a, uint guide_b, float inv_two_sigma_sq) {
  const vec3 d = abs(unpack_rgb(guide_a) - unpack_rgb(guide_b));
  const float g = d.x + d.y + d.z;
  return exp(-g * g * inv_two_sigma_sq) + 0.01;
}

// Rounds a weighted mean of guides back to 8 bits per channel.
uint round_guide(vec3 mean) { return pack_rgb(uvec3(clamp(floor(mean + 0.5), 0.0, 255.0))); }

// The confident spatial sigma (DepthOptions::confident_sigma_s, docs/accuracy.md): the guide's
// fourth byte carries the mean confidence of the raw cost curves (wta.glsl) around the pixel,
// 255 = 1, which the down pass averages with its weights like the guide. Where it is at least
// kConfidentFrom the spatial sigma falls linearly, over kConfidentRamp, from sigma_s to
// sigma_confident: raw curves that already single out a distance need less of their
// neighbourhood. CPU check: isb_filter_cpu.
const float kConfidentFrom = 0.5;
const float kConfidentRamp = 0.2;

uint confidence_byte(float confidence) { return uint(clamp(floor(confidence * 255.0 + 0.5), 0.0, 255.0)); }

// w_down of a fine pixel whose guide is `own`, at (2^l - 0.5)^2 = scale_sq.
float confident_w_down(uint own, float scale_sq, float sigma_s, float sigma_confident) {
  const float a = clamp((float(own >> 24u) / 255.0 - kConfidentFrom) / kConfidentRamp, 0.0, 1.0);
  const float sigma = mix(sigma_s, sigma_confident, a);
  return exp(-scale_sq / (2.0 * sigma * sigma));
}
