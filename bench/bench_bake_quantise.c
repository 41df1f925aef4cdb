/* Parameter quantisation (docs/BAKE.md, "Quantisation"): bakes smoothly
 * varying float maps (every texel distinct) unquantised and with
 * nbrdf_bake_options.quantise_bits = 12, 10, 8, 6, 4, and reports the
 * distinct tuples evaluated, the bake time, and the lobe error each
 * quantised texel adds against the unquantised one (METRICS.md lobe error
 * of the decoded lobes, all colour channels together). Float storage
 * throughout, so that half rounding does not mix in.
 *
 *   bench_bake_quantise [--bundle DIR] [--size N] [--texels T] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bench_clock.h"
#include "bench_sort.h"
#include "verify/verify_internal.h"
#include "nbrdf/bake.h"
#include "texture/latent_exr.h"
#include "texture/oiio_shim.h"

/* Smooth float maps: every texel's tuple distinct, values spread over the
 * trained ranges. */
static int write_maps(const char *dir, int n, char paths[6][1024], nbrdf_error *err) {
  static const char *names[6] = {"alpha1", "eta", "alpha2", "r0", "albedo", "sigma_t"};
  for (int id = 0; id < 6; id++) {
    int ch = id == NBRDF_BAKE_R0 || id == NBRDF_BAKE_ALBEDO ? 3 : 1;
    float *px = malloc(sizeof(float) * (size_t)n * n * ch);
    for (int y = 0; y < n; y++)
      for (int x = 0; x < n; x++)
        for (int c = 0; c < ch; c++) {
          double u = (x + 0.5) / n, v = (y + 0.5) / n, s = sin(6.0 * u + 4.0 * v + c);
          double val = 0;
          switch (id) {
          case NBRDF_BAKE_ALPHA1:
            val = 0.02 + 0.8 * u * u;
            break;
          case NBRDF_BAKE_ETA:
            val = 1.1 + 0.8 * v;
            break;
          case NBRDF_BAKE_ALPHA2:
            val = 0.05 + 0.5 * (0.5 + 0.5 * sin(5.0 * v + 3.0 * u));
            break;
          case NBRDF_BAKE_R0:
            val = 0.5 + 0.45 * s;
            break;
          case NBRDF_BAKE_ALBEDO:
            val = 0.55 + 0.4 * cos(3.0 * u - 5.0 * v + c);
            break;
          default:
            val = 2.5 + 2.5 * sin(7.0 * u * v + 1.0);
            break;
          }
          px[((size_t)y * n + x) * ch + c] = (float)val;
        }
    snprintf(paths[id], 1024, "%s/%s.exr", dir, names[id]);
    nbrdf_status st = texture_image_write(paths[id], n, n, ch, px, NBRDF_PIXEL_FLOAT, err);
    free(px);
    if (st != NBRDF_OK) return 0;
  }
  return 1;
}

/* Decoded lobe images of texel p of `r`, all colour channels (C sets). */
static int decode_texel(texture_latent_reader *r, verify_decoder *dec, verify_point p, float *texel,
                        float *lat, double *img, nbrdf_error *err) {
  const texture_latent_layout *L = &texture_latent_reader_info(r)->layout;
  if (texture_latent_reader_read(r, 0, p.x, p.y, 1, 1, texel, err) != NBRDF_OK) return 0;
  for (int c = 0; c < texture_latent_colours(L); c++) {
    for (int k = 0; k < L->latent_dim; k++)
      lat[k] = texel[texture_latent_index_latent(L, c, k)];
    int finite;
    if (verify_decode(dec, lat, img + VERIFY_SET * c, &finite, err) != NBRDF_OK || !finite)
      return 0;
  }
  return 1;
}

