/* nbrdf render: a preview (or a reference image) of a latent texture on a
 * sphere or a plane; linear EXR and a display PNG. */
#include <float.h>
#include <limits.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "cli/cli.h"
#include "cli/cli_cancel.h"
#include "cli/cli_outputs.h"
#include "cli/cli_params.h"
#include "cli/cli_progress.h"
#include "model/material.h"
#include "nbrdf/render.h"

static int parse_numbers(const char *text, double *v, int n) {
  char buf[256];
  snprintf(buf, sizeof buf, "%s", text);
  char *s = buf;
  for (int k = 0; k < n; k++) {
    char *comma = strchr(s, ',');
    if ((k < n - 1) != (comma != NULL)) return 0;
    if (comma) *comma = '\0';
    if (!cli_parse_double(s, &v[k])) return 0;
    s = comma ? comma + 1 : s;
  }
  return 1;
}

/* --lobe X,Y[,LEVEL]: two or three indices (digits only). field[k], len[k]: each as typed. */
static int parse_lobe(const char *text, uint64_t xyl[3], const char *field[3], int len[3]) {
  const char *s = text;
  int n = 0;
  xyl[2] = 0, field[2] = "0", len[2] = 1;
  for (;;) {
    const char *comma = strchr(s, ',');
    size_t l = comma ? (size_t)(comma - s) : strlen(s);
    char buf[32];
    if (n == 3 || l == 0 || l >= sizeof buf) {
      /* More digits than fit: an index no texture has, refused as out of range below. */
      if (n < 3 && l >= sizeof buf && strspn(s, "0123456789") == l)
        xyl[n] = UINT64_MAX;
      else
        return 0;
    } else {
      memcpy(buf, s, l);
      buf[l] = '\0';
      if (!cli_parse_index(buf, &xyl[n])) return 0;
    }
    field[n] = s, len[n] = (int)l, n++;
    if (!comma) break;
    s = comma + 1;
  }
  return n >= 2;
}

typedef struct render_args {
  nbrdf_render_options o;
  cli_params params;
  const char *latent, *out, *png, *bundle;
  cli_progress_state ps;
  int lobes[8][3], n_lobes;
  const char *lobe_field[8][3]; /* as typed, for messages */
  int lobe_len[8][3];
  const char *lobe_text[8];
  int light_given, side_by_side, camera_pos_given, camera_target_given, camera_up_given;
} render_args;

static int read_env(const char *cmd, const cli_opt *o, const char *v) {
  (void)cmd;
  nbrdf_render_options *r = o->dest;
  r->env = !strcmp(v, "sky") ? NBRDF_ENV_SKY
                             : (!strcmp(v, "white") ? NBRDF_ENV_CONSTANT : NBRDF_ENV_IMAGE);
  r->env_path = r->env == NBRDF_ENV_IMAGE ? v : NULL;
  return 0;
}

static int read_light(const char *cmd, const cli_opt *o, const char *v) {
  render_args *a = o->dest;
  nbrdf_render_options *r = &a->o;
  double d[4];
  a->light_given = 1;
  if (!strcmp(v, "none")) {
    r->light_intensity = 0.0;
    return 0;
  }
  if (!parse_numbers(v, d, 4) || d[3] < 0.0)
    return cli_opt_bad(cmd, o->name, "X,Y,Z,I with I >= 0 (or none)", v);
  r->light_pos[0] = d[0], r->light_pos[1] = d[1], r->light_pos[2] = d[2];
  r->light_intensity = d[3];
  return 0;
}

/* --camera-pos / --camera-target / --camera-up: X,Y,Z. */
static int read_xyz(const char *cmd, const cli_opt *o, const char *v) {
  render_args *a = o->dest;
  double d[3];
  if (!parse_numbers(v, d, 3) || !isfinite(d[0]) || !isfinite(d[1]) || !isfinite(d[2]))
    return cli_opt_bad(cmd, o->name, "X,Y,Z (three finite numbers, world units, y up)", v);
  double *to = a->o.camera_up;
  int *given = &a->camera_up_given;
  if (!strcmp(o->name, "--camera-pos")) to = a->o.camera_pos, given = &a->camera_pos_given;
  if (!strcmp(o->name, "--camera-target")) to = a->o.camera_target, given = &a->camera_target_given;
  memcpy(to, d, sizeof d);
  *given = 1;
  return 0;
}

