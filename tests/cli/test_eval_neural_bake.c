/* `nbrdf eval --model neural` computes what a bake computes (issue 15, item
 * 9): for parameter tuples inside and outside the trained ranges (sigma_t
 * 1000, eta 1 and 2.5, alpha 0.001, r0 1), eval's f equals the decode of the texel of
 * a --float bake of the same constants at the same directions, within float
 * rounding (the networks run in batches of other shapes), and eval warns
 * about exactly the parameters the bake's range report names, with the same range. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "nbrdf/model.h"
#include "testing.h"
#include "texture/latent_exr.h"

#define N_DIRS 5
static const double DIRS[N_DIRS][4] = {
    {30, 0, 30, 180}, {0, 0, 0, 0}, {60, 10, 20, 250}, {80, 0, 89.9, 180}, {45, 90, 70, -30}};

static const char *cli_bin(void) {
  const char *b = getenv("NBRDF");
  return b ? b : "nbrdf";
}

static char *slurp(const char *path) {
  FILE *f = fopen(path, "rb");
  if (!f) return calloc(1, 1);
  char *buf = calloc(1, 1 << 16);
  size_t n = buf ? fread(buf, 1, (1 << 16) - 1, f) : 0;
  (void)n;
  fclose(f);
  return buf;
}

/* Which of the six parameters a message set warns about, and the range it
 * names ("<name>: ... outside the model's trained range [lo, hi]"). */
static void warned(const char *text, const char *const *names, char ranges[6][64]) {
  for (int id = 0; id < 6; id++) {
    ranges[id][0] = '\0';
    char key[32];
    snprintf(key, sizeof key, "%s: ", names[id]);
    for (const char *p = strstr(text, key); p; p = strstr(p + 1, key)) {
      if (p > text && p[-1] != ' ' && p[-1] != '\n') continue; /* "alpha1: " inside "xalpha1: " */
      const char *eol = strchr(p, '\n'), *r = strstr(p, "trained range [");
      if (!r || (eol && r > eol)) continue;
      const char *end = strchr(r, ']');
      if (end) snprintf(ranges[id], 64, "%.*s", (int)(end - r + 1), r);
    }
  }
}

/* The same from the bake's range report, its --progress=json "range" events: the range
 * in alpha (an event in perceptual roughness gives sqrt of it), in eval's words. */
static void reported(const char *json, const char *const *names, char ranges[6][64]) {
  for (int id = 0; id < 6; id++) {
    ranges[id][0] = '\0';
    char key[64];
    snprintf(key, sizeof key, "\"event\":\"range\",\"parameter\":\"%s\"", names[id]);
    const char *p = strstr(json, key);
    if (!p) continue;
    const char *lo = strstr(p, "\"lo\":"), *hi = strstr(p, "\"hi\":"), *eol = strchr(p, '\n');
    if (!lo || !hi || (eol && hi > eol)) continue;
    double l = atof(lo + 5), h = atof(hi + 5);
    const char *units = strstr(p, "\"units\":\"perceptual roughness\"");
    if (units && (!eol || units < eol)) l *= l, h *= h;
    snprintf(ranges[id], 64, "trained range [%g, %g]", l, h);
  }
}

