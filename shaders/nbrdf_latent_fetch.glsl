// nbrdf shaders: filtered fetch of a latent texture from a storage buffer (GLSL 450).
//
// The convention is src/texture/latent_fetch.h's (the C reference evaluator), which is
// OpenGL's GL_LINEAR_MIPMAP_LINEAR with GL_REPEAT and an explicit lod (textureLod):
//  - (u, v): u to the right, v DOWN (v = 0 is the EXR's first row); period 1 in both;
//  - level l is max(1, W >> l) x max(1, H >> l); texel (i, j) of a w x h level has its
//    centre at ((i + 0.5) / w, (j + 0.5) / h);
//  - bilinear: x = u w - 0.5, i0 = floor(x), fx = x - i0 (same for y), texels i0, i0 + 1
//    (mod w) weighted (1 - fx)(1 - fy), fx(1 - fy), (1 - fx) fy, fx fy;
//  - trilinear: lod clamped to [0, levels - 1] (NaN -> 0), l0 = floor(lod), t = lod - l0,
//    (1 - t) bilinear(l0) + t bilinear(l0 + 1) (l0 alone at the last level or t = 0);
//  - every channel (latents, proxy σ and w) is filtered alike: a weighted mean of latents
//    is the paper's latent interpolation.
// Texels are float runs in the library's logical order (src/texture/latent_layout.h): per
// colour channel (Y, or R G B) its latent_dim latents, then σ and w when the texture stores
// the proxy. Buffer layout (nbrdf_gpu_pack_latents, docs/SHADERS.md):
//   word 0 magic 0x544c424e ("NBLT"), 1 version 1, 2 floats per texel, 3 levels,
//   4 latent_dim, 5 colour channels (1 or 3), 6 proxy stored (0/1), 7..15 reserved,
//   16 + 4 l: level l's width, height, word offset of its texels, 0 (l < 32),
//   then the texels, row-major per level.
// Use:
//   NbrdfFootprint fp = nbrdf_latent_footprint(uv, lod);   // once per shading point
//   float v = nbrdf_latent_channel(fp, c);                 // any logical channel c
#ifndef NBRDF_LATENT_FETCH_GLSL
#define NBRDF_LATENT_FETCH_GLSL

#ifndef NBRDF_LATENTS_SET
#define NBRDF_LATENTS_SET 0
#endif
#ifndef NBRDF_LATENTS_BINDING
#define NBRDF_LATENTS_BINDING 1
#endif

const uint NBRDF_L_CHANNELS = 2u, NBRDF_L_LEVELS = 3u, NBRDF_L_LATENT_DIM = 4u,
           NBRDF_L_COLOURS = 5u, NBRDF_L_PROXY = 6u, NBRDF_L_HEADER = 16u;

layout(std430, set = NBRDF_LATENTS_SET, binding = NBRDF_LATENTS_BINDING) readonly buffer
    NbrdfLatents {
  uint nbrdf_l[];
};

// The texels and weights of one fetch: [0..3] level l0, [4..7] level l0 + 1.
struct NbrdfFootprint {
  uint texel[8]; // word index of each texel's first channel
  float weight[8];
  float t;       // weight of level l0 + 1; 0: level l0 alone
};

// Positive modulo of a floor()ed coordinate, reduced in float first (huge u stays exact
// enough and never overflows the int conversion).
int nbrdf_wrap(float xf, int n) {
  int m = int(xf - float(n) * floor(xf / float(n)));
  if (m >= n) m -= n;
  if (m < 0) m += n;
  return m;
}