static int read_plane_repeat(const char *cmd, const cli_opt *o, const char *v) {
  double *d = o->dest;
  if (!cli_parse_double(v, d) || !(*d > 0.0)) return cli_opt_bad(cmd, o->name, "a number > 0", v);
  return 0;
}

static int read_lobe(const char *cmd, const cli_opt *o, const char *v) {
  render_args *a = o->dest;
  uint64_t xyl[3];
  if (a->n_lobes == 8) return cli_usage_error(cmd, "at most 8 --lobe options");
  if (!parse_lobe(v, xyl, a->lobe_field[a->n_lobes], a->lobe_len[a->n_lobes]))
    return cli_opt_bad(cmd, o->name,
                       "X,Y or X,Y,LEVEL: the column X and row Y of a texel of mip level LEVEL "
                       "(0, the default, is the full size), each an integer from 0",
                       v);
  /* Sizes and levels are the texture's: checked against it once it is known. */
  for (int k = 0; k < 3; k++)
    a->lobes[a->n_lobes][k] = xyl[k] > INT_MAX ? INT_MAX : (int)xyl[k];
  a->lobe_text[a->n_lobes++] = v;
  return 0;
}

static void render_options(render_args *a, cli_opt_visit visit, void *user) {
  // clang-format off
  const cli_opt t[] = {
      {.type = CLI_OPT_PATH, .name = "--output", .alias = "-o", .meta = "FILE", .dest = &a->out,
       .help = "linear float RGB OpenEXR to write"},
      {.type = CLI_OPT_PATH, .name = "--png", .meta = "FILE", .dest = &a->png,
       .help = "also a display PNG (OpenColorIO view transform: the\n"
               "--ocio / $OCIO config's default view, else built-in sRGB)"},
      {.type = CLI_OPT_ENUM, .name = "--mode", .choices = "neural|reference", .dest = &a->o.mode,
       .help = "neural: decode the texture (default); reference: the\n"
               "Monte Carlo ground truth of the parameters given below"},
      {.type = CLI_OPT_ENUM, .name = "--scene", .choices = "sphere|plane", .dest = &a->o.scene,
       .help = "the object (default sphere)"},
      {.type = CLI_OPT_CUSTOM, .name = "--env", .meta = "sky|white|FILE", .choices = "sky|white",
       .dest = &a->o, .parse = read_env,
       .help = "procedural sky (default), constant white (a furnace) or\n"
               "a lat-long HDR/EXR image (linear, +y up)"},
      {.type = CLI_OPT_FLOAT, .name = "--env-scale", .meta = "S", .lo = 0, .hi = FLT_MAX,
       .dest = &a->o.env_scale, .help = "multiplies the environment (default 1)"},
      {.type = CLI_OPT_DOUBLE, .name = "--env-rotation", .meta = "DEG", .lo = -1e6, .hi = 1e6,
       .dest = &a->o.env_rotation_deg,
       .help = "turns the environment about +y, counter-clockwise seen\n"
               "from above (default 0)"},
      {.type = CLI_OPT_CUSTOM, .name = "--light", .meta = "X,Y,Z,I|none", .choices = "none",
       .dest = a, .parse = read_light,
       .help = "point light at (X,Y,Z), intensity I W/sr (default\n"
               "3,4,4,30; none with --mesh)"},
      {.type = CLI_OPT_PATH, .name = "--mesh", .meta = "FILE", .dest = &a->o.mesh_path,
       .help = "render on this mesh instead of --scene: glTF 2.0\n"
               "(.gltf/.glb), PLY or OBJ with texture coordinates, y up;\n"
               "it shadows itself"},
      {.type = CLI_OPT_CUSTOM, .name = "--camera-pos", .meta = "X,Y,Z", .dest = a,
       .parse = read_xyz,
       .help = "camera position (with --camera-target; default: the\n"
               "scene's view, for a mesh its bounds seen from +z)"},
      {.type = CLI_OPT_CUSTOM, .name = "--camera-target", .meta = "X,Y,Z", .dest = a,
       .parse = read_xyz, .help = "the point the camera looks at"},
      {.type = CLI_OPT_CUSTOM, .name = "--camera-up", .meta = "X,Y,Z", .dest = a,
       .parse = read_xyz, .help = "the camera's up direction (default 0,1,0)"},
      {.type = CLI_OPT_DOUBLE, .name = "--fov", .meta = "DEG", .lo = 0.01, .hi = 179.0,
       .dest = &a->o.fov_deg,
       .help = "vertical field of view in degrees (default 40; plane 50)"},
      {.type = CLI_OPT_FLAG, .name = "--side-by-side", .dest = &a->side_by_side, .value = 1,
       .help = "neural image (left) beside the reference mode's (right,\n"
               "the Monte Carlo ground truth of the constant parameters\n"
               "given below): the output is twice as wide"},
      {.type = CLI_OPT_INT, .name = "--width", .meta = "W", .lo = 1, .hi = 16384,
       .dest = &a->o.width, .help = "image width (default 256)"},
      {.type = CLI_OPT_INT, .name = "--height", .meta = "H", .lo = 1, .hi = 16384,
       .dest = &a->o.height, .help = "image height (default 256)"},
      {.type = CLI_OPT_INT, .name = "--spp", .meta = "N", .lo = 1, .hi = 1 << 20, .dest = &a->o.spp,
       .help = "samples per pixel (default 16)"},
      {.type = CLI_OPT_U64, .name = "--seed", .meta = "S", .hi = 2147483647.0, .dest = &a->o.seed,
       .help = "random seed (default 0)"},
      {.type = CLI_OPT_INT, .name = "--threads", .meta = "N", .lo = 0, .hi = 1024,
       .dest = &a->o.threads, .help = "tile threads (default: 1 neural, all cores reference)"},
      {.type = CLI_OPT_FLAG, .name = "--no-mip", .dest = &a->o.mip, .value = 0,
       .help = "fetch level 0 only (no trilinear mip filtering)"},
      {.type = CLI_OPT_CUSTOM, .name = "--plane-repeat", .meta = "R", .dest = &a->o.plane_repeat,
       .parse = read_plane_repeat, .help = "plane: world units per texture repeat (default 1)"},
      {.type = CLI_OPT_PATH, .name = "--bundle", .meta = "DIR", .dest = &a->bundle,
       .help = "model bundle (neural; default: $NBRDF_BUNDLE, else the\n"
               "installed one: see 'nbrdf --version')"},
      {.type = CLI_OPT_CUSTOM, .name = "--lobe", .meta = "X,Y[,LEVEL]", .dest = a,
       .parse = read_lobe,
       .help = "also write the lobe images (docs/METRICS.md) of texel\n"
               "(X, Y) of mip LEVEL (default 0) to OUT-lobe-X-Y-LEVEL.png:\n"
               "decoded, and in reference mode beside the ground truth\n"
               "(1024 walks per pixel) with the lobe error; repeatable (8 at\n"
               "most)"},
      CLI_PROGRESS_OPTION(&a->ps, "progress as JSON lines on stdout"),
      {.help = "\nreference mode: the parameters as for 'nbrdf bake' (constants only):"},
      CLI_PARAMS_OPTIONS(&a->params),
      {0},
  };
  // clang-format on
  visit(user, NULL, t);
}

