/* A texture verify should pass, and the same texture with damaged latents,
 * which it must fail. An untrained bundle's baked latents are far from the
 * physics, so the passing texture holds a latent fitted to the ground truth
 * itself (nbrdf_model_project with the decoder frozen) in every texel; the
 * damaged one has one texel replaced by the bake's latent of the same
 * parameters, or by a scaled copy of the fitted latent. verify must single
 * out exactly that texel. */
#include "test_verify_fixture.h"

#define W 4
#define H 4

/* The fitted latent: lobe pixels as (ωi, ωo, f) samples of the ground truth. */
static void fitted_latent(float *latent) {
  nbrdf_error e, *err = &e;
  double *img = malloc(sizeof(double) * FIX_SET);
  fix_reference_images(fix_tuple, 256, 31, img);
  size_t n = 0, per = (size_t)NBRDF_LOBE_RES * NBRDF_LOBE_RES;
  float *wi = malloc(sizeof(float) * FIX_SET * 7), *wo = wi + 3 * FIX_SET, *f = wo + 3 * FIX_SET;
  for (int t = 0; t < VERIFY_N_THETA; t++) {
    double th = verify_theta_deg[t] * M_PI / 180, phi = verify_phi_deg[t] * M_PI / 180;
    double c = cos(phi), s = sin(phi);
    for (size_t p = 0; p < per; p++) {
      double o[3];
      if (!lobe_pixel_wo(NBRDF_LOBE_RES, (int)(p / NBRDF_LOBE_RES), (int)(p % NBRDF_LOBE_RES), o))
        continue;
      /* At verify's azimuth of the image: the latent is fitted where verify asks. */
      wi[3 * n] = (float)(c * sin(th)), wi[3 * n + 1] = (float)(s * sin(th));
      wi[3 * n + 2] = (float)cos(th);
      wo[3 * n] = (float)(c * o[0] - s * o[1]), wo[3 * n + 1] = (float)(s * o[0] + c * o[1]);
      wo[3 * n + 2] = (float)o[2];
      f[n++] = (float)(img[t * per + p] / o[2]);
    }
  }
  size_t offsets[2] = {0, n};
  nbrdf_project_options po = NBRDF_PROJECT_OPTIONS_DEFAULT;
  po.steps = 400;
  po.rows_per_brdf = 512;
  po.learning_rate = 3e-2f;
  po.seed = 3;
  CHECK_OK(nbrdf_model_project(fix_model, 1, offsets, wi, wo, f, &po, latent, NULL, err), err);
  free(wi);
  free(img);
}

static nbrdf_status write_texture(const char *file, const float *texels, nbrdf_error *err) {
  texture_latent_layout L = {nbrdf_model_latent_dim(fix_model), NBRDF_COLOUR_MONO, 1};
  texture_latent_meta meta = {nbrdf_model_name(fix_model), nbrdf_model_checksum(fix_model), "test",
                            "roughness=alpha", NULL, 0, NULL, NULL};
  texture_latent_exr_options o = NBRDF_LATENT_EXR_OPTIONS_DEFAULT;
  o.storage = NBRDF_LATENT_FLOAT;
  o.mip_levels = 1;
  texture_latent_writer *w = NULL;
  nbrdf_status st = texture_latent_writer_create(&w, file, W, H, &L, &meta, &o, NULL, 0, err);
  if (st == NBRDF_OK) st = texture_latent_writer_write_rows(w, texels, H, err);
  if (st == NBRDF_OK) return texture_latent_writer_finish(w, err);
  texture_latent_writer_abort(w);
  return st;
}

static const nbrdf_verify_texel *worst(const nbrdf_verify_report *r) {
  const nbrdf_verify_texel *w = &r->texels[0];
  for (size_t i = 1; i < r->n_texels; i++)
    if (r->texels[i].lobe_error > w->lobe_error) w = &r->texels[i];
  return w;
}

