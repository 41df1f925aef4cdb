/* Direction encodings: (ωi, ωo) -> the direction features a decoder reads
 * after its latent. Forward only: nothing is trained through the directions.
 *
 * Both directions are first rotated about the normal so that ωi has azimuth 0
 * (model_encode_canonical below): the features below are of that pair.
 *
 * Kinds (each 6 base features, optionally followed by frequency features):
 * - CARTESIAN: (ωi.x, ωi.y, ωi.z, ωo.x, ωo.y, ωo.z), the input of the paper's
 *   released decoder (32 latent + 6 = 38 inputs).
 * - HALFDIFF: Rusinkiewicz 1998 half/difference coordinates: the half vector
 *   h = normalize(ωi + ωo) in the shading frame, then the difference vector
 *   d = ωi expressed in the half-vector frame, i.e. ωi rotated by −φh about z
 *   and then by −θh about y: (h.x, h.y, h.z, d.x, d.y, d.z). h.z = cos θh and
 *   d.z = cos θd are the two coordinates on which specular peaks and Fresnel
 *   depend, so a small network finds them without having to learn them; d is
 *   invariant to a rotation of both directions about the normal.
 * - octaves K > 0 appends, for each of the 6 base features x and k < K,
 *   sin(2^k π x) and cos(2^k π x) (NeRF-style frequency encoding), so the
 *   width is 6 + 12 K. Sharp lobes (α ≈ 0.01) need high frequencies that a
 *   ReLU MLP of 6 inputs reaches only with many units.
 *
 * Directions are unit vectors with z > 0 in the shading frame; below-horizon
 * or unnormalised inputs are the caller's business (the public decode call
 * validates them). */
#ifndef NBRDF_MODEL_ENCODING_H
#define NBRDF_MODEL_ENCODING_H

#include <stddef.h>

typedef enum model_encoding_kind {
  MODEL_ENCODING_CARTESIAN = 0,
  MODEL_ENCODING_HALFDIFF = 1
} model_encoding_kind;

#define MODEL_ENCODING_MAX_OCTAVES 8

typedef struct model_encoding {
  model_encoding_kind kind;
  int octaves; /* 0 .. MODEL_ENCODING_MAX_OCTAVES */
} model_encoding;

/* Number of floats one (ωi, ωo) pair becomes: 6 + 12 · octaves. */
/* Rotates ωi and ωo together about the normal so that ωi has azimuth 0
 * (ωi.y = 0, ωi.x >= 0); unchanged when ωi is at the normal. Every encoding
 * starts with it: the BRDFs are isotropic, and the training data have ωi in
 * the xz-plane (train/dataset.c), so a decoder has only ever seen that
 * azimuth; a renderer's ωi has any. Training inputs are unchanged bit for bit
 * (ωi.y = 0 gives the identity rotation exactly). */
void model_encode_canonical(double wi[3], double wo[3]);

int model_encoding_width(const model_encoding *enc);

/* "cartesian" / "halfdiff"; NULL for an invalid kind. */
const char *model_encoding_kind_name(model_encoding_kind kind);
/* Parses a name of model_encoding_kind_name; returns 0 when unknown. */
int model_encoding_kind_parse(const char *name, model_encoding_kind *kind);

/* Encodes n pairs: wi, wo are [n × 3]; row k of the output starts at
 * out + k · stride (stride >= width), so the features can be written straight
 * after each row's latent in a decoder input buffer. */
void model_encode(const model_encoding *enc, size_t n, const float *wi, const float *wo, float *out,
                  size_t stride);

/* The six base features of one pair, in double (tests, the proxy). */
void model_encode_halfdiff(const double wi[3], const double wo[3], double h[3], double d[3]);

#endif