static void check_tuple(const nbrdf_model *m, const char *params[6], const char *roughness) {
  static const char *const names[6] = {"alpha1", "eta", "alpha2", "r0", "albedo", "sigma_t"};
  const char *tmp = testing_tmpdir(), *bin = cli_bin(), *src = testing_source_dir();
  char cmd[4096], exr[1024], csv[1024], out[1024], bake_out[1024], eval_err[1024];
  snprintf(exr, sizeof exr, "%s/t.exr", tmp);
  snprintf(csv, sizeof csv, "%s/q.csv", tmp);
  snprintf(out, sizeof out, "%s/out.csv", tmp);
  snprintf(bake_out, sizeof bake_out, "%s/bake.json", tmp);
  snprintf(eval_err, sizeof eval_err, "%s/eval.err", tmp);
  remove(exr);
  snprintf(cmd, sizeof cmd,
           "'%s' bake --bundle '%s/models/default' --float --roughness %s --alpha1 %s --eta %s "
           "--alpha2 %s --r0 %s --albedo %s --sigma-t %s -o '%s' --progress=json >'%s' 2>/dev/null",
           bin, src, roughness, params[0], params[1], params[2], params[3], params[4], params[5],
           exr, bake_out);
  CHECK_MSG(system(cmd) == 0, "bake failed: %s", cmd);
  FILE *f = fopen(csv, "w");
  if (!f) return;
  fprintf(f, "alpha1,eta,alpha2,r0,albedo,sigma_t,theta_i,phi_i,theta_o,phi_o\n");
  for (int d = 0; d < N_DIRS; d++)
    fprintf(f, "%s,%s,%s,%s,%s,%s,%.17g,%.17g,%.17g,%.17g\n", params[0], params[1], params[2],
            params[3], params[4], params[5], DIRS[d][0], DIRS[d][1], DIRS[d][2], DIRS[d][3]);
  fclose(f);
  snprintf(cmd, sizeof cmd,
           "'%s' eval --model neural --bundle '%s/models/default' --roughness %s <'%s' >'%s' "
           "2>'%s'",
           bin, src, roughness, csv, out, eval_err);
  CHECK_MSG(system(cmd) == 0, "eval failed: %s", cmd);

  /* The baked texel, decoded by the library at the same directions. */
  nbrdf_error err = {0};
  texture_latent_reader *r = NULL;
  CHECK_OK(texture_latent_reader_open(&r, exr, &err), &err);
  if (!r) return;
  const texture_latent_info *in = texture_latent_reader_info(r);
  float texel[64], latent[32], wi[3 * N_DIRS], wo[3 * N_DIRS], dec[N_DIRS];
  CHECK(in->channels <= 64 && in->layout.latent_dim == 32);
  CHECK_OK(texture_latent_reader_read(r, 0, 0, 0, 1, 1, texel, &err), &err);
  const texture_latent_layout layout = in->layout;
  texture_latent_reader_close(r);
  float lat[32 * N_DIRS];
  for (int k = 0; k < 32; k++)
    latent[k] = texel[texture_latent_index_latent(&layout, 0, k)];
  for (int d = 0; d < N_DIRS; d++) {
    memcpy(lat + 32 * d, latent, sizeof latent);
    for (int s = 0; s < 2; s++) {
      double th = DIRS[d][2 * s] * (M_PI / 180.0), ph = DIRS[d][2 * s + 1] * (M_PI / 180.0);
      float *w = (s ? wo : wi) + 3 * d;
      w[0] = (float)(sin(th) * cos(ph)), w[1] = (float)(sin(th) * sin(ph)), w[2] = (float)cos(th);
    }
  }
  CHECK_OK(nbrdf_model_decode(m, N_DIRS, 1, lat, wi, wo, dec, &err), &err);

  /* eval's f column, row by row. */
  FILE *o = fopen(out, "r");
  char line[1024];
  int row = -1;
  while (o && fgets(line, sizeof line, o)) {
    if (row >= 0 && row < N_DIRS) {
      const char *last = strrchr(line, ',');
      double fe = last ? strtod(last + 1, NULL) : NAN;
      CHECK_MSG(fabs(fe - dec[row]) <= 1e-5 * fabs(dec[row]) + 1e-7,
                "(%s %s %s %s %s %s, %s) direction %d: eval f %.9g, decoded bake texel %.9g",
                params[0], params[1], params[2], params[3], params[4], params[5], roughness, row,
                fe, (double)dec[row]);
    }
    row++;
  }
  if (o) fclose(o);
  CHECK_MSG(row == N_DIRS, "eval printed %d rows, not %d", row, N_DIRS);

  /* The same parameters warned about, with the same ranges. */
  char *be = slurp(bake_out), *ee = slurp(eval_err);
  char rb[6][64], re[6][64];
  reported(be, names, rb);
  warned(ee, names, re);
  for (int id = 0; id < 6; id++)
    CHECK_MSG(!strcmp(rb[id], re[id]),
              "(%s %s %s %s %s %s) %s: bake reports '%s', eval warns '%s'\nbake: %s\neval: %s",
              params[0], params[1], params[2], params[3], params[4], params[5], names[id], rb[id],
              re[id], be, ee);
  free(be);
  free(ee);
}

/* The warnings themselves are checked: a tuple that must warn does. */
static void check_warns(const char *param, const char *expect) {
  char path[1024];
  snprintf(path, sizeof path, "%s/eval.err", testing_tmpdir());
  char *e = slurp(path);
  CHECK_MSG(strstr(e, expect) != NULL, "%s: eval's warnings lack '%s': %s", param, expect, e);
  free(e);
}

static void check_quiet(const char *param, const char *absent) {
  char path[1024];
  snprintf(path, sizeof path, "%s/eval.err", testing_tmpdir());
  char *e = slurp(path);
  CHECK_MSG(strstr(e, absent) == NULL, "%s: eval warns '%s': %s", param, absent, e);
  free(e);
}

int main(void) {
  char dir[4096];
  snprintf(dir, sizeof dir, "%s/models/default", testing_source_dir());
  nbrdf_error err = {0};
  nbrdf_model *m = NULL;
  CHECK_OK(nbrdf_model_load(dir, &m, &err), &err);
  if (!m) return testing_finish();
  const char *inside[6] = {"0.1", "1.5", "0.3", "0.9", "0.8", "1"};
  check_tuple(m, inside, "alpha");
  const char *thick[6] = {"0.1", "1.5", "0.3", "0.9", "0.8", "1000"};
  check_tuple(m, thick, "alpha");
  check_warns("sigma_t 1000", "sigma_t: 1000 outside the model's trained range [0, 5]");
  /* eta = 1 (no coat) is inside the tables since models/v1 (whose grid began at 1.05). */
  const char *matched[6] = {"0.1", "1", "0.3", "0.9", "0.8", "1"};
  check_tuple(m, matched, "alpha");
  check_quiet("eta 1", "eta:");
  const char *dense[6] = {"0.1", "2.5", "0.3", "0.9", "0.8", "1"};
  check_tuple(m, dense, "alpha");
  check_warns("eta 2.5", "eta: 2.5 outside the model's trained range [1, 2]");
  const char *smooth[6] = {"0.001", "1.5", "0.001", "1", "0.8", "1"};
  check_tuple(m, smooth, "alpha");
  check_warns("alpha 0.001", "alpha2: 0.001 outside the model's trained range [0.01, 1]");
  const char *all[6] = {"0.001", "1", "0.001", "1", "1", "1000"};
  check_tuple(m, all, "alpha");
  /* Perceptual roughness: r = 0.05 is alpha = 0.0025, clamped; r = 0.5 is 0.25. */
  const char *perceptual[6] = {"0.05", "1.3", "0.5", "0.5", "0.3", "2"};
  check_tuple(m, perceptual, "perceptual");
  check_warns("perceptual 0.05", "alpha1: 0.0025 outside the model's trained range [0.01, 1]");
  nbrdf_model_destroy(m);
  return testing_finish();
}
