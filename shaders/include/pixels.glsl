// Packed pixel formats shared by the kernels: RGBA8 colour in one uint (r in the low byte),
// 8-bit masks four to a uint.

vec3 unpack_rgb(uint packed) {
  return vec3(float(packed & 0xffu), float((packed >> 8) & 0xffu), float((packed >> 16) & 0xffu));
}

uint pack_rgb(uvec3 v) { return v.x | (v.y << 8) | (v.z << 16); }

uvec3 unpack_rgb_u(uint packed) { return uvec3(packed & 0xffu, (packed >> 8) & 0xffu, (packed >> 16) & 0xffu); }

// Byte `index` of an array of uints holding four bytes each.
#define BYTE_AT(array, index) (((array)[(index) >> 2] >> (((index) & 3u) * 8u)) & 0xffu)
