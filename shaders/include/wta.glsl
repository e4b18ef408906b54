// Winner takes all with the parabola sub-candidate step (ALGORITHM.md §3 step 5), one candidate
// at a time in candidate order, so a kernel can take the winner while it computes the costs
// (isb_upsample.comp fuses it into the filter's last pass) or read them back
// (winner_take_all.comp). The first minimal candidate i* wins, delta = (C(i*-1) - C(i*+1)) /
// (2 (C(i*-1) + C(i*+1) - 2 C(i*) + 1e-8)) clamped to [-0.5, 0.5] (0 at the first or last
// candidate), mapped through the inverse-distance spacing to a distance. A flat cost (max = min)
// gives d_max.

struct Wta {
  float lowest, highest, before, after, previous;
  uint best;
  bool want_after;
};

Wta wta_start(float cost0) { return Wta(cost0, cost0, 0.0, 0.0, cost0, 0u, true); }

// Candidate i >= 1 with cost c, after candidates 0 .. i - 1.
void wta_step(inout Wta s, uint i, float c) {
  if (s.want_after) {
    s.after = c;
    s.want_after = false;
  }
  if (c < s.lowest) {
    s.lowest = c;
    s.best = i;
    s.before = s.previous;
    s.want_after = true;
  }
  s.highest = max(s.highest, c);
  s.previous = c;
}

float wta_distance(Wta s, uint num_candidates, float inv_d_min, float inv_d_max, float d_max) {
  if (s.highest == s.lowest) return d_max;
  float delta = 0.0;
  if (s.best > 0u && s.best + 1u < num_candidates) {
    delta = clamp(0.5 * (s.before - s.after) / (s.before + s.after - 2.0 * s.lowest + 1e-8), -0.5,
                  0.5);
  }
  const float k = float(s.best) + delta;
  const float inverse = inv_d_min + (inv_d_max - inv_d_min) * k / float(num_candidates - 1u);
  return 1.0 / inverse;
}

// Candidate i of n with cost c: starts the winner at i = 0, steps it for 0 < i < n (padding
// candidates past n are skipped).
void wta_candidate(inout Wta s, uint i, uint n, float c) {
  if (i == 0u) {
    s = wta_start(c);
  } else if (i < n) {
    wta_step(s, i, c);
  }
}

// The cost curve's confidence, taken in the same single pass (docs/accuracy.md, "Confidence"):
// the geometric mean of two things in [0, 1]:
// - the peak ratio, 1 - m1 / m2, where m1 is the lowest cost and m2 the second lowest local
//   minimum (a candidate no higher than its neighbours; the ends count with one neighbour), or
//   the highest cost where the curve has one minimum: near 0 for a flat curve (plain surfaces,
//   no match) or two equally good distances;
// - the sharpness, k / (k + m1), where k is the curvature at the winner (C(i-1) + C(i+1) - 2 m1,
//   one-sided at the ends): near 0 for a broad minimum, whose distance is imprecise.
// Their product ranked the errors best of what was measured (docs/accuracy.md); the square root
// spreads it over the 8-bit levels the stream carries.
const float kNoMinimum = 3.0e38;

struct Peaks {
  float before_previous, previous;  // the costs of candidates i - 2 and i - 1
  float lowest, second;             // the two lowest local minima so far
};

void peaks_insert(inout Peaks s, float m) {
  if (m < s.lowest) {
    s.second = s.lowest;
    s.lowest = m;
  } else if (m < s.second) {
    s.second = m;
  }
}

// Candidate i of n with cost c (padding candidates past n are skipped).
void peaks_candidate(inout Peaks s, uint i, uint n, float c) {
  if (i == 0u) {
    s = Peaks(kNoMinimum, c, kNoMinimum, kNoMinimum);
  } else if (i < n) {
    if (s.previous < s.before_previous && s.previous <= c) peaks_insert(s, s.previous);
    s.before_previous = s.previous;
    s.previous = c;
  }
}

