// Shared by plane_fit.comp and plane_fill.comp (server/stitch/plane_fill.h): their push
// constants, the panorama's rays and the fit's spatial weights from the host's table (per column
// cos and sin of the longitude, per row sin and cos of the colatitude, then the weight of tap
// offsets -taps .. taps). Include after declaring the `table` buffer (vec2 table[]).

layout(push_constant) uniform Push {
  uint width;
  uint height;
  int step;
  int taps;
  float fill_below;
  float support;
  float sigma_c;
  float lambda;
  float inv_d_min;
  float inv_d_max;
  int refits;
  float tau;
} push;

// Pixels per side of the cells that get one plane each.
const int kCell = 4;

vec3 ray(int x, int y) {
  const vec2 longitude = table[x];
  const vec2 colatitude = table[int(push.width) + y];
  return vec3(colatitude.x * longitude.x, colatitude.x * longitude.y, colatitude.y);
}

float spatial(int t) { return table[int(push.width + push.height) + t + push.taps].x; }

// Pixel i is one to fill: it has a distance, less confident than fill_below.
bool to_fill(uint i) { return distance_in[i] > 0.0 && confidence[i] < push.fill_below; }
