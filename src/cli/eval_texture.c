/* nbrdf eval --texture: CSV point queries of a latent texture (eval_texture.h). */
#include "cli/eval_texture.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "cli/cli_device.h"
#include "core/csv_columns.h"
#include "core/vec3.h"
#include "model/model_gpu.h"
#include "texture/latent_fetch.h"

enum { COL_U, COL_V, COL_THETA_I, COL_PHI_I, COL_THETA_O, COL_PHI_O, N_COLS };
/* Rows decoded per call: bounds memory for any number of rows. */
#define CHUNK 4096

/* θ = 90° is excluded: the direction would lie in the surface. */
static const core_csv_column COLUMNS[N_COLS] = {{"u", 0, 1, 0},        {"v", 0, 1, 0},
                                                {"theta_i", 0, 90, 1}, {"phi_i", -360, 360, 0},
                                                {"theta_o", 0, 90, 1}, {"phi_o", -360, 360, 0}};
/* The output's columns, NULL-terminated: an input must not have them already. */
static const char *const OUT_MONO[] = {"f", NULL};
static const char *const OUT_RGB[] = {"f_r", "f_g", "f_b", NULL};

static const core_csv_column *const SPEC[N_COLS] = {&COLUMNS[0], &COLUMNS[1], &COLUMNS[2],
                                                    &COLUMNS[3], &COLUMNS[4], &COLUMNS[5]};

static int find_columns(const core_csv_table *t, const char *input, int colours,
                        size_t index[N_COLS]) {
  nbrdf_error err = {0};
  if (core_csv_columns_find(t, input, SPEC, N_COLS, colours == 3 ? OUT_RGB : OUT_MONO,
                            "--texture needs u,v,theta_i,phi_i,theta_o,phi_o", index, &err))
    return cli_fail_error("eval", &err);
  return CLI_EXIT_OK;
}

static int parse_row(const core_csv_table *t, const char *input, size_t r,
                     const size_t index[N_COLS], double v[N_COLS]) {
  nbrdf_error err = {0};
  if (core_csv_columns_read(t, input, r, SPEC, index, N_COLS, v, &err))
    return cli_fail_error("eval", &err);
  return CLI_EXIT_OK;
}

static void direction(double theta_deg, double phi_deg, float *w) {
  vec3 d = v3_from_spherical(theta_deg * (M_PI / 180.0), phi_deg * (M_PI / 180.0));
  w[0] = (float)d.x, w[1] = (float)d.y, w[2] = (float)d.z;
}

static void write_row(FILE *out, const core_csv_table *t, size_t r) {
  size_t width = core_csv_record_width(t, r);
  for (size_t c = 0; c < width; c++) {
    if (c) fputc(',', out);
    core_csv_write_raw(out, t, r, c);
  }
}

typedef struct buffers {
  float *texel, *lat, *wi, *wo, *f;
} buffers;

/* Parses, fetches and decodes rows [r0, r0 + n) (records r0 + 1 ...) into f. */
static int decode_chunk(const core_csv_table *t, const char *input, const size_t index[N_COLS],
                        const nbrdf_model *model, gpu_network *gpu, const texture_latent_image *img,
                        int level, size_t r0, size_t n, buffers *b) {
  const texture_latent_layout *lay = &img->layout;
  int colours = texture_latent_colours(lay), D = lay->latent_dim;
  for (size_t k = 0; k < n; k++) {
    double v[N_COLS];
    int rc = parse_row(t, input, r0 + k + 1, index, v);
    if (rc != CLI_EXIT_OK) return rc;
    texture_latent_fetch_level(img, level, (float)v[COL_U], (float)v[COL_V], b->texel);
    for (int c = 0; c < colours; c++)
      memcpy(b->lat + (k * colours + c) * D, b->texel + texture_latent_index_latent(lay, c, 0),
             sizeof(float) * (size_t)D);
    direction(v[COL_THETA_I], v[COL_PHI_I], b->wi + 3 * k);
    direction(v[COL_THETA_O], v[COL_PHI_O], b->wo + 3 * k);
  }
  nbrdf_error err = {0};
  if (model_decode_on(model, gpu, n, colours, b->lat, b->wi, b->wo, b->f, &err) != NBRDF_OK)
    return cli_fail("eval", "lines %zu to %zu: %s", t->line[r0 + 1], t->line[r0 + n], err.message);
  return CLI_EXIT_OK;
}