int main(int argc, char **argv) {
  const char *bundle = "models/default";
  int n = 512, n_texels = 32;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!strcmp(argv[i], "--bundle"))
      bundle = argv[i + 1];
    else if (!strcmp(argv[i], "--size"))
      n = atoi(argv[i + 1]);
    else if (!strcmp(argv[i], "--texels"))
      n_texels = atoi(argv[i + 1]);
  }
  nbrdf_error err = {0};
  nbrdf_model *model = NULL;
  char dir[] = "/tmp/bench_bake_quantise_XXXXXX", paths[6][1024];
  if (nbrdf_model_load(bundle, &model, &err) != NBRDF_OK || !mkdtemp(dir) ||
      !write_maps(dir, n, paths, &err)) {
    fprintf(stderr, "bench_bake_quantise: %s\n", err.message);
    return 1;
  }
  nbrdf_bake_inputs in = NBRDF_BAKE_INPUTS_DEFAULT;
  for (int id = 0; id < 6; id++)
    in.param[id].path = paths[id];
  static const int bits[] = {0, 12, 10, 8, 6, 4};
  const int n_bits = (int)(sizeof bits / sizeof *bits);
  char out[6][1100];
  verify_point *pts = NULL;
  size_t np = verify_select(n, n, n_texels, 3, 0, &pts);
  verify_decoder *dec = verify_decoder_create(model);
  float *texel = malloc(sizeof(float) * 1024), *lat = malloc(sizeof(float) * 1024);
  double *ref = malloc(sizeof(double) * VERIFY_SET * 3 * np),
         *img = malloc(sizeof(double) * VERIFY_SET * 3);
  double *errs = malloc(sizeof(double) * np);
  printf("bench_bake_quantise: %d x %d RGB smooth float maps (every tuple distinct), bundle %s, "
         "%zu texels compared, float storage\n\n",
         n, n, nbrdf_model_name(model), np);
  printf("| quantise | evaluated | of BRDFs | bake wall s | bake CPU s | lobe error median | p90 | "
         "max | load |\n");
  printf("|---|---:|---:|---:|---:|---:|---:|---:|---|\n");
  for (int b = 0; b < n_bits; b++) {
    snprintf(out[b], sizeof out[b], "%s/q%d.exr", dir, bits[b]);
    nbrdf_bake_options o = NBRDF_BAKE_OPTIONS_DEFAULT;
    o.storage = NBRDF_BAKE_FLOAT;
    o.mip_levels = 1;
    o.quantise_bits = bits[b];
    nbrdf_bake_report rep;
    double w0 = bench_wall_seconds(), c0 = bench_cpu_seconds();
    if (nbrdf_bake(model, &in, &o, out[b], &rep, &err) != NBRDF_OK) {
      fprintf(stderr, "bench_bake_quantise: %s\n", err.message);
      return 1;
    }
    double bw = bench_wall_seconds() - w0, bc = bench_cpu_seconds() - c0;
    texture_latent_reader *r = NULL;
    if (texture_latent_reader_open(&r, out[b], &err) != NBRDF_OK) return 1;
    int C = texture_latent_colours(&texture_latent_reader_info(r)->layout);
    for (size_t i = 0; i < np; i++) {
      double *dst = b == 0 ? ref + VERIFY_SET * 3 * i : img;
      if (!decode_texel(r, dec, pts[i], texel, lat, dst, &err)) {
        fprintf(stderr, "bench_bake_quantise: decode: %s\n", err.message);
        return 1;
      }
      errs[i] = b == 0 ? 0 : lobe_l1_error(VERIFY_SET * C, ref + VERIFY_SET * 3 * i, img);
    }
    texture_latent_reader_close(r);
    qsort(errs, np, sizeof *errs, bench_cmp_double);
    char load[128];
    bench_load_line(load, sizeof load);
    char name[16];
    snprintf(name, sizeof name, bits[b] ? "%d bits" : "off", bits[b]);
    printf("| %s | %zu | %.1f %% | %.1f | %.1f | %.3f %% | %.3f %% | %.3f %% | %s |\n", name,
           rep.evaluated, 100.0 * (double)rep.evaluated / (double)rep.brdfs, bw, bc,
           100 * errs[np / 2], 100 * errs[(size_t)(0.9 * (double)(np - 1))], 100 * errs[np - 1],
           load);
    fflush(stdout);
  }
  for (int b = 0; b < n_bits; b++)
    unlink(out[b]);
  for (int id = 0; id < 6; id++)
    unlink(paths[id]);
  rmdir(dir);
  free(pts), free(texel), free(lat), free(ref), free(img), free(errs);
  verify_decoder_free(dec);
  nbrdf_model_destroy(model);
  return 0;
}
