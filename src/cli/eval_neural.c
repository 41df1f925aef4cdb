#include "cli/eval_neural.h"

#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "cli/cli.h"
#include "nbrdf/model.h"

/* Trained σT values are {0, 1, 2, 5} (paper Table 2). */
#define SIGMA_T_TRAINED_MAX 5.0

static void warn_clamped(size_t line, const char *const names[2], unsigned char flags) {
  for (int a = 0; a < 2; a++)
    if (flags & (1u << a))
      fprintf(stderr, "nbrdf eval: warning: line %zu: %s outside the bundle's table, clamped\n",
              line, names[a]);
}

int eval_neural(const char *bundle, eval_neural_kind kind, size_t n, const double *params,
                const nbrdf_query *q, const size_t *lines, double *f) {
  struct stat sb;
  if (!bundle) {
    if (stat("models/default", &sb) != 0 || !S_ISDIR(sb.st_mode))
      return cli_fail("eval", "no models/default bundle here; pass --bundle DIR");
    bundle = "models/default";
  }
  nbrdf_error err = {0};
  nbrdf_model *m = NULL;
  if (nbrdf_model_load(bundle, &m, &err) != NBRDF_OK) return cli_fail_error("eval", &err);
  if (!nbrdf_model_is_trained(m))
    fprintf(stderr, "nbrdf eval: warning: bundle '%s' is untrained (random networks)\n", bundle);
  int D = nbrdf_model_latent_dim(m), np = kind == EVAL_NEURAL_LAYERED ? 6 : 2;
  float *top = malloc(n * (size_t)D * sizeof *top), *bottom = malloc(n * (size_t)D * sizeof *top);
  float *lat = malloc(n * (size_t)D * sizeof *lat), *a = malloc(n * sizeof *a);
  float *s = malloc(n * sizeof *s), *wi = malloc(6 * n * sizeof *wi),
        *out = malloc(n * sizeof *out);
  double *p0 = malloc(4 * n * sizeof *p0);
  unsigned char *c0 = malloc(2 * n);
  int rc = CLI_EXIT_OK;
  if (!top || !bottom || !lat || !a || !s || !wi || !out || !p0 || !c0)
    rc = cli_fail("eval", "out of memory for %zu rows", n);
  double *p1 = p0 + n, *p2 = p0 + 2 * n, *p3 = p0 + 3 * n;
  unsigned char *c1 = c0 + n;
  for (size_t k = 0; k < n && rc == CLI_EXIT_OK; k++) {
    const double *v = params + k * (size_t)np;
    p0[k] = v[0], p1[k] = v[1];
    if (kind == EVAL_NEURAL_LAYERED) {
      p2[k] = v[2], p3[k] = v[3], a[k] = (float)v[4], s[k] = (float)v[5];
      if (v[5] > SIGMA_T_TRAINED_MAX)
        fprintf(stderr, "nbrdf eval: warning: line %zu: sigma_t %g beyond the trained 0..5\n",
                lines[k], v[5]);
    }
    for (int j = 0; j < 3; j++)
      wi[3 * k + j] = (float)q[k].wi[j], wi[3 * n + 3 * k + j] = (float)q[k].wo[j];
  }
  nbrdf_status st = NBRDF_OK;
  if (rc == CLI_EXIT_OK) {
    if (kind == EVAL_NEURAL_LAYERED) {
      st = nbrdf_model_base_latents(m, NBRDF_BASE_DIELECTRIC, n, p0, p1, NBRDF_RANGE_CLAMP, top, c0,
                                    &err);
      if (!st)
        st = nbrdf_model_base_latents(m, NBRDF_BASE_CONDUCTOR, n, p2, p3, NBRDF_RANGE_CLAMP, bottom,
                                      c1, &err);
      if (!st) st = nbrdf_model_layer(m, n, top, bottom, a, s, lat, &err);
    } else {
      nbrdf_base_kind bk =
          kind == EVAL_NEURAL_CONDUCTOR ? NBRDF_BASE_CONDUCTOR : NBRDF_BASE_DIELECTRIC;
      memset(c1, 0, n);
      st = nbrdf_model_base_latents(m, bk, n, p0, p1, NBRDF_RANGE_CLAMP, lat, c0, &err);
    }
    if (!st) st = nbrdf_model_decode(m, n, 1, lat, wi, wi + 3 * n, out, &err);
    if (st) rc = cli_fail_error("eval", &err);
  }
  for (size_t k = 0; k < n && rc == CLI_EXIT_OK; k++) {
    static const char *const top_names[2] = {"alpha1", "eta"},
                             *const bottom_names[2] = {"alpha2", "r0"},
                             *const cond[2] = {"alpha", "r0"}, *const diel[2] = {"alpha", "eta"};
    warn_clamped(lines[k],
                 kind == EVAL_NEURAL_LAYERED     ? top_names
                 : kind == EVAL_NEURAL_CONDUCTOR ? cond
                                                 : diel,
                 c0[k]);
    if (kind == EVAL_NEURAL_LAYERED) warn_clamped(lines[k], bottom_names, c1[k]);
    f[k] = out[k];
  }
  free(top), free(bottom), free(lat), free(a), free(s), free(wi), free(out), free(p0), free(c0);
  nbrdf_model_destroy(m);
  return rc;
}
