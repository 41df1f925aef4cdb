/* Shared by the verify tests: an untrained bundle, constant inputs, and the
 * lobe images of a latent and of the ground truth computed here, apart from
 * src/verify/verify*.c (through lobe_images and the per-image whole-lobe
 * estimator with seeds verify never uses). */
#ifndef NBRDF_TESTS_TEST_VERIFY_FIXTURE_H
#define NBRDF_TESTS_TEST_VERIFY_FIXTURE_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brdf/brdf_handle.h"
#include "brdf/layered_lobe.h"
#include "lobe/lobe.h"
#include "model/bundle.h"
#include "nbrdf/verify.h"
#include "testing.h"
#include "texture/latent_exr.h"
#include "verify/verify_internal.h"

#define FIX_SET ((size_t)VERIFY_N_THETA * NBRDF_LOBE_RES * NBRDF_LOBE_RES)

static nbrdf_model *fix_model;

static inline const char *fix_path(const char *name) {
  static char buf[4][640];
  static int k;
  k = (k + 1) % 4;
  snprintf(buf[k], sizeof buf[k], "%s/%s", testing_tmpdir(), name);
  return buf[k];
}

static inline void fix_load_model(void) {
  nbrdf_error e, *err = &e;
  CHECK_OK(model_bundle_init_random(fix_path("bundle"), "verify-test", 5, "small", err), err);
  CHECK_OK(nbrdf_model_load(fix_path("bundle"), &fix_model, err), err);
}

/* The tuple of the constant inputs below, in nbrdf_bake_param_id order. */
static const float fix_tuple[NBRDF_BAKE_PARAM_COUNT] = {0.3f, 1.5f, 0.2f, 0.7f, 0.8f, 1.0f};

static inline nbrdf_bake_inputs fix_constants(void) {
  nbrdf_bake_inputs in = NBRDF_BAKE_INPUTS_DEFAULT;
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++)
    nbrdf_bake_param_constant(&in.param[id], fix_tuple[id]);
  return in;
}

typedef struct fix_decode {
  const float *latent;
  double phi; /* radians: ωi and ωo rotated about the normal (verify's azimuth of the image) */
} fix_decode;

static inline nbrdf_status fix_decode_fn(void *user, size_t n, const nbrdf_query *q, double *f,
                                         nbrdf_error *err) {
  const fix_decode *d = user;
  int D = nbrdf_model_latent_dim(fix_model);
  float *lat = malloc(sizeof(float) * n * (size_t)D), *wi = malloc(sizeof(float) * n * 6);
  float *wo = wi + 3 * n, *out = malloc(sizeof(float) * n);
  for (size_t k = 0; k < n; k++) {
    memcpy(lat + k * D, d->latent, sizeof(float) * D);
    double c = cos(d->phi), s = sin(d->phi);
    wi[3 * k] = (float)(c * q[k].wi[0] - s * q[k].wi[1]);
    wi[3 * k + 1] = (float)(s * q[k].wi[0] + c * q[k].wi[1]);
    wo[3 * k] = (float)(c * q[k].wo[0] - s * q[k].wo[1]);
    wo[3 * k + 1] = (float)(s * q[k].wo[0] + c * q[k].wo[1]);
    wi[3 * k + 2] = (float)q[k].wi[2], wo[3 * k + 2] = (float)q[k].wo[2];
  }
  nbrdf_status st = nbrdf_model_decode(fix_model, n, 1, lat, wi, wo, out, err);
  for (size_t k = 0; st == NBRDF_OK && k < n; k++)
    f[k] = out[k];
  free(lat), free(wi), free(out);
  return st;
}

/* Lobe images of one latent, each at verify's θi and azimuth. */
static inline void fix_decoded_images(const float *latent, double *images) {
  nbrdf_error e, *err = &e;
  const size_t per = (size_t)NBRDF_LOBE_RES * NBRDF_LOBE_RES;
  for (int k = 0; k < VERIFY_N_THETA; k++) {
    fix_decode d = {latent, verify_phi_deg[k] * M_PI / 180};
    CHECK_OK(lobe_images(fix_decode_fn, &d, NBRDF_LOBE_RES, 1, &verify_theta_deg[k],
                         images + k * per, err),
             err);
  }
}

/* Ground-truth lobe images of a tuple with `walks` walks per image. */
static inline void fix_reference_images(const float *t, int walks, uint64_t seed, double *images) {
  nbrdf_error e, *err = &e;
  nbrdf_brdf *bottom = NULL, *b = NULL;
  CHECK_OK(nbrdf_brdf_create_conductor(t[NBRDF_BAKE_ALPHA2], t[NBRDF_BAKE_R0], &bottom, err), err);
  CHECK_OK(nbrdf_brdf_create_layered(t[NBRDF_BAKE_ALPHA1], t[NBRDF_BAKE_ETA], t[NBRDF_BAKE_ALBEDO],
                                     t[NBRDF_BAKE_SIGMA_T], bottom, &b, err),
           err);
  nbrdf_brdf_destroy(bottom);
  if (!b) return;
  const size_t per = (size_t)NBRDF_LOBE_RES * NBRDF_LOBE_RES;
  for (int k = 0; k < VERIFY_N_THETA; k++)
    CHECK(brdf_layered_lobe_image(&brdf_handle_bsdf(b)->layered, verify_theta_deg[k] * M_PI / 180,
                                  NBRDF_LOBE_RES, walks, seed * 8 + (uint64_t)k, 0,
                                  images + k * per, NULL));
  nbrdf_brdf_destroy(b);
}

/* Level-0 texel (x, y) of a texture: all channels (caller frees). */
static inline float *fix_read_texel(const char *file, int level, int x, int y) {
  nbrdf_error e, *err = &e;
  texture_latent_reader *r = NULL;
  CHECK_OK(texture_latent_reader_open(&r, file, err), err);
  if (!r) return NULL;
  float *t = malloc(sizeof(float) * texture_latent_reader_info(r)->channels);
  CHECK_OK(texture_latent_reader_read(r, level, x, y, 1, 1, t, err), err);
  texture_latent_reader_close(r);
  return t;
}

#endif