// After the last candidate, with the winner `w` of the same n candidates.
float peaks_confidence(Peaks s, Wta w, uint n) {
  if (s.previous < s.before_previous) peaks_insert(s, s.previous);
  const float second = min(s.second, w.highest);
  const float ratio = second > s.lowest ? clamp(1.0 - s.lowest / second, 0.0, 1.0) : 0.0;
  // Sharpness: the curvature at the winner against its cost (one-sided at the ends).
  float curvature;
  if (w.best == 0u) curvature = 2.0 * (w.after - w.lowest);
  else if (w.best + 1u >= n) curvature = 2.0 * (w.before - w.lowest);
  else curvature = w.before + w.after - 2.0 * w.lowest;
  const float sharpness = curvature / (curvature + w.lowest + 1e-12);
  return sqrt(ratio * sharpness);
}

// The raw agreement (DepthOptions::raw_agreement, docs/accuracy.md): the fused winner also follows
// the raw curve (the sweep's costs before the filter) of the same pixel. Where the filtered
// curve's winner sits high on a raw curve that discriminates and whose lowest candidate is nearer
// (a lower index), the filter may have carried a farther distance over a near structure (a pole,
// a leg, the near side of an edge); the confidence is multiplied by exp(-(d p / t)^2), with d the
// raw cost at the winner within the raw curve's range (0 at its lowest, 1 at its highest),
// p = 1 - lowest / highest the raw curve's power (0 for a flat one) and t the tolerance, so the
// stitcher's fills replace such distances.
// A raw curve that puts the surface farther is not heard: on a real glossy floor reflections lie
// beyond it, and disputing those covered kaist-rig's floor in fills (docs/accuracy.md, stop 45).
struct RawCurve {
  float at_best, lowest, highest;
  uint lowest_at;
};

// Raw cost r of candidate i of n, after the winner `wta` took the filtered cost of the same one.
void raw_candidate(inout RawCurve s, Wta wta, uint i, uint n, float r) {
  if (i == 0u) {
    s = RawCurve(r, r, r, 0u);
  } else if (i < n) {
    if (wta.best == i) s.at_best = r;
    if (r < s.lowest) s.lowest_at = i;
    s.lowest = min(s.lowest, r);
    s.highest = max(s.highest, r);
  }
}

// The factor in (0, 1] for the filtered winner `best`, for a positive inv_tolerance (1 / the
// tolerance).
float raw_agreement(RawCurve s, uint best, float inv_tolerance) {
  if (s.lowest_at >= best) return 1.0;
  const float range = s.highest - s.lowest;
  const float d = range > 0.0 ? (s.at_best - s.lowest) / range : 0.0;
  const float power = s.highest > 0.0 ? 1.0 - s.lowest / s.highest : 0.0;
  const float x = d * power * inv_tolerance;
  return exp(-x * x);
}

#ifdef VOLUME_V
// Candidate i of n with cost c into the winner and the confidence.
void winner_candidate(inout Wta wta, inout Peaks peaks, uint i, uint n, float c) {
  wta_candidate(wta, i, n, c);
  peaks_candidate(peaks, i, n, c);
}

// The candidates of one volume texel (volume.glsl, included before this file), i the first.
void winner_texel(inout Wta wta, inout Peaks peaks, uint i, uint n, VOLUME_V c) {
#if VOLUME_PACK == 4
  winner_candidate(wta, peaks, i, n, c.x);
  winner_candidate(wta, peaks, i + 1u, n, c.y);
  winner_candidate(wta, peaks, i + 2u, n, c.z);
  winner_candidate(wta, peaks, i + 3u, n, c.w);
#else
  winner_candidate(wta, peaks, i, n, c);
#endif
}

// The same with the raw costs r of the texel's candidates, for the raw agreement.
void winner_raw_texel(inout Wta wta, inout Peaks peaks, inout RawCurve raw, uint i, uint n,
                      VOLUME_V c, VOLUME_V r) {
#if VOLUME_PACK == 4
  winner_candidate(wta, peaks, i, n, c.x);
  raw_candidate(raw, wta, i, n, r.x);
  winner_candidate(wta, peaks, i + 1u, n, c.y);
  raw_candidate(raw, wta, i + 1u, n, r.y);
  winner_candidate(wta, peaks, i + 2u, n, c.z);
  raw_candidate(raw, wta, i + 2u, n, r.z);
  winner_candidate(wta, peaks, i + 3u, n, c.w);
  raw_candidate(raw, wta, i + 3u, n, r.w);
#else
  winner_candidate(wta, peaks, i, n, c);
  raw_candidate(raw, wta, i, n, r);
#endif
}
#endif
