/* Half or float latents (docs/BAKE.md, "Half or float"): bakes the same maps
 * with both storages and reports what half storage costs in accuracy (the
 * lobe error between the decoded lobes of a half texel and of the same
 * float texel, METRICS.md's definition with the float texel as reference)
 * and what it saves (file size, bake and read time).
 *
 *   examples/make_maps.sh /tmp/maps
 *   bench_bake_half --maps /tmp/maps [--bundle DIR] [--texels N] [--level L]
 *
 * The maps are those of examples/make_maps.sh (alpha1.png eta.exr alpha2.png
 * r0.png albedo.png sigma_t.exr), baked with the CLI's defaults. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "bench_clock.h"
#include "bench_sort.h"
#include "verify/verify_internal.h"
#include "nbrdf/bake.h"
#include "texture/latent_exr.h"

static void inputs(const char *maps, char paths[6][1024], nbrdf_bake_inputs *in) {
  static const char *files[6] = {"alpha1.png", "eta.exr",    "alpha2.png",
                                 "r0.png",     "albedo.png", "sigma_t.exr"};
  nbrdf_bake_inputs d = NBRDF_BAKE_INPUTS_DEFAULT;
  *in = d;
  for (int id = 0; id < 6; id++) {
    snprintf(paths[id], 1024, "%s/%s", maps, files[id]);
    in->param[id].path = paths[id];
  }
  in->param[NBRDF_BAKE_ETA].remap = 1;
  in->param[NBRDF_BAKE_ETA].lo = 1.0f, in->param[NBRDF_BAKE_ETA].hi = 2.0f;
  in->param[NBRDF_BAKE_SIGMA_T].remap = 1;
  in->param[NBRDF_BAKE_SIGMA_T].lo = 0.0f, in->param[NBRDF_BAKE_SIGMA_T].hi = 5.0f;
}

/* Seconds to read every level of `path` whole. */
static double read_all(const char *path, nbrdf_error *err) {
  texture_latent_reader *r = NULL;
  double t0 = bench_wall_seconds();
  if (texture_latent_reader_open(&r, path, err) != NBRDF_OK) return -1;
  const texture_latent_info *info = texture_latent_reader_info(r);
  float *buf = malloc(sizeof(float) * (size_t)info->width * info->height * info->channels);
  for (int l = 0; l < info->levels; l++) {
    int w, h;
    if (texture_latent_reader_level_size(r, l, &w, &h, err) != NBRDF_OK ||
        texture_latent_reader_read(r, l, 0, 0, w, h, buf, err) != NBRDF_OK) {
      free(buf);
      texture_latent_reader_close(r);
      return -1;
    }
  }
  free(buf);
  texture_latent_reader_close(r);
  return bench_wall_seconds() - t0;
}