static void test_fitted_passes_damaged_fails(void) {
  nbrdf_error e, *err = &e;
  const int D = nbrdf_model_latent_dim(fix_model), C = D + 2;
  float *fit = malloc(sizeof(float) * D), *tex = malloc(sizeof(float) * W * H * C);
  fitted_latent(fit);
  for (int i = 0; i < W * H; i++) {
    memcpy(tex + i * C, fit, sizeof(float) * D);
    tex[i * C + D] = 0.2f, tex[i * C + D + 1] = 0.5f; /* proxy: unused by verify */
  }
  CHECK_OK(write_texture(fix_path("fit.exr"), tex, err), err);
  nbrdf_bake_inputs in = fix_constants();
  nbrdf_verify_options o = NBRDF_VERIFY_OPTIONS_DEFAULT;
  o.walks = 64;
  nbrdf_verify_report *good = NULL;
  CHECK_OK(nbrdf_verify(fix_model, fix_path("fit.exr"), &in, &o, &good, err), err);
  if (!good) return;
  /* The threshold a pipeline would gate on: what the fitted latent reaches. */
  const double gate = 1.2 * good->overall.worst;
  CHECK(good->n_texels == W * H && good->overall.median == good->overall.worst);

  /* The bake's latent for these parameters: the untrained layering network
   * lands far from the fit. */
  nbrdf_bake_options bo = NBRDF_BAKE_OPTIONS_DEFAULT;
  bo.storage = NBRDF_BAKE_FLOAT;
  CHECK_OK(nbrdf_bake(fix_model, &in, &bo, fix_path("baked.exr"), NULL, err), err);
  float *baked = fix_read_texel(fix_path("baked.exr"), 0, 0, 0);
  nbrdf_verify_report *b = NULL;
  CHECK_OK(nbrdf_verify(fix_model, fix_path("baked.exr"), &in, &o, &b, err), err);
  printf("  fitted latent: lobe error %.2f %% (reference noise %.2f %%); baked: %.2f %%\n",
         100 * good->overall.worst, 100 * good->overall.noise_median,
         b ? 100 * b->overall.worst : NAN);
  CHECK_MSG(b && b->overall.worst > 2 * gate, "the fit (%g) is not better than the bake (%g)",
            good->overall.worst, b ? b->overall.worst : NAN);
  nbrdf_verify_report_free(b);

  /* Damage: texel (2, 1) gets the baked latent, texel (0, 3) the fit x 3. */
  memcpy(tex + (1 * W + 2) * C, baked, sizeof(float) * D);
  for (int k = 0; k < D; k++)
    tex[(3 * W + 0) * C + k] = 3 * fit[k];
  CHECK_OK(write_texture(fix_path("damaged.exr"), tex, err), err);
  nbrdf_verify_report *bad = NULL;
  CHECK_OK(nbrdf_verify(fix_model, fix_path("damaged.exr"), &in, &o, &bad, err), err);
  if (bad) {
    int over = 0;
    for (size_t i = 0; i < bad->n_texels; i++) {
      const nbrdf_verify_texel *t = &bad->texels[i];
      int damaged = (t->x == 2 && t->y == 1) || (t->x == 0 && t->y == 3);
      over += t->lobe_error > gate;
      CHECK_MSG(damaged == (t->lobe_error > gate), "texel (%d, %d): %g vs gate %g", t->x, t->y,
                t->lobe_error, gate);
    }
    CHECK(over == 2 && bad->overall.worst > gate && bad->overall.median <= gate);
    CHECK(worst(bad)->x == 2 || worst(bad)->y == 3);
  }
  nbrdf_verify_report_free(bad);
  nbrdf_verify_report_free(good);
  free(baked);
  free(fit);
  free(tex);
}

int main(void) {
  fix_load_model();
  if (!fix_model) return testing_finish();
  RUN(test_fitted_passes_damaged_fails);
  nbrdf_model_destroy(fix_model);
  return testing_finish();
}
