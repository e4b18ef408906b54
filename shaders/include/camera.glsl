// Camera models in GLSL, the same formulas as client_sdk/include/omnisweep/camera/*.h
// (ALGORITHM.md §2 for the double sphere model). One Camera record per rig camera, filled by
// reproject::pack_cameras (client_sdk/src/reproject/gpu_camera.cc); rows of cam_from_ref take
// points from the reference camera's frame into this camera's frame (w holds the translation).

#include "omnisweep/reproject/camera_model_ids.h"

const uint kModelDoubleSphere = uint(OMNISWEEP_MODEL_DOUBLE_SPHERE);
const uint kModelKannalaBrandt = uint(OMNISWEEP_MODEL_KANNALA_BRANDT);
const uint kModelExtendedUnified = uint(OMNISWEEP_MODEL_EXTENDED_UNIFIED);
const uint kModelPinhole = uint(OMNISWEEP_MODEL_PINHOLE);
// Panorama, ALGORITHM.md §5 convention; width, height only.
const uint kModelEquirectangular = uint(OMNISWEEP_MODEL_EQUIRECTANGULAR);
const uint kModelAny = uint(OMNISWEEP_MODEL_ANY);

// The model every camera of a role has, where the host knows it (specialization constants 20
// and 21, reproject::model_constants); kModelAny leaves it to each camera's `model` field. With
// the model fixed the compiler keeps only that model's code: a CPU device (lavapipe) would
// otherwise run every model's branch under a mask for every call, and a GPU holds registers for
// all of them. Sources are the rig's cameras (and the warp's source), targets the views warped to.
layout(constant_id = 20) const uint kSourceModel = kModelAny;
layout(constant_id = 21) const uint kTargetModel = kModelAny;

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

// Kernels read camera records from a uniform buffer, declared by CAMERA_RECORDS(binding): every
// invocation reads the same few records, which a CPU device loads once as scalars (a storage
// buffer would be read lane by lane) and a GPU serves from its constant cache. Its std140 layout
// of Camera is the std430 one (reproject::GpuCamera, 96 bytes); 170 records fill the 16 KiB
// every Vulkan device allows a uniform buffer (reproject::kMaxCameraRecords).
const uint kMaxCameraRecords = 170u;
#define CAMERA_RECORDS(index) \
  layout(std140, set = 0, binding = index) uniform Cameras { Camera cameras[kMaxCameraRecords]; };

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

uint model_of(Camera c, uint fixed_model) { return fixed_model == kModelAny ? c.model : fixed_model; }

// Projects p (camera frame) to pixel coordinates with camera c of model `model`; false when
// invalid.
bool project_as(uint model, Camera c, vec3 p, out vec2 uv) {
  if (model == kModelEquirectangular) {
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
  if (model == kModelDoubleSphere) {
    const float xi = c.extra.x, alpha = c.extra.y;
    const float d1 = length(p);
    const float k = xi * d1 + p.z;
    const float d2 = sqrt(p.x * p.x + p.y * p.y + k * k);
    const float den = alpha * d2 + (1.0 - alpha) * k;
    ok = ok && den > 0.0;
    m = p.xy / den;
  } else if (model == kModelKannalaBrandt) {
    const float r = length(p.xy);
    const float d = kb4_distort(c, atan(r, p.z));
    m = r > 1e-9 * abs(p.z) ? p.xy * (d / r) : p.xy / p.z;
  } else if (model == kModelExtendedUnified) {
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

// Unprojects a pixel of camera c (of model `model`) to a unit ray (camera frame); false when the
// pixel sees no valid ray.
bool unproject_as(uint model, Camera c, vec2 uv, out vec3 ray) {
  if (model == kModelEquirectangular) {
    const float phi = (uv.y + 0.5) * kPi / float(c.height) - 0.5 * kPi;
    const float theta = (uv.x + 0.5) * 2.0 * kPi / float(c.width) + kPi;
    ray = vec3(cos(phi) * sin(theta), sin(phi), cos(phi) * cos(theta));
    return true;
  }
  const vec2 m = (uv - c.focal_center.zw) / c.focal_center.xy;
  const float r2 = dot(m, m);
  vec3 r = vec3(0.0, 0.0, 1.0);
  if (model == kModelDoubleSphere) {
    const float xi = c.extra.x, alpha = c.extra.y;
    const float s1 = 1.0 - (2.0 * alpha - 1.0) * r2;
    if (s1 < 0.0) return false;
    const float mz = (1.0 - alpha * alpha * r2) / (alpha * sqrt(s1) + 1.0 - alpha);
    const float s2 = mz * mz + (1.0 - xi * xi) * r2;
    const float den = mz * mz + r2;
    if (s2 < 0.0 || den <= 0.0) return false;
    const float k = (mz * xi + sqrt(s2)) / den;
    r = vec3(k * m, k * mz - xi);
  } else if (model == kModelKannalaBrandt) {
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
  } else if (model == kModelExtendedUnified) {
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

// The calls kernels make: a camera in the source or the target role.
bool project_source(Camera c, vec3 p, out vec2 uv) { return project_as(model_of(c, kSourceModel), c, p, uv); }
bool project_target(Camera c, vec3 p, out vec2 uv) { return project_as(model_of(c, kTargetModel), c, p, uv); }
bool unproject_source(Camera c, vec2 uv, out vec3 ray) { return unproject_as(model_of(c, kSourceModel), c, uv, ray); }
bool unproject_target(Camera c, vec2 uv, out vec3 ray) { return unproject_as(model_of(c, kTargetModel), c, uv, ray); }
