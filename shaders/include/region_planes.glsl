// Shared by the region_*.comp kernels (server/stitch/region_planes.h): their push constants,
// sizes, the panorama's rays from the host's table (per column cos and sin of the longitude, per
// row sin and cos of the colatitude) and the arithmetic of server/stitch/region_planes_math.h,
// function for function (keep the two in step). Include after declaring the `table` buffer
// (vec2 table[]) where ray() is used (define REGION_RAYS).

layout(push_constant) uniform Push {
  uint width;
  uint height;
  int block;
  int blocks_x;
  int blocks_y;
  int rim;
  int min_pixels;
  int max_regions;
  int max_planes;
  int draws;
  int min_inliers;
  int min_inlier_fraction;
  float fill_below;
  float support;
  float tau;
  float inv_d_min;
  float inv_d_max;
  int plane;  // region_ransac_step: the plane being found
  int phase;  // region_support: 0 counts the supports, 1 collects the sample's candidates
  float surround_cos;  // cos of RegionPlaneParams::surround_angle_deg
} push;

const uint kNone = 0xffffffffu;
const int kSample = 1024;      // kRegionPlaneSample
const int kCandidates = 2048;  // kRegionPlaneCandidates
const int kMaxPlanes = 16;     // kRegionPlaneMaxPlanes
const int kNearRegions = 8;    // region_math::kNearRegions

// The regions' records (uint regions[]): [0] the count; region l at kHeader + l * kRecord.
const int kHeader = 4;
const int kRecord = 9;
const int kRoot = 0;       // its first block
const int kSupports = 1;   // support entries before sampling
const int kLastBin = 2;    // the last hash bin sampled (int; -1: none)
const int kCollected = 3;  // candidates collected
const int kSampled = 4;    // supports in the sample
const int kPlanes = 5;     // planes found
const int kAlive = 6;      // supports of the sample not yet an inlier (even planes' list)
const int kDone = 7;       // 1 once no further plane is found
const int kAliveOdd = 8;   // the same for the odd planes' list (region_ransac_step.comp)
int field(int region, int f) { return kHeader + region * kRecord + f; }

#ifdef REGION_RAYS
vec3 ray(int x, int y) {
  const vec2 longitude = table[x];
  const vec2 colatitude = table[int(push.width) + y];
  return vec3(colatitude.x * longitude.x, colatitude.x * longitude.y, colatitude.y);
}
#endif

uint mix_hash(uint x) {
  const uint state = x * 747796405u + 2891336453u;
  const uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

uint draw_hash(uint root, uint k, uint t) {
  return mix_hash(root * 0x9e3779b9u ^ mix_hash(k * 0x85ebca6bu ^ mix_hash(t)));
}

uint support_hash(uint block, uint root) {
  return mix_hash(block * 0x9e3779b9u ^ mix_hash(root + 0x7f4a7c15u));
}

int needed_inliers(int n, uint supports) {
  const int share = int((uint(push.min_inliers) * uint(n) + supports - 1u) / supports);
  return max(3, max(share, n / push.min_inlier_fraction));
}

// The a of a . r_i = v_i by Cramer's rule; false where |det| <= min_det or a is not finite.
bool solve3(vec3 r0, vec3 r1, vec3 r2, vec3 v, float min_det, out vec3 a) {
  const vec3 c12 = cross(r1, r2), c20 = cross(r2, r0), c01 = cross(r0, r1);
  const float det = dot(r0, c12);
  a = vec3(0.0);
  if (!(abs(det) > min_det)) return false;
  const float inv = 1.0 / det;
  a = (c12 * v.x + c20 * v.y + c01 * v.z) * inv;
  return !any(isinf(a)) && !any(isnan(a));
}

float msac(vec3 a, vec4 s) {
  const float e = (dot(a, s.xyz) - s.w) / (push.tau * s.w);
  return max(0.0, 1.0 - e * e);
}

bool is_inlier(vec3 a, vec4 s) { return abs(dot(a, s.xyz) - s.w) < push.tau * s.w; }

uint quadrant(vec3 centre, vec3 t) {
  if (!(dot(t, centre) > push.surround_cos)) return 0u;
  vec3 e1 = vec3(-centre.y, centre.x, 0.0);
  const float len = sqrt(dot(e1, e1));
  e1 = len < 1e-6 ? vec3(1.0, 0.0, 0.0) : e1 * (1.0 / len);
  const vec3 e2 = cross(centre, e1);
  const float u = dot(t, e1), w = dot(t, e2);
  return u >= 0.0 ? (w >= 0.0 ? 1u : 2u) : (w >= 0.0 ? 4u : 8u);
}
