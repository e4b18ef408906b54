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

#ifdef VOLUME_V
// The candidates of one volume texel (volume.glsl, included before this file), i the first.
void wta_texel(inout Wta s, uint i, uint n, VOLUME_V c) {
#if VOLUME_PACK == 4
  wta_candidate(s, i, n, c.x);
  wta_candidate(s, i + 1u, n, c.y);
  wta_candidate(s, i + 2u, n, c.z);
  wta_candidate(s, i + 3u, n, c.w);
#else
  wta_candidate(s, i, n, c);
#endif
}
#endif