static void render_args_init(render_args *a) {
  memset(a, 0, sizeof *a);
  a->o = (nbrdf_render_options)NBRDF_RENDER_OPTIONS_DEFAULT;
  a->o.light_intensity = 30.0;
  cli_params_init(&a->params);
  a->ps = cli_progress_init(CLI_PROGRESS_BAR, NULL);
}

void cmd_render_options(cli_opt_visit visit, void *user) {
  render_args a;
  render_args_init(&a);
  render_options(&a, visit, user);
}

void cmd_render_usage(FILE *out) {
  fprintf(
      out,
      "usage: nbrdf render LATENT.exr -o OUT.exr [options]\n"
      "\n"
      "Renders the latent texture on a unit sphere, a ground plane or a mesh (--mesh)\n"
      "under an environment and a point light (direct lighting, MIS of light and BRDF samples;\n"
      "docs/RENDER.md). Deterministic for a seed, whatever the thread count.\n"
      "\n");
  cmd_render_options(cli_options_help_visit, out);
  fprintf(out, "\nexit status: 0 success, 1 failure, 2 bad usage\n");
}

/* Ground-truth BRDFs of constant parameters, one per colour channel. */
static int make_reference(const cli_params *p, nbrdf_brdf **brdfs, int *channels) {
  double v[NBRDF_BAKE_PARAM_COUNT][3];
  *channels = 1;
  for (int k = 0; k < NBRDF_BAKE_PARAM_COUNT; k++) {
    const nbrdf_bake_param *q = &p->in.param[k];
    if (q->path)
      return cli_usage_error("render", "reference mode takes constant parameters; --%s is a map",
                             nbrdf_bake_param_name(k));
    for (int c = 0; c < 3; c++)
      v[k][c] = q->value[q->channels == 3 ? c : 0];
    if (q->channels == 3) *channels = 3;
  }
  for (int c = 0; c < 3; c++) {
    v[NBRDF_BAKE_ALPHA1][c] = model_roughness_alpha(p->roughness, v[NBRDF_BAKE_ALPHA1][c]);
    v[NBRDF_BAKE_ALPHA2][c] = model_roughness_alpha(p->roughness, v[NBRDF_BAKE_ALPHA2][c]);
  }
  /* As typed (no clamping, model/material.h): the ground truth refuses what it cannot
   * represent. */
  for (int c = 0; c < *channels; c++) {
    nbrdf_error err = {0};
    double m[MODEL_MATERIAL_PARAMS];
    for (int k = 0; k < MODEL_MATERIAL_PARAMS; k++)
      m[k] = v[k][c];
    if (model_material_truth(m, &brdfs[c], &err) != NBRDF_OK) return cli_fail_error("render", &err);
  }
  return CLI_EXIT_OK;
}