int main(int argc, char **argv) {
  const char *bundle = "models/default", *maps = NULL;
  int n_texels = 64, level = 0;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!strcmp(argv[i], "--bundle"))
      bundle = argv[i + 1];
    else if (!strcmp(argv[i], "--maps"))
      maps = argv[i + 1];
    else if (!strcmp(argv[i], "--texels"))
      n_texels = atoi(argv[i + 1]);
    else if (!strcmp(argv[i], "--level"))
      level = atoi(argv[i + 1]);
  }
  if (!maps) {
    fprintf(stderr, "usage: bench_bake_half --maps DIR [--bundle DIR] [--texels N] [--level L]\n");
    return 2;
  }
  nbrdf_error err = {0};
  nbrdf_model *model = NULL;
  if (nbrdf_model_load(bundle, &model, &err) != NBRDF_OK) {
    fprintf(stderr, "bench_bake_half: %s\n", err.message);
    return 1;
  }
  char dir[] = "/tmp/bench_bake_half_XXXXXX";
  if (!mkdtemp(dir)) return 1;
  char out[2][1100], paths[6][1024];
  nbrdf_bake_inputs in;
  inputs(maps, paths, &in);
  double bake_wall[2], bake_cpu[2], read_s[2];
  long long size[2];
  for (int s = 0; s < 2; s++) {
    snprintf(out[s], sizeof out[s], "%s/%s.exr", dir, s ? "float" : "half");
    nbrdf_bake_options o = NBRDF_BAKE_OPTIONS_DEFAULT;
    o.storage = s ? NBRDF_BAKE_FLOAT : NBRDF_BAKE_HALF;
    double w0 = bench_wall_seconds(), c0 = bench_cpu_seconds();
    if (nbrdf_bake(model, &in, &o, out[s], NULL, &err) != NBRDF_OK) {
      fprintf(stderr, "bench_bake_half: %s\n", err.message);
      return 1;
    }
    bake_wall[s] = bench_wall_seconds() - w0, bake_cpu[s] = bench_cpu_seconds() - c0;
    struct stat sb;
    size[s] = stat(out[s], &sb) == 0 ? (long long)sb.st_size : -1;
    read_s[s] = read_all(out[s], &err);
  }

  /* Decode the same texels of both files. */
  texture_latent_reader *r[2] = {NULL, NULL};
  for (int s = 0; s < 2; s++)
    if (texture_latent_reader_open(&r[s], out[s], &err) != NBRDF_OK) {
      fprintf(stderr, "bench_bake_half: %s\n", err.message);
      return 1;
    }
  const texture_latent_info *info = texture_latent_reader_info(r[0]);
  const texture_latent_layout *L = &info->layout;
  int w, h, C = texture_latent_colours(L), D = L->latent_dim;
  if (texture_latent_reader_level_size(r[0], level, &w, &h, &err) != NBRDF_OK) {
    fprintf(stderr, "bench_bake_half: %s\n", err.message);
    return 1;
  }
  verify_point *pts = NULL;
  size_t n = verify_select(w, h, n_texels, 1, level, &pts);
  verify_decoder *dec = verify_decoder_create(model);
  float *texel[2] = {malloc(sizeof(float) * info->channels),
                     malloc(sizeof(float) * info->channels)};
  float *lat = malloc(sizeof(float) * D);
  double *img[2] = {malloc(sizeof(double) * VERIFY_SET * C),
                    malloc(sizeof(double) * VERIFY_SET * C)};
  double *errs = malloc(sizeof(double) * n), max_rel_latent = 0;
  double d0 = bench_wall_seconds();
  for (size_t i = 0; i < n; i++) {
    for (int s = 0; s < 2; s++) {
      if (texture_latent_reader_read(r[s], level, pts[i].x, pts[i].y, 1, 1, texel[s], &err) !=
          NBRDF_OK) {
        fprintf(stderr, "bench_bake_half: %s\n", err.message);
        return 1;
      }
      for (int c = 0; c < C; c++) {
        for (int k = 0; k < D; k++)
          lat[k] = texel[s][texture_latent_index_latent(L, c, k)];
        int finite;
        if (verify_decode(dec, lat, img[s] + VERIFY_SET * c, &finite, &err) != NBRDF_OK ||
            !finite) {
          fprintf(stderr, "bench_bake_half: decode failed %s\n", err.message);
          return 1;
        }
      }
    }
    for (int k = 0; k < info->channels; k++) {
      double a = texel[1][k], b = texel[0][k];
      double rel = (b - a) / (a < 0 ? -a : a > 0 ? a : 1);
      rel = rel < 0 ? -rel : rel;
      if (rel > max_rel_latent) max_rel_latent = rel;
    }
    errs[i] = lobe_l1_error(VERIFY_SET * C, img[1], img[0]);
  }
  double dsec = bench_wall_seconds() - d0;
  qsort(errs, n, sizeof *errs, bench_cmp_double);
  char load[128];
  bench_load_line(load, sizeof load);
  printf("bench_bake_half: maps %s, bundle %s, %d x %d %s texture, level %d (%d x %d), %zu "
         "texels\n\n",
         maps, nbrdf_model_name(model), info->width, info->height, C == 3 ? "rgb" : "mono", level,
         w, h, n);
  printf("| quantity | half | float |\n|---|---:|---:|\n");
  printf("| file size (MiB) | %.2f | %.2f |\n", size[0] / 1048576.0, size[1] / 1048576.0);
  printf("| bake wall s (CPU s) | %.2f (%.2f) | %.2f (%.2f) |\n", bake_wall[0], bake_cpu[0],
         bake_wall[1], bake_cpu[1]);
  printf("| read every level, wall s | %.3f | %.3f |\n", read_s[0], read_s[1]);
  printf("\nLobe error of the half texel against the float texel (all colour channels):\n\n");
  printf("| texels | median | p90 | max | max relative latent/proxy change | load |\n");
  printf("|---:|---:|---:|---:|---:|---|\n");
  printf("| %zu | %.4f %% | %.4f %% | %.4f %% | %.2e | %s |\n", n, 100 * errs[n / 2],
         100 * errs[(size_t)(0.9 * (double)(n - 1))], 100 * errs[n - 1], max_rel_latent, load);
  printf("\n(decoding: %.1f s wall for %zu distinct latents)\n", dsec,
         verify_decoder_distinct(dec));
  for (int s = 0; s < 2; s++) {
    texture_latent_reader_close(r[s]);
    unlink(out[s]);
    free(texel[s]), free(img[s]);
  }
  rmdir(dir);
  free(lat), free(errs), free(pts);
  verify_decoder_free(dec);
  nbrdf_model_destroy(model);
  return 0;
}
