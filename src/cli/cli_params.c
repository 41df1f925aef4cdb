#include "cli/cli_params.h"

#include <stdio.h>
#include <string.h>

#include "cli/cli.h"
#include "model/material.h"
#include "texture/param_source.h"

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

void cli_params_usage(FILE *out) {
  fprintf(out, "  --alpha1 V            top coat roughness (see --roughness)\n"
               "  --eta V               top coat IOR (8/16-bit maps: see --eta-range)\n"
               "  --alpha2 V            bottom conductor roughness\n"
               "  --r0 V                bottom Schlick reflectance at normal incidence (colour)\n"
               "  --albedo V            slab single-scattering albedo (colour)\n"
               "  --sigma-t V           slab optical depth (8/16-bit maps: see --sigma-t-range)\n"
               "  --roughness alpha|perceptual\n"
               "                        alpha: GGX alpha as in the paper (default); perceptual:\n"
               "                        the artists' roughness r of Blender et al., alpha = r^2\n"
               "  --r0-colourspace CS, --albedo-colourspace CS\n"
               "                        colour space of 8/16-bit colour maps (default sRGB)\n"
               "  --ocio CONFIG         OpenColorIO config for colour spaces (default $OCIO)\n"
               "  --eta-range LO,HI     8/16-bit eta maps: [0,1] -> [LO,HI] (default 1,2)\n"
               "  --sigma-t-range LO,HI 8/16-bit sigma_t maps: [0,1] -> [LO,HI] (default 0,5)\n"
               "  --resample none|bilinear\n"
               "                        maps of different sizes (or not the output size):\n"
               "                        an error (default), or each resampled bilinearly to\n"
               "                        the output size, else the largest width and height\n");
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

int cli_params_option(const char *cmd, int argc, char **argv, int *i, cli_params *p) {
  const char *a = argv[*i];
  const char *v = *i + 1 < argc ? argv[*i + 1] : NULL;
  if (!v) return 0;
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++)
    if (!strcmp(a, flag_names[id])) {
      nbrdf_error err = {0};
      if (nbrdf_bake_param_parse(nbrdf_bake_param_name(id), v, &p->in.param[id], &err) !=
          NBRDF_OK) {
        cli_usage_error(cmd, "%s", err.message);
        return -1;
      }
      /* What nbrdf_bake would refuse of a constant (texture_param_source_constant,
       * bake_tuple.c) is a bad option here, before anything is loaded. */
      const nbrdf_bake_param *q = &p->in.param[id];
      int colour = id == NBRDF_BAKE_R0 || id == NBRDF_BAKE_ALBEDO;
      for (int c = 0; !q->path && c < q->channels; c++)
        if (q->value[c] < 0.0f || (colour && q->value[c] > 1.0f)) {
          cli_usage_error(cmd, "%s '%s': %g is %s; expected %s", a, v, (double)q->value[c],
                          q->value[c] < 0.0f ? "negative" : "above 1 (not physical)",
                          colour ? "a reflectance in [0, 1]" : "a value >= 0");
          return -1;
        }
      p->given[id] = 1, ++*i;
      return 1;
    }
  if (!strcmp(a, "--roughness")) {
    int convention = model_roughness_parse(v);
    if (convention < 0)
      return cli_usage_error(cmd, "--roughness is 'alpha' or 'perceptual', not '%s'", v), -1;
    p->roughness = (nbrdf_roughness)convention;
    p->roughness_given = 1;
  } else if (!strcmp(a, "--r0-colourspace")) {
    p->in.param[NBRDF_BAKE_R0].colour_space = v;
  } else if (!strcmp(a, "--albedo-colourspace")) {
    p->in.param[NBRDF_BAKE_ALBEDO].colour_space = v;
  } else if (!strcmp(a, "--ocio")) {
    p->in.ocio_config = v;
  } else if (!strcmp(a, "--resample")) {
    if (!strcmp(v, "none"))
      p->in.resample = NBRDF_RESAMPLE_NONE;
    else if (!strcmp(v, "bilinear"))
      p->in.resample = NBRDF_RESAMPLE_BILINEAR;
    else
      return cli_usage_error(cmd, "--resample is 'none' or 'bilinear', not '%s'", v), -1;
  } else if (!strcmp(a, "--eta-range") || !strcmp(a, "--sigma-t-range")) {
    int eta = a[2] == 'e';
    if (!parse_range(v, &p->in.param[eta ? NBRDF_BAKE_ETA : NBRDF_BAKE_SIGMA_T]))
      return cli_usage_error(cmd, "%s needs LO,HI with LO < HI (numbers, LO >= 0), not '%s'", a,
                             v),
             -1;
  } else {
    return 0;
  }
  ++*i;
  return 1;
}

void cli_params_explain(nbrdf_error *err) {
  static const char advice[] = TEXTURE_RESAMPLE_ADVICE;
  size_t n = strlen(err->message), a = sizeof advice - 1;
  if (err->status != NBRDF_ERR_MISMATCH || n < a || strcmp(err->message + n - a, advice)) return;
  snprintf(err->message + n - a, sizeof err->message - (n - a),
           "; pass --resample bilinear to resample the maps to one size");
}

int cli_params_require(const char *cmd, const cli_params *p) {
  for (int k = 0; k < NBRDF_BAKE_PARAM_COUNT; k++)
    if (!p->given[k]) return cli_usage_error(cmd, "%s is required", flag_names[k]);
  return CLI_EXIT_OK;
}