void nbrdf_latent_bilinear(uint level, vec2 uv, int slot, inout NbrdfFootprint fp) {
  uint rec = NBRDF_L_HEADER + 4u * level;
  int w = int(nbrdf_l[rec]), h = int(nbrdf_l[rec + 1u]);
  uint start = nbrdf_l[rec + 2u], C = nbrdf_l[NBRDF_L_CHANNELS];
  float x = uv.x * float(w) - 0.5, y = uv.y * float(h) - 0.5;
  float xf = floor(x), yf = floor(y);
  float fx = x - xf, fy = y - yf;
  int i0 = nbrdf_wrap(xf, w), j0 = nbrdf_wrap(yf, h);
  int i1 = i0 + 1 == w ? 0 : i0 + 1, j1 = j0 + 1 == h ? 0 : j0 + 1;
  fp.texel[slot + 0] = start + (uint(j0 * w + i0)) * C;
  fp.texel[slot + 1] = start + (uint(j0 * w + i1)) * C;
  fp.texel[slot + 2] = start + (uint(j1 * w + i0)) * C;
  fp.texel[slot + 3] = start + (uint(j1 * w + i1)) * C;
  precise float w00 = (1.0 - fx) * (1.0 - fy), w10 = fx * (1.0 - fy);
  precise float w01 = (1.0 - fx) * fy, w11 = fx * fy;
  fp.weight[slot + 0] = w00;
  fp.weight[slot + 1] = w10;
  fp.weight[slot + 2] = w01;
  fp.weight[slot + 3] = w11;
}

// Footprint of one level only (bilinear).
NbrdfFootprint nbrdf_latent_footprint_level(vec2 uv, uint level) {
  NbrdfFootprint fp;
  nbrdf_latent_bilinear(level, uv, 0, fp);
  for (int k = 4; k < 8; k++) {
    fp.texel[k] = fp.texel[k - 4];
    fp.weight[k] = 0.0;
  }
  fp.t = 0.0;
  return fp;
}

// Trilinear footprint at (uv, lod).
NbrdfFootprint nbrdf_latent_footprint(vec2 uv, float lod) {
  float last = float(nbrdf_l[NBRDF_L_LEVELS] - 1u);
  if (!(lod > 0.0)) lod = 0.0; // NaN too
  if (lod > last) lod = last;
  float l0 = floor(lod);
  NbrdfFootprint fp = nbrdf_latent_footprint_level(uv, uint(l0));
  fp.t = lod - l0;
  if (l0 + 1.0 <= last && fp.t != 0.0) nbrdf_latent_bilinear(uint(l0) + 1u, uv, 4, fp);
  else fp.t = 0.0;
  return fp;
}

// The filtered value of logical channel c (src/texture/latent_fetch.c's arithmetic order).
float nbrdf_latent_channel(NbrdfFootprint fp, uint c) {
  precise float a = fp.weight[0] * uintBitsToFloat(nbrdf_l[fp.texel[0] + c]) +
                    fp.weight[1] * uintBitsToFloat(nbrdf_l[fp.texel[1] + c]) +
                    fp.weight[2] * uintBitsToFloat(nbrdf_l[fp.texel[2] + c]) +
                    fp.weight[3] * uintBitsToFloat(nbrdf_l[fp.texel[3] + c]);
  if (fp.t == 0.0) return a;
  precise float b = fp.weight[4] * uintBitsToFloat(nbrdf_l[fp.texel[4] + c]) +
                    fp.weight[5] * uintBitsToFloat(nbrdf_l[fp.texel[5] + c]) +
                    fp.weight[6] * uintBitsToFloat(nbrdf_l[fp.texel[6] + c]) +
                    fp.weight[7] * uintBitsToFloat(nbrdf_l[fp.texel[7] + c]);
  precise float r = (1.0 - fp.t) * a + fp.t * b;
  return r;
}

// Logical channel of latent k of colour channel `colour`, and of its proxy σ and w.
uint nbrdf_latent_index(uint colour, uint k) {
  uint per = nbrdf_l[NBRDF_L_LATENT_DIM] + (nbrdf_l[NBRDF_L_PROXY] != 0u ? 2u : 0u);
  return colour * per + k;
}
uint nbrdf_latent_index_sigma(uint colour) {
  return nbrdf_latent_index(colour, nbrdf_l[NBRDF_L_LATENT_DIM]);
}
uint nbrdf_latent_index_w(uint colour) { return nbrdf_latent_index_sigma(colour) + 1u; }

#endif
