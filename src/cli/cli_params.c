#include "cli/cli_params.h"

#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "cli/cli.h"
#include "model/material.h"
#include "texture/param_source.h"
#include "texture/tile_pattern.h"

static const char *const flag_names[NBRDF_BAKE_PARAM_COUNT] = {"--alpha1", "--eta",    "--alpha2",
                                                               "--r0",     "--albedo", "--sigma-t"};

void cli_params_init(cli_params *p) {
  memset(p, 0, sizeof *p);
  p->in = (nbrdf_bake_inputs)NBRDF_BAKE_INPUTS_DEFAULT;
  nbrdf_bake_param *eta = &p->in.param[NBRDF_BAKE_ETA], *st = &p->in.param[NBRDF_BAKE_SIGMA_T];
  eta->remap = 1, eta->lo = 1.0f, eta->hi = 2.0f;
  st->remap = 1, st->lo = 0.0f, st->hi = NBRDF_BAKE_SIGMA_T_MAX;
  p->roughness = NBRDF_ROUGHNESS_ALPHA;
}

/* LO,HI: floats with 0 <= LO < HI, as the map reader requires (a parameter is >= 0): a bad
 * range is the command line's fault, whether or not a map uses it. */
static int parse_range(const char *text, nbrdf_bake_param *p) {
  float lo, hi;
  char a[64], *comma;
  if (strlen(text) >= sizeof a) return 0;
  snprintf(a, sizeof a, "%s", text);
  if (!(comma = strchr(a, ','))) return 0;
  *comma = '\0';
  if (!cli_parse_float(a, &lo) || !cli_parse_float(comma + 1, &hi) || !(lo >= 0.0f && lo < hi))
    return 0;
  p->remap = 1, p->lo = lo, p->hi = hi;
  return 1;
}

int cli_params_read_range(const char *cmd, const cli_opt *o, const char *value) {
  if (parse_range(value, o->dest)) return 0;
  return cli_opt_bad(cmd, o->name, "LO,HI with LO < HI (numbers, LO >= 0)", value);
}

int cli_params_read(const char *cmd, const cli_opt *o, const char *v) {
  cli_params *p = o->dest;
  int id = o->value;
  nbrdf_error err = {0};
  /* A tile pattern, unless a file of that very name exists: its tiles are found once the
   * whole command line is known (texture/tile_set.h). */
  struct stat sb;
  texture_tile_pattern *tp = NULL;
  p->tiled[id] = 0;
  if (stat(v, &sb) != 0 && (strchr(v, '<') || strstr(v, "%(UDIM)d"))) {
    if (texture_tile_pattern_parse(v, &tp, &err) != NBRDF_OK)
      return cli_usage_error(cmd, "%s: %s", o->name, err.message);
    int tiled = texture_tile_pattern_is_tiled(tp);
    texture_tile_pattern_free(tp);
    if (tiled) {
      p->in.param[id].path = v;
      p->tiled[id] = 1;
      return 0;
    }
  }
  if (nbrdf_bake_param_parse(nbrdf_bake_param_name(id), v, &p->in.param[id], &err) != NBRDF_OK)
    return cli_usage_error(cmd, "%s", err.message);
  /* What nbrdf_bake would refuse of a constant (texture_param_source_constant,
   * bake_tuple.c) is a bad option here, before anything is loaded. */
  const nbrdf_bake_param *q = &p->in.param[id];
  int colour = id == NBRDF_BAKE_R0 || id == NBRDF_BAKE_ALBEDO;
  for (int c = 0; !q->path && c < q->channels; c++)
    if (q->value[c] < 0.0f || (colour && q->value[c] > 1.0f))
      return cli_usage_error(cmd, "%s '%s': %g is %s; expected %s", o->name, v, (double)q->value[c],
                             q->value[c] < 0.0f ? "negative" : "above 1 (not physical)",
                             colour ? "a reflectance in [0, 1]" : "a value >= 0");
  return 0;
}

void cli_params_explain(nbrdf_error *err) {
  static const char advice[] = TEXTURE_RESAMPLE_ADVICE;
  size_t n = strlen(err->message), a = sizeof advice - 1;
  if (err->status != NBRDF_ERR_MISMATCH || n < a || strcmp(err->message + n - a, advice)) return;
  snprintf(err->message + n - a, sizeof err->message - (n - a),
           "; pass --resample bilinear to resample the maps to one size");
}

int cli_params_any_tiled(const cli_params *p) {
  for (int k = 0; k < NBRDF_BAKE_PARAM_COUNT; k++)
    if (p->tiled[k]) return 1;
  return 0;
}

int cli_params_require(const char *cmd, const cli_params *p) {
  for (int k = 0; k < NBRDF_BAKE_PARAM_COUNT; k++)
    if (!p->given[k]) return cli_usage_error(cmd, "%s is required", flag_names[k]);
  return CLI_EXIT_OK;
}
