/* nbrdf_verify on textures baked from an untrained bundle: its figures equal
 * an independent computation (decoded lobe images by lobe_images, the
 * ground truth with other seeds), mip texels are compared with the mean of
 * their footprint's references, and a texture of another bundle, missing or
 * mismatched inputs and bad options are refused with a message. */
#include "test_verify_fixture.h"
#include "texture/oiio_shim.h"

static nbrdf_verify_report *run(const char *file, const nbrdf_bake_inputs *in,
                                const nbrdf_verify_options *o) {
  nbrdf_error e, *err = &e;
  nbrdf_verify_report *rep = NULL;
  CHECK_OK(nbrdf_verify(fix_model, file, in, o, &rep, err), err);
  return rep;
}

/* A constant bake (a 1 x 1 texture): verify's lobe error, albedo error and
 * reference noise against the same quantities computed here. */
static void test_figures_match_independent_computation(void) {
  nbrdf_error e, *err = &e;
  nbrdf_bake_inputs in = fix_constants();
  nbrdf_bake_options bo = NBRDF_BAKE_OPTIONS_DEFAULT;
  bo.storage = NBRDF_BAKE_FLOAT;
  CHECK_OK(nbrdf_bake(fix_model, &in, &bo, fix_path("const.exr"), NULL, err), err);
  nbrdf_verify_options o = NBRDF_VERIFY_OPTIONS_DEFAULT;
  o.walks = 128;
  nbrdf_verify_report *rep = run(fix_path("const.exr"), &in, &o);
  if (!rep) return;
  CHECK(rep->n_texels == 1 && rep->texels[0].footprint == 1 && rep->references == 1);
  CHECK(rep->decoded == 1 && rep->colours == 1 && rep->n_levels == 1);
  CHECK(rep->decoder_queries == VERIFY_N_THETA * lobe_pixels_inside(NBRDF_LOBE_RES));
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++)
    CHECK(rep->texels[0].params[id][0] == fix_tuple[id]);

  float *texel = fix_read_texel(fix_path("const.exr"), 0, 0, 0);
  double *a = malloc(sizeof(double) * FIX_SET * 4), *r1 = a + FIX_SET, *r2 = r1 + FIX_SET;
  double *ref = r2 + FIX_SET;
  fix_decoded_images(texel, a); /* logical order: the latent comes first */
  fix_reference_images(fix_tuple, 256, 101, r1);
  fix_reference_images(fix_tuple, 256, 102, r2);
  for (size_t i = 0; i < FIX_SET; i++)
    ref[i] = 0.5 * (r1[i] + r2[i]);
  double lobe = lobe_l1_error(FIX_SET, ref, a);
  double albedo = lobe_albedo_error(NBRDF_LOBE_RES, VERIFY_N_THETA, ref, a, NULL);
  /* Both references are noisy (verify's: 2 x 128 walks, a few %); the
   * untrained decoder is far off, so the noise moves the error little. */
  const nbrdf_verify_texel *t = &rep->texels[0];
  CHECK_REL(t->lobe_error, lobe, 0.05, 0);
  CHECK_REL(t->albedo_error, albedo, 0.05, 1e-3);
  /* Seed-to-seed noise at 128 walks vs 256 walks: of the same size (it
   * falls more slowly than 1/sqrt(walks) at these counts: rare bright walks). */
  double noise256 = lobe_l1_error(FIX_SET, r1, r2);
  CHECK_MSG(t->reference_noise > 0.8 * noise256 && t->reference_noise < 2.5 * noise256,
            "noise %g at 128 walks, %g at 256", t->reference_noise, noise256);
  CHECK(rep->overall.median == t->lobe_error && rep->overall.worst == t->lobe_error);
  printf("  lobe error %.2f %% (independent %.2f %%), noise %.2f %% (256 walks: %.2f %%)\n",
         100 * t->lobe_error, 100 * lobe, 100 * t->reference_noise, 100 * noise256);
  free(a);
  free(texel);
  nbrdf_verify_report_free(rep);
}

/* A 4 x 4 map, alpha1 0.1 on the left half and 0.5 on the right: level 1
 * texels see one value, the level 2 texel the mean of both references. */