/* OUT.exr -> OUT-lobe-X-Y-L.png */
static void lobe_path(const char *out, const int xyl[3], char path[4096]) {
  size_t n = strlen(out);
  if (n > 4 && !strcmp(out + n - 4, ".exr")) n -= 4;
  snprintf(path, 4096, "%.*s-lobe-%d-%d-%d.png", (int)(n < 4000 ? n : 4000), out, xyl[0], xyl[1],
           xyl[2]);
}

/* The lobe images of texel xyl, with the lobe error in reference mode. */
static int write_lobe(const nbrdf_model *model, const char *latent, const char *out,
                      const int xyl[3], const nbrdf_render_options *o, int json) {
  char path[4096];
  lobe_path(out, xyl, path);
  int ref = o->mode == NBRDF_RENDER_REFERENCE;
  double lobe_error;
  nbrdf_error err = {0};
  if (nbrdf_render_lobes(model, latent, xyl[0], xyl[1], xyl[2], ref ? o->reference : NULL,
                         o->reference_channels, 1024, o->seed, path, &lobe_error, &err) != NBRDF_OK)
    return cli_fail_error("render", &err);
  if (json && ref)
    printf("{\"event\":\"lobe\",\"output\":\"%s\",\"lobe_error_pct\":%.4g}\n", path,
           100 * lobe_error);
  else if (json)
    printf("{\"event\":\"lobe\",\"output\":\"%s\"}\n", path);
  else if (ref)
    printf("wrote %s: texel (%d, %d) level %d, lobe error %.2f %% against the ground truth\n", path,
           xyl[0], xyl[1], xyl[2], 100 * lobe_error);
  else
    printf("wrote %s: texel (%d, %d) level %d, decoded\n", path, xyl[0], xyl[1], xyl[2]);
  return CLI_EXIT_OK;
}