int cli_eval_texture(const cli_eval_texture_options *o, const core_csv_table *t, FILE *out) {
  nbrdf_model *bundle = NULL, *model = NULL;
  int rc = cli_model_load("eval", o->bundle, &bundle, NULL, 0);
  if (rc != CLI_EXIT_OK) return rc;
  nbrdf_error err = {0};
  texture_latent_image *img = NULL;
  /* The texture's own decoder when it carries one: as a renderer decodes it. */
  nbrdf_status st = texture_latent_image_load_model(o->texture, bundle, &img, &model, &err);
  nbrdf_model_destroy(bundle);
  if (st != NBRDF_OK) return cli_fail_error("eval", &err);
  int colours = texture_latent_colours(&img->layout);
  model_gpu *gpu = NULL;
  char note[512];
  if (model_gpu_open(model, NULL, o->device, MODEL_GPU_DECODER, &gpu, note, sizeof note, &err) !=
      NBRDF_OK) {
    texture_latent_image_free(img);
    nbrdf_model_destroy(model);
    return cli_fail_error("eval", &err);
  }
  if (note[0]) cli_device_note("eval", note);
  size_t index[N_COLS];
  buffers b = {0};
  if (o->level >= img->levels)
    rc = cli_level_error("eval", "--level", o->texture, img->levels,
                         o->level_text ? o->level_text : "0");
  if (rc == CLI_EXIT_OK) rc = find_columns(t, o->input, colours, index);
  /* A GPU gets every row in one call (it streams them in its own chunks). */
  size_t n = t->n_records - 1, chunk = n < CHUNK || gpu ? n : CHUNK;
  float *f = NULL;
  if (rc == CLI_EXIT_OK && n > 0) {
    size_t lat = chunk * (size_t)colours * (size_t)img->layout.latent_dim;
    b.texel = malloc(sizeof(float) * (size_t)img->channels);
    b.lat = malloc(sizeof(float) * lat);
    b.wi = malloc(sizeof(float) * 3 * chunk);
    b.wo = malloc(sizeof(float) * 3 * chunk);
    f = malloc(sizeof(float) * n * (size_t)colours);
    if (!b.texel || !b.lat || !b.wi || !b.wo || !f)
      rc = cli_fail("eval", "out of memory for %zu rows", n);
  }
  /* Every row is parsed and decoded before anything is written: a bad row
   * leaves stdout empty, as for the other models. */
  for (size_t r0 = 0; rc == CLI_EXIT_OK && r0 < n; r0 += chunk) {
    b.f = f + r0 * (size_t)colours;
    rc = decode_chunk(t, o->input, index, model, gpu ? gpu->decoder : NULL, img, o->level, r0,
                      n - r0 < chunk ? n - r0 : chunk, &b);
  }
  if (rc == CLI_EXIT_OK) {
    const char *const *outs = colours == 3 ? OUT_RGB : OUT_MONO;
    write_row(out, t, 0);
    for (int c = 0; c < colours; c++)
      fprintf(out, ",%s", outs[c]);
    fputc('\n', out);
    for (size_t k = 0; k < n; k++) {
      write_row(out, t, k + 1);
      for (int c = 0; c < colours; c++)
        fprintf(out, ",%.9g", (double)f[k * colours + c]);
      fputc('\n', out);
    }
    if (fflush(out) != 0 || ferror(out)) rc = cli_fail("eval", "writing stdout failed");
  }
  free(b.texel), free(b.lat), free(b.wi), free(b.wo), free(f);
  model_gpu_close(gpu);
  texture_latent_image_free(img);
  nbrdf_model_destroy(model);
  return rc;
}