static void test_mip_footprints(void) {
  nbrdf_error e, *err = &e;
  float px[16];
  for (int i = 0; i < 16; i++)
    px[i] = i % 4 < 2 ? 0.1f : 0.5f;
  CHECK_OK(texture_image_write(fix_path("alpha1.exr"), 4, 4, 1, px, NBRDF_PIXEL_FLOAT, err), err);
  nbrdf_bake_inputs in = fix_constants();
  static char map_path[640];
  snprintf(map_path, sizeof map_path, "%s", fix_path("alpha1.exr"));
  in.param[NBRDF_BAKE_ALPHA1].path = map_path;
  CHECK_OK(nbrdf_bake(fix_model, &in, NULL, fix_path("mips.exr"), NULL, err), err);
  nbrdf_verify_options o = NBRDF_VERIFY_OPTIONS_DEFAULT;
  o.walks = 16;
  o.level = NBRDF_VERIFY_ALL_LEVELS;
  nbrdf_verify_report *rep = run(fix_path("mips.exr"), &in, &o);
  if (!rep) return;
  CHECK(rep->levels == 3 && rep->n_levels == 3 && rep->n_texels == 16 + 4 + 1);
  CHECK(rep->references == 2); /* one per distinct tuple, shared by every level */
  for (size_t i = 0; i < rep->n_texels; i++) {
    const nbrdf_verify_texel *t = &rep->texels[i];
    CHECK(t->footprint == 1 << (2 * t->level));
    double want = t->level == 2 ? 0.3 : t->x << t->level < 2 ? 0.1 : 0.5;
    CHECK_NEAR(t->params[NBRDF_BAKE_ALPHA1][0], want, 1e-6);
    CHECK(isfinite(t->lobe_error) && t->lobe_error > 0 && t->reference_noise > 0);
  }
  CHECK(rep->per_level[2].level == 2 && rep->per_level[2].texels == 1);
  CHECK(rep->overall.texels == 21 && rep->overall.median <= rep->overall.p90);
  CHECK(rep->overall.p90 <= rep->overall.worst);

  /* The level-2 texel's figure from the mean of the two references here. */
  float *texel = fix_read_texel(fix_path("mips.exr"), 2, 0, 0);
  double *a = malloc(sizeof(double) * FIX_SET * 3), *left = a + FIX_SET, *right = left + FIX_SET;
  fix_decoded_images(texel, a);
  float tl[6], tr[6];
  memcpy(tl, fix_tuple, sizeof tl), memcpy(tr, fix_tuple, sizeof tr);
  tl[NBRDF_BAKE_ALPHA1] = 0.1f, tr[NBRDF_BAKE_ALPHA1] = 0.5f;
  fix_reference_images(tl, 256, 7, left);
  fix_reference_images(tr, 256, 8, right);
  for (size_t i = 0; i < FIX_SET; i++)
    left[i] = 0.5 * (left[i] + right[i]);
  CHECK_REL(rep->texels[20].lobe_error, lobe_l1_error(FIX_SET, left, a), 0.1, 0);
  free(a);
  free(texel);

  /* A stratified sample: 3 texels of level 0, distinct and in range. */
  o.level = 0, o.texels = 3;
  nbrdf_verify_report *few = run(fix_path("mips.exr"), &in, &o);
  if (few) {
    CHECK(few->n_texels <= 3 && few->n_texels >= 2);
    for (size_t i = 0; i < few->n_texels; i++)
      for (size_t j = 0; j < i; j++)
        CHECK(few->texels[i].x != few->texels[j].x || few->texels[i].y != few->texels[j].y);
  }
  nbrdf_verify_report_free(few);
  nbrdf_verify_report_free(rep);
}

static void test_refusals(void) {
  nbrdf_error e, *err = &e;
  nbrdf_bake_inputs in = fix_constants();
  nbrdf_verify_report *rep = NULL;
  nbrdf_model *other = NULL;
  CHECK_OK(model_bundle_init_random(fix_path("other"), "verify-test", 6, "small", err), err);
  CHECK_OK(nbrdf_model_load(fix_path("other"), &other, err), err);
  CHECK_FAILS(nbrdf_verify(other, fix_path("const.exr"), &in, NULL, &rep, err), NBRDF_ERR_MISMATCH,
              err, "checksum");
  CHECK(rep == NULL);
  nbrdf_model_destroy(other);
  /* RGB inputs for a mono texture; a map of another size. */
  nbrdf_bake_inputs rgb = fix_constants();
  rgb.param[NBRDF_BAKE_R0].channels = 3;
  CHECK_FAILS(nbrdf_verify(fix_model, fix_path("const.exr"), &rgb, NULL, &rep, err),
              NBRDF_ERR_MISMATCH, err, "mono");
  nbrdf_bake_inputs map = fix_constants();
  char map_path[640];
  snprintf(map_path, sizeof map_path, "%s", fix_path("alpha1.exr"));
  map.param[NBRDF_BAKE_ALPHA1].path = map_path;
  CHECK_FAILS(nbrdf_verify(fix_model, fix_path("const.exr"), &map, NULL, &rep, err),
              NBRDF_ERR_MISMATCH, err,
              "resampled to one size only when asked"); /* the map is not the texture's size */
  CHECK_FAILS(nbrdf_verify(fix_model, fix_path("missing.exr"), &in, NULL, &rep, err), NBRDF_ERR_IO,
              err, "missing.exr");
  nbrdf_verify_options o = NBRDF_VERIFY_OPTIONS_DEFAULT;
  o.level = 3;
  CHECK_FAILS(nbrdf_verify(fix_model, fix_path("mips.exr"), &in, &o, &rep, err), NBRDF_ERR_ARGUMENT,
              err, "no level 3");
  o.level = 0, o.walks = 0;
  CHECK_FAILS(nbrdf_verify(fix_model, fix_path("mips.exr"), &in, &o, &rep, err), NBRDF_ERR_ARGUMENT,
              err, "walks");
  CHECK(rep == NULL);
}

