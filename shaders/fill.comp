#version 450
// Fills count floats of a buffer with `value`, every `stride`-th element (stride is a
// specialization constant, 1 by default): the runtime's smallest kernel, used to clear buffers.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;
layout(constant_id = 0) const uint kStride = 1;

layout(std430, set = 0, binding = 0) writeonly buffer Data { float data[]; };
layout(push_constant) uniform Push {
  uint count;
  float value;
} push;

void main() {
  const uint i = gl_GlobalInvocationID.x;
  if (i * kStride < push.count) data[i * kStride] = push.value;
}
