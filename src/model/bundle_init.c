/* `nbrdf bundle init`: a complete bundle of randomly initialised networks, so
 * that everything downstream of the model can be built and tested before the
 * trained bundle exists. */
#include <math.h>
#include <stdlib.h>

#include "core/error.h"
#include "core/rng.h"
#include "model/bundle.h"

#define INIT_LATENT_DIM 32
#define INIT_ALPHA_NODES 12
#define INIT_ETA_NODES 8
#define INIT_R0_NODES 8

/* Smooth random latents: z_j(u, v) = c0 + c1 u + c2 v + c3 u v over the
 * normalised grid coordinates, so that neighbouring parameters give
 * neighbouring latents (as a trained table does) and baked maps show their
 * structure. Coefficients N(0, 0.5²) from PCG32 stream `stream`. */
static void fill_smooth(model_base_table *t, uint64_t seed, uint64_t stream) {
  core_rng rng;
  core_rng_init(&rng, seed, stream);
  for (int j = 0; j < t->dim; j++) {
    double c[4];
    for (int q = 0; q < 4; q++)
      c[q] = 0.5 * core_rng_normal(&rng);
    for (int a = 0; a < t->n[0]; a++) {
      double u = (double)a / (t->n[0] - 1);
      for (int b = 0; b < t->n[1]; b++) {
        double v = (double)b / (t->n[1] - 1);
        t->latents[((size_t)a * t->n[1] + b) * t->dim + j] =
            (float)(c[0] + c[1] * u + c[2] * v + c[3] * u * v);
      }
    }
  }
}

static void linspace(float *x, int n, double lo, double hi) {
  for (int i = 0; i < n; i++)
    x[i] = (float)(lo + (hi - lo) * i / (n - 1));
}

nbrdf_status model_bundle_init_random(const char *dir, const char *name, uint64_t seed,
                                      const char *decoder_preset, nbrdf_error *err) {
  /* α nodes follow the paper's Table 2 sampling α = u³, u ∈ [0.216, 1]: dense where
   * lobes change fastest (small α). */
  float alpha[INIT_ALPHA_NODES], eta[INIT_ETA_NODES], r0[INIT_R0_NODES];
  for (int i = 0; i < INIT_ALPHA_NODES; i++) {
    double u = 0.216 + (1.0 - 0.216) * i / (INIT_ALPHA_NODES - 1);
    alpha[i] = (float)(u * u * u);
  }
  alpha[0] = 0.01f, alpha[INIT_ALPHA_NODES - 1] = 1.0f;
  linspace(eta, INIT_ETA_NODES, 1.05, 2.0);
  linspace(r0, INIT_R0_NODES, 0.0, 1.0);

  model_decoder_config cfg;
  model_decoder *dec = NULL;
  model_layering *lay = NULL;
  model_sampler *smp = NULL;
  model_base_table tables[2] = {{0}, {0}};
  nbrdf_status st = model_decoder_preset(decoder_preset, INIT_LATENT_DIM, &cfg, err);
  /* One seed, distinct derived seeds per part: the parts stay independent. */
  if (st == NBRDF_OK) st = model_decoder_create(&cfg, core_hash64(seed, 1), &dec, err);
  if (st == NBRDF_OK)
    st = model_layering_create("paper", INIT_LATENT_DIM, core_hash64(seed, 2), &lay, err);
  if (st == NBRDF_OK)
    st = model_sampler_create("default", INIT_LATENT_DIM, core_hash64(seed, 3), &smp, err);
  if (st == NBRDF_OK)
    st = model_base_table_init(&tables[0], MODEL_TABLE_DIELECTRIC, INIT_LATENT_DIM,
                               INIT_ALPHA_NODES, alpha, INIT_ETA_NODES, eta, err);
  if (st == NBRDF_OK)
    st = model_base_table_init(&tables[1], MODEL_TABLE_CONDUCTOR, INIT_LATENT_DIM, INIT_ALPHA_NODES,
                               alpha, INIT_R0_NODES, r0, err);
  if (st == NBRDF_OK) {
    fill_smooth(&tables[0], core_hash64(seed, 4), 0);
    fill_smooth(&tables[1], core_hash64(seed, 4), 1);
    model_bundle_parts parts = {
        .name = name,
        .trained = 0,
        .seed = seed,
        .note = "UNTRAINED: random initial weights; values are meaningless (nbrdf bundle init)",
        .card = NULL,
        .decoder = dec,
        .layering = lay,
        .sampler = smp,
        .tables = {&tables[0], &tables[1]},
    };
    st = model_bundle_save(dir, &parts, NULL, err);
  }
  model_decoder_destroy(dec);
  model_layering_destroy(lay);
  model_sampler_destroy(smp);
  model_base_table_free(&tables[0]);
  model_base_table_free(&tables[1]);
  return st;
}
