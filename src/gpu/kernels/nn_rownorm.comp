#version 450
// Per row, in place on y [rows x N]: LayerNorm (mean, then the biased variance of the
// deviations, eps 1e-5, as src/nn/kernels.c) with gamma p[g_off..] and beta p[be_off..],
// then ReLU if RELU; with NORM off only the ReLU. One workgroup per row at a time.
layout(local_size_x = 64) in;
layout(std430, binding = 1) readonly buffer P { float p[]; };
layout(std430, binding = 2) buffer Y { float y[]; };
layout(push_constant) uniform PC {
  uint rows, K, N, w_off, b_off, flags, g_off, be_off;
} pc;

const uint NORM = 16u, RELU = 32u;
shared float red[64];

float reduce_sum(float v) {
  uint t = gl_LocalInvocationID.x;
  red[t] = v;
  barrier();
  for (uint s = 32u; s > 0u; s >>= 1u) {
    if (t < s) red[t] += red[t + s];
    barrier();
  }
  float r = red[0];
  barrier();
  return r;
}

void main() {
  const uint t = gl_LocalInvocationID.x, w = pc.N;
  for (uint row = gl_WorkGroupID.x; row < pc.rows; row += gl_NumWorkGroups.x) {
    uint base = row * w;
    float mean = 0.0, rs = 1.0;
    if ((pc.flags & NORM) != 0u) {
      float s = 0.0;
      for (uint c = t; c < w; c += 64u) s += y[base + c];
      mean = reduce_sum(s) / float(w);
      float q = 0.0;
      for (uint c = t; c < w; c += 64u) {
        float d = y[base + c] - mean;
        q += d * d;
      }
      rs = 1.0 / sqrt(reduce_sum(q) / float(w) + 1e-5);
    }
    for (uint c = t; c < w; c += 64u) {
      float v = y[base + c];
      if ((pc.flags & NORM) != 0u) v = (v - mean) * rs * p[pc.g_off + c] + p[pc.be_off + c];
      if ((pc.flags & RELU) != 0u) v = max(v, 0.0);
      y[base + c] = v;
    }
  }
}