/* A texture whose settings name a roughness convention this build does not
 * know is refused, naming the file and the value: guessing alpha would compare
 * against another BRDF. */
static void test_unknown_roughness_setting(void) {
  nbrdf_error e, *err = &e;
  nbrdf_bake_inputs in = fix_constants();
  nbrdf_verify_report *rep = NULL;
  FILE *f = fopen(fix_path("const.exr"), "rb");
  CHECK(f != NULL);
  if (!f) return;
  static char bytes[1 << 20];
  size_t n = fread(bytes, 1, sizeof bytes, f);
  fclose(f);
  char *at = NULL;
  for (size_t k = 0; k + 15 <= n && !at; k++)
    if (!memcmp(bytes + k, "roughness=alpha", 15)) at = bytes + k;
  CHECK(at != NULL);
  if (!at) return;
  at[14] = 'z'; /* same length: the header's offsets stay valid */
  f = fopen(fix_path("odd-roughness.exr"), "wb");
  CHECK(f && fwrite(bytes, 1, n, f) == n);
  if (f) fclose(f);
  CHECK_FAILS(nbrdf_verify(fix_model, fix_path("odd-roughness.exr"), &in, NULL, &rep, err),
              NBRDF_ERR_FORMAT, err, "odd-roughness.exr: its bake settings have roughness=alphz");
  CHECK(rep == NULL);
}

static int cancel_at_two(void *user, const char *stage, double done, double total) {
  (void)stage, (void)total;
  ++*(int *)user;
  return done >= 2;
}

static void test_cancel_and_outputs(void) {
  nbrdf_error e, *err = &e;
  nbrdf_bake_inputs in = fix_constants();
  static char map_path[640];
  snprintf(map_path, sizeof map_path, "%s", fix_path("alpha1.exr"));
  in.param[NBRDF_BAKE_ALPHA1].path = map_path;
  nbrdf_verify_options o = NBRDF_VERIFY_OPTIONS_DEFAULT;
  o.walks = 8;
  int calls = 0;
  o.progress = cancel_at_two, o.user = &calls;
  nbrdf_verify_report *rep = NULL;
  CHECK_FAILS(nbrdf_verify(fix_model, fix_path("mips.exr"), &in, &o, &rep, err),
              NBRDF_ERR_CANCELLED, err, "cancelled");
  CHECK(rep == NULL && calls >= 1); /* calls are throttled to ~10 a second */
  o.progress = NULL;
  rep = run(fix_path("mips.exr"), &in, &o);
  if (!rep) return;
  CHECK_OK(nbrdf_verify_write_json(rep, "mips.exr", 2, fix_path("v.json"), err), err);
  FILE *f = fopen(fix_path("v.json"), "r");
  char text[8192] = "";
  if (f) {
    size_t n = fread(text, 1, sizeof text - 1, f);
    text[n] = '\0';
    fclose(f);
  }
  CHECK(strstr(text, "\"lobe_error_median_pct\"") && strstr(text, "\"reference_noise_pct\""));
  CHECK(strstr(text, "\"alpha1\":\t0.5") || strstr(text, "\"alpha1\":\t0.1"));
  int listed = 0;
  for (const char *p = text; (p = strstr(p, "\"footprint\"")); p++)
    listed++;
  CHECK(listed == 2);
  CHECK_OK(nbrdf_verify_write_heatmap(rep, 0, 0.0, fix_path("h.png"), err), err);
  int w = 0, h = 0;
  CHECK(testing_png_size(fix_path("h.png"), &w, &h) && w == 256 && h == 256);
  CHECK_FAILS(nbrdf_verify_write_heatmap(rep, 5, 0.0, fix_path("h5.png"), err), NBRDF_ERR_ARGUMENT,
              err, "level 5");
  nbrdf_verify_report_free(rep);
}

int main(void) {
  fix_load_model();
  if (!fix_model) return testing_finish();
  RUN(test_figures_match_independent_computation);
  RUN(test_mip_footprints);
  RUN(test_refusals);
  RUN(test_unknown_roughness_setting);
  RUN(test_cancel_and_outputs);
  nbrdf_model_destroy(fix_model);
  return testing_finish();
}