int cmd_render(int argc, char **argv) {
  render_args a;
  render_args_init(&a);
  cli_positionals pos = {&a.latent, 1, 0, "LATENT.exr"};
  cli_parse_call call = {"render", NULL, argc, 1, argv, &pos, 0};
  render_options(&a, cli_options_parse_visit, &call);
  if (call.rc == CLI_OPTIONS_HELP) {
    cmd_render_usage(stdout);
    return CLI_EXIT_OK;
  }
  if (call.rc != CLI_OPTIONS_OK) return call.rc;
  nbrdf_render_options o = a.o;
  const char *latent = a.latent, *out = a.out, *png = a.png;
  const int n_lobes = a.n_lobes;
  if (!latent) return cli_usage_error("render", "the latent texture LATENT.exr is required");
  if (!out) return cli_usage_error("render", "-o OUT.exr is required");
  if (o.mesh_path) {
    if (o.scene != NBRDF_SCENE_SPHERE)
      return cli_usage_error("render", "--mesh and --scene plane exclude each other");
    o.scene = NBRDF_SCENE_MESH;
    /* The artist's world lights the preview; a point light only when asked for. */
    if (!a.light_given) o.light_intensity = 0.0;
  }
  if ((a.camera_target_given || a.camera_up_given) && !a.camera_pos_given)
    return cli_usage_error("render", "--camera-target and --camera-up need --camera-pos");
  if (a.camera_pos_given && !a.camera_target_given)
    return cli_usage_error("render", "--camera-pos needs --camera-target");
  o.camera_set = a.camera_pos_given;
  if (a.side_by_side && o.mode != NBRDF_RENDER_NEURAL)
    return cli_usage_error("render", "--side-by-side renders both modes: leave --mode out");
  /* A --lobe the texture lacks is a bad option: name the field and the texture's range. An
   * unreadable texture is left to the render, which says why. */
  for (int k = 0; k < n_lobes; k++) {
    int w = 0, h = 0, levels = cli_texture_levels(latent, a.lobes[k][2], &w, &h);
    const int *xyl = a.lobes[k], *len = a.lobe_len[k];
    const char *const *f = a.lobe_field[k];
    char option[96];
    snprintf(option, sizeof option, "--lobe %.80s", a.lobe_text[k]);
    if (levels > 0 && xyl[2] >= levels) {
      char level[96];
      snprintf(level, sizeof level, "%.*s", len[2] < 80 ? len[2] : 80, f[2]);
      return cli_level_error("render", option, latent, levels, level);
    }
    if (levels > 0 && (xyl[0] >= w || xyl[1] >= h))
      return cli_usage_error("render",
                             "%s: level %d of %s is %d x %d texels (X 0..%d, Y 0..%d); there is "
                             "no texel (%.*s, %.*s)",
                             option, xyl[2], latent, w, h, w - 1, h - 1, len[0] < 32 ? len[0] : 32,
                             f[0], len[1] < 32 ? len[1] : 32, f[1]);
  }
  nbrdf_brdf *ref[3] = {NULL, NULL, NULL};
  nbrdf_model *model = NULL;
  nbrdf_error err = {0};
  int rc = CLI_EXIT_OK;
  if (o.mode == NBRDF_RENDER_REFERENCE || a.side_by_side) {
    rc = cli_params_require("render", &a.params);
    if (rc == CLI_EXIT_OK) rc = make_reference(&a.params, ref, &o.reference_channels);
    o.reference = (const nbrdf_brdf *const *)ref;
  }
  if (rc == CLI_EXIT_OK && (o.mode == NBRDF_RENDER_NEURAL || n_lobes > 0)) {
    char used[PATH_MAX];
    rc = cli_model_load("render", a.bundle, &model, used, sizeof used);
    if (rc == CLI_EXIT_OK && !nbrdf_model_is_trained(model))
      fprintf(stderr, "nbrdf render: warning: bundle '%s' is untrained (random networks)\n", used);
  }
  if (rc == CLI_EXIT_OK) {
    cli_inputs inputs;
    cli_inputs_init(&inputs);
    cli_inputs_add(&inputs, latent);
    cli_inputs_add(&inputs, o.env_path);
    cli_inputs_add(&inputs, o.mesh_path);
    cli_inputs_add_params(&inputs, &a.params);
    cli_inputs_add_model(&inputs, model);
    char lobe_paths[8][4096];
    const char *outputs[10] = {out, png};
    for (int k = 0; k < n_lobes; k++) {
      lobe_path(out, a.lobes[k], lobe_paths[k]);
      outputs[2 + k] = lobe_paths[k];
    }
    rc = cli_outputs_check("render", &inputs, outputs, 2 + n_lobes);
  }
  /* --side-by-side: the neural image in the left half, the reference in the right. */
  int panes = a.side_by_side ? 2 : 1, out_w = o.width * panes;
  size_t pane = (size_t)3 * o.width * o.height;
  float *rgb = rc == CLI_EXIT_OK ? malloc(sizeof(float) * pane * panes) : NULL;
  if (rc == CLI_EXIT_OK && !rgb) rc = cli_fail("render", "out of memory");
  /* Lobes first: a bad texel fails before the render writes anything. */
  for (int k = 0; rc == CLI_EXIT_OK && k < n_lobes; k++)
    rc = write_lobe(model, latent, out, a.lobes[k], &o, a.ps.json);
  if (rc == CLI_EXIT_OK) {
    cli_progress_start(&a.ps);
    o.progress = cli_progress, o.user = &a.ps, o.cancel = cli_cancel_flag();
    cli_cancel_watch();
    nbrdf_render_stats stats;
    nbrdf_status st = nbrdf_render(model, latent, &o, rgb, &stats, &err);
    if (st == NBRDF_OK && a.side_by_side) {
      nbrdf_render_options r = o;
      nbrdf_render_stats rs;
      r.mode = NBRDF_RENDER_REFERENCE;
      st = nbrdf_render(NULL, latent, &r, rgb + pane, &rs, &err);
      stats.brdf_evals += rs.brdf_evals;
      /* rows of the two panes interleaved into one image twice as wide */
      float *both = st == NBRDF_OK ? malloc(sizeof(float) * pane * 2) : NULL;
      if (st == NBRDF_OK && !both)
        st = NBRDF_ERR_MEMORY, snprintf(err.message, sizeof err.message, "out of memory");
      for (int y = 0; both && y < o.height; y++)
        for (int k = 0; k < 2; k++)
          memcpy(both + 3 * ((size_t)y * out_w + (size_t)k * o.width),
                 rgb + k * pane + 3 * (size_t)y * o.width, sizeof(float) * 3 * o.width);
      if (both) free(rgb), rgb = both;
    }
    cli_cancel_unwatch();
    if (st == NBRDF_OK)
      st = nbrdf_render_write(out, png, out_w, o.height, rgb, NULL, a.params.in.ocio_config, &err);
    if (st != NBRDF_OK) {
      if (a.ps.json) printf("{\"event\":\"error\",\"status\":\"%s\"}\n", nbrdf_status_name(st));
      rc = st == NBRDF_ERR_CANCELLED
               ? cli_fail("render", "%s: cancelled; no file written", cli_cancel_reason())
               : cli_fail_error("render", &err);
    } else if (a.ps.json) {
      printf("{\"event\":\"done\",\"width\":%d,\"height\":%d,\"spp\":%d,\"decoded\":%zu,"
             "\"decode_seconds\":%.4f,\"brdf_evals\":%zu,\"triangles\":%d}\n",
             out_w, o.height, o.spp, stats.decoded, stats.decode_seconds, stats.brdf_evals,
             stats.triangles);
    } else {
      printf("wrote %s%s%s: %d x %d, %d spp, %s mode, %d mip levels, %zu decoder queries, %zu "
             "ground-truth evaluations\n",
             out, png ? " and " : "", png ? png : "", out_w, o.height, o.spp,
             a.side_by_side ? "neural | reference"
                            : (o.mode == NBRDF_RENDER_NEURAL ? "neural" : "reference"),
             stats.levels, stats.decoded, stats.brdf_evals);
      if (stats.decoded && stats.decode_seconds > 0.0)
        printf("decoder: %.3g queries/s inside the renderer (%.2f s decoding, all threads)\n",
               stats.decoded / stats.decode_seconds, stats.decode_seconds);
    }
  }
  free(rgb);
  for (int c = 0; c < 3; c++)
    nbrdf_brdf_destroy(ref[c]);
  nbrdf_model_destroy(model);
  return rc;
}
