// Camera models in GLSL, the same formulas as client_sdk/include/omnisweep/camera/*.h
// (ALGORITHM.md §2 for the double sphere model). One Camera record per rig camera, filled by
// server/depth/gpu_camera.cc; rows of cam_from_ref take points from the reference camera's
// frame into this camera's frame (w holds the translation).

const uint kModelDoubleSphere = 0u;
const uint kModelKannalaBrandt = 1u;
const uint kModelExtendedUnified = 2u;
const uint kModelPinhole = 3u;
const uint kModelEquirectangular = 4u;  // panorama, ALGORITHM.md §5 convention; width, height only

const float kPi = 3.14159265358979;

struct Camera {
  vec4 focal_center;  // fx, fy, cx, cy
  vec4 extra;         // ds: xi, alpha; kb4: k1..k4; eucm: alpha, beta
  vec4 row0;          // cam_from_ref rotation row 0 | translation x
  vec4 row1;
  vec4 row2;
  uint model;
  float cos_max;      // cosine of the largest valid angle to the optical axis
  uint width;
  uint height;
};

vec3 to_camera(Camera c, vec3 p) {
  return vec3(dot(c.row0.xyz, p) + c.row0.w, dot(c.row1.xyz, p) + c.row1.w, dot(c.row2.xyz, p) + c.row2.w);
}

bool in_valid_cone(Camera c, vec3 p) {
  const float n = length(p);
  return n > 0.0 && p.z > c.cos_max * n;
}

float kb4_distort(Camera c, float t) {
  const float t2 = t * t;
  return t * (1.0 + t2 * (c.extra.x + t2 * (c.extra.y + t2 * (c.extra.z + t2 * c.extra.w))));
}

// Projects p (camera frame) to pixel coordinates; false when invalid.
bool project(Camera c, vec3 p, out vec2 uv) {
  if (c.model == kModelEquirectangular) {
    const float n = length(p);
    const float phi = asin(clamp(p.y / max(n, 1e-30), -1.0, 1.0));
    float theta = atan(p.x, p.z) - kPi;  // (-2 pi, 0]
    if (theta < 0.0) theta += 2.0 * kPi;
    float x = theta * float(c.width) / (2.0 * kPi) - 0.5;
    if (x >= float(c.width) - 0.5) x -= float(c.width);
    uv = vec2(x, (phi + 0.5 * kPi) * float(c.height) / kPi - 0.5);
    return n > 0.0;
  }
  vec2 m = vec2(0.0);
  bool ok = in_valid_cone(c, p);
  if (c.model == kModelDoubleSphere) {
    const float xi = c.extra.x, alpha = c.extra.y;
    const float d1 = length(p);
    const float k = xi * d1 + p.z;
    const float d2 = sqrt(p.x * p.x + p.y * p.y + k * k);
    const float den = alpha * d2 + (1.0 - alpha) * k;
    ok = ok && den > 0.0;
    m = p.xy / den;
  } else if (c.model == kModelKannalaBrandt) {
    const float r = length(p.xy);
    const float d = kb4_distort(c, atan(r, p.z));
    m = r > 1e-9 * abs(p.z) ? p.xy * (d / r) : p.xy / p.z;
  } else if (c.model == kModelExtendedUnified) {
    const float alpha = c.extra.x, beta = c.extra.y;
    const float d = sqrt(beta * dot(p.xy, p.xy) + p.z * p.z);
    const float den = alpha * d + (1.0 - alpha) * p.z;
    ok = ok && den > 0.0;
    m = p.xy / den;
  } else {
    ok = ok && p.z > 0.0;
    m = p.xy / p.z;
  }
  uv = c.focal_center.xy * m + c.focal_center.zw;
  return ok && !any(isnan(uv)) && !any(isinf(uv));
}

// Unprojects a pixel to a unit ray (camera frame); false when the pixel sees no valid ray.
bool unproject(Camera c, vec2 uv, out vec3 ray) {
  if (c.model == kModelEquirectangular) {
    const float phi = (uv.y + 0.5) * kPi / float(c.height) - 0.5 * kPi;
    const float theta = (uv.x + 0.5) * 2.0 * kPi / float(c.width) + kPi;
    ray = vec3(cos(phi) * sin(theta), sin(phi), cos(phi) * cos(theta));
    return true;
  }
  const vec2 m = (uv - c.focal_center.zw) / c.focal_center.xy;
  const float r2 = dot(m, m);
  vec3 r = vec3(0.0, 0.0, 1.0);
  if (c.model == kModelDoubleSphere) {
    const float xi = c.extra.x, alpha = c.extra.y;
    const float s1 = 1.0 - (2.0 * alpha - 1.0) * r2;
    if (s1 < 0.0) return false;
    const float mz = (1.0 - alpha * alpha * r2) / (alpha * sqrt(s1) + 1.0 - alpha);
    const float s2 = mz * mz + (1.0 - xi * xi) * r2;
    const float den = mz * mz + r2;
    if (s2 < 0.0 || den <= 0.0) return false;
    const float k = (mz * xi + sqrt(s2)) / den;
    r = vec3(k * m, k * mz - xi);
  } else if (c.model == kModelKannalaBrandt) {
    const float ru = sqrt(r2);
    const float theta_max = acos(clamp(c.cos_max, -1.0, 1.0));
    if (ru > kb4_distort(c, theta_max)) return false;
    float theta = min(ru, 1.0);
    for (int i = 0; i < 20; ++i) {
      const float t2 = theta * theta;
      const float derivative = 1.0 + t2 * (3.0 * c.extra.x + t2 * (5.0 * c.extra.y + t2 * (7.0 * c.extra.z + t2 * 9.0 * c.extra.w)));
      theta = clamp(theta - (kb4_distort(c, theta) - ru) / derivative, 0.0, theta_max);
    }
    r = ru > 0.0 ? vec3(sin(theta) * m / ru, cos(theta)) : vec3(0.0, 0.0, 1.0);
    ray = r;
    return true;
  } else if (c.model == kModelExtendedUnified) {
    const float alpha = c.extra.x, beta = c.extra.y;
    const float s = 1.0 - (2.0 * alpha - 1.0) * beta * r2;
    if (s < 0.0) return false;
    r = vec3(m, (1.0 - beta * alpha * alpha * r2) / (alpha * sqrt(s) + 1.0 - alpha));
  } else {
    r = vec3(m, 1.0);
  }
  if (!in_valid_cone(c, r)) return false;
  ray = normalize(r);
  return true;
}
