/* nbrdf bake: parameter maps or constants -> a latent OpenEXR texture. */
#include <limits.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "cli/cli.h"
#include "cli/cli_cancel.h"
#include "cli/cli_device.h"
#include "cli/cli_outputs.h"
#include "cli/cli_params.h"
#include "cli/cli_progress.h"
#include "nbrdf/bake.h"
#include "nbrdf/model.h"

void cmd_bake_usage(FILE *out) {
  fprintf(out, "usage: nbrdf bake --alpha1 V --eta V --alpha2 V --r0 V --albedo V --sigma-t V\n"
               "                  -o OUT.exr [options]\n"
               "\n"
               "Bakes a layered BRDF (rough dielectric coat over a rough conductor, with a slab\n"
               "of albedo A and optical depth sigma_t between them) into a tiled, mip-mapped\n"
               "latent OpenEXR texture (docs/LATENT-TEXTURE.md). Each V is a constant ('0.3',\n"
               "or '0.8,0.5,0.2' for RGB; decimal, no hex/inf/nan) or an existing image file\n"
               "(grey or RGB, either optionally with alpha, which is ignored: colour under\n"
               "alpha 0 is read as stored; a regular file, at most 65536x65536; all maps one\n"
               "size, or --resample). Write './0.5' for a file named like a number.\n"
               "The texture is mono when every input is grey, else RGB (one BRDF per channel).\n"
               "\n"
               "inputs (shared with 'nbrdf verify'):\n");
  cli_params_usage(out);
  fprintf(
      out,
      "\n"
      "options:\n"
      "  -o, --output FILE     the texture to write (written whole or not at all)\n"
      "  --half | --float      latent storage (default half)\n"
      "  --mip-levels full|1   the full mip chain (default) or level 0 only\n"
      "  --tile N              tile edge in texels (default 64)\n"
      "  --size WxH            output size (1..65536 each; default: the maps' size, or\n"
      "                        1x1 when every input is a constant); maps of another\n"
      "                        size need --resample bilinear\n"
      "  --compression zip|piz|rle|none\n"
      "                        lossless EXR compression (default zip: smallest; rle or\n"
      "                        none write faster, see docs/BAKE.md)\n"
      "  --bundle DIR          model bundle (default: $NBRDF_BUNDLE, else the installed\n"
      "                        one: see 'nbrdf --version')\n"
      "  --decoder FILE        a decoder.safetensors of the bundle's latent size (a fine-\n"
      "                        tuned copy, say) that the texture carries and is decoded\n"
      "                        with (format version 2, docs/LATENT-TEXTURE.md); default:\n"
      "                        none, the bundle's decoder (a version-1 texture). It takes\n"
      "                        the bundle decoder's place in every stage: specialised\n"
      "                        carries it fine-tuned to the scene, compact the small\n"
      "                        decoder distilled from that fine-tuned copy\n"
      "  --range clamp|refuse  values outside the model's trained ranges: clamp with a\n"
      "                        warning (default) or stop naming the file and texel\n"
      "  --quantise BITS       round every parameter to 2^BITS levels over its trained\n"
      "                        range (2..16; default off): fewer distinct tuples for\n"
      "                        smooth float maps, at a measured cost (docs/BAKE.md)\n"
      "  --energy-audit N      decoded directional albedo of the first N distinct latents\n"
      "                        (16384; 0: off): the worst goes into the header as\n"
      "                        nbrdf:maxAlbedo, a warning names it above 1.01\n"
      "  --accuracy fast|fitted|specialised|compact\n"
      "                        fast (default): the universal networks; fitted: latents\n"
      "                        fitted to the layered ground truth of the scene's own\n"
      "                        BRDFs (representative tuples; any reader decodes it);\n"
      "                        specialised: also a decoder fine-tuned to the scene,\n"
      "                        carried in the texture (format 2); compact: as\n"
      "                        specialised, then 8 latent channels per colour channel\n"
      "                        and a small decoder distilled for the scene (fast to\n"
      "                        decode, a third of the channels). docs/BAKE.md\n"
      "                        measures the trade\n"
      "  --compact K[,WIDTH]   compact's latent channels per colour channel (1..8,\n"
      "                        default 8) and decoder width (4..256, default 32);\n"
      "                        implies --accuracy compact\n"
      "  --budget SECONDS      fitted/specialised/compact: the cost-model seconds the\n"
      "                        ground truth and fit may take (defaults 120 / 300 / 400;\n"
      "                        about the wall time on one free core; the result does\n"
      "                        not depend on the machine or its load)\n"
      "  --seed S              above fast: random walks and tuple selection (1)\n"
      CLI_DEVICE_USAGE
      "  --progress=json       progress as JSON lines on stdout (for tools), instead of\n"
      "                        the bar drawn on stderr when it is a terminal\n"
      "\n"
      "Ctrl-C, SIGTERM or SIGHUP cancel cleanly: no output file is left. An output that\n"
      "is one of the inputs (a map, a bundle file), a FIFO or device, or read-only is\n"
      "refused (docs/RELIABILITY.md).\n"
      "exit status: 0 success, 1 failure (the message names the file and texel), 2 bad usage\n");
}

/* Prints `text` as a JSON string (control characters dropped). */
static void json_string(const char *text) {
  putchar('"');
  for (const char *c = text; *c; c++)
    if (*c == '"' || *c == '\\')
      printf("\\%c", *c);
    else if ((unsigned char)*c >= 0x20)
      putchar(*c);
  putchar('"');
}

static void on_warning(void *user, const char *message) {
  const cli_progress_state *p = user;
  if (p->json) {
    printf("{\"event\":\"warning\",\"message\":");
    json_string(message);
    printf("}\n");
  }
  fprintf(stderr, "nbrdf bake: warning: %s\n", message);
}

/* Where the networks run: one line on stderr (the user is the progress state, as warnings'). */
static void on_note(void *user, const char *message) {
  (void)user;
  cli_device_note("bake", message);
}

/* "WxH" or "N" (square), each 1..NBRDF_BAKE_SIZE_MAX. */
static int parse_size(const char *text, int *w, int *h) {
  char a[64], *x;
  long lw, lh;
  if (strlen(text) >= sizeof a) return 0;
  snprintf(a, sizeof a, "%s", text);
  x = strchr(a, 'x');
  if (!x) x = strchr(a, 'X');
  if (x) *x = '\0';
  if (!cli_parse_int(a, 1, NBRDF_BAKE_SIZE_MAX, &lw)) return 0;
  if (!x)
    lh = lw;
  else if (!cli_parse_int(x + 1, 1, NBRDF_BAKE_SIZE_MAX, &lh))
    return 0;
  *w = (int)lw, *h = (int)lh;
  return 1;
}

int cmd_bake(int argc, char **argv) {
  cli_params params;
  cli_params_init(&params);
  nbrdf_bake_options opts = NBRDF_BAKE_OPTIONS_DEFAULT;
  const char *out = NULL, *bundle = NULL, *decoder = NULL;
  cli_progress_state ps = cli_progress_init(CLI_PROGRESS_BAR, NULL);
  int budget_given = 0, compact_given = 0;
  nbrdf_error err = {0};
  if (cli_device_default("bake", &opts.device) < 0) return CLI_EXIT_USAGE;
  for (int i = 1; i < argc; i++) {
    const char *a = argv[i];
    const char *v = i + 1 < argc ? argv[i + 1] : NULL;
    int used = cli_params_option("bake", argc, argv, &i, &params);
    if (used < 0) return CLI_EXIT_USAGE;
    if (used) continue;
    int dev = cli_device_option("bake", argc, argv, &i, &opts.device);
    if (dev < 0) return CLI_EXIT_USAGE;
    if (dev) continue;
    if (cli_is_help(a)) {
      cmd_bake_usage(stdout);
      return CLI_EXIT_OK;
    } else if ((!strcmp(a, "-o") || !strcmp(a, "--output")) && v) {
      out = v, i++;
    } else if (!strcmp(a, "--half") || !strcmp(a, "--float")) {
      opts.storage = a[2] == 'h' ? NBRDF_BAKE_HALF : NBRDF_BAKE_FLOAT;
    } else if (!strcmp(a, "--mip-levels") && v) {
      if (strcmp(v, "full") && strcmp(v, "0") && strcmp(v, "1"))
        return cli_usage_error("bake",
                               "--mip-levels is 'full' or 1 (OpenEXR mip chains are "
                               "complete), not '%s'",
                               v);
      opts.mip_levels = !strcmp(v, "1"), i++;
    } else if (!strcmp(a, "--tile") && v) {
      long t;
      if (!cli_parse_int(v, 8, 1024, &t))
        return cli_usage_error("bake", "--tile needs an integer in [8, 1024], not '%s'", v);
      opts.tile_size = (int)t, i++;
    } else if (!strcmp(a, "--size") && v) {
      if (!parse_size(v, &params.in.width, &params.in.height))
        return cli_usage_error("bake",
                               "--size needs WxH (or N for NxN), each an integer in [1, %d], "
                               "not '%s'",
                               NBRDF_BAKE_SIZE_MAX, v);
      i++;
    } else if (!strcmp(a, "--compression") && v) {
      static const char *const names[] = {"zip", "piz", "rle", "none"};
      int k = 0;
      while (k < 4 && strcmp(v, names[k]))
        k++;
      if (k == 4)
        return cli_usage_error("bake", "--compression is zip, piz, rle or none, not '%s'", v);
      opts.compression = (nbrdf_bake_compression)k, i++;
    } else if (!strcmp(a, "--bundle") && v) {
      bundle = v, i++;
    } else if (!strcmp(a, "--decoder") && v) {
      decoder = v, i++;
    } else if (!strcmp(a, "--range") && v) {
      if (!strcmp(v, "clamp"))
        opts.range = NBRDF_RANGE_CLAMP;
      else if (!strcmp(v, "refuse"))
        opts.range = NBRDF_RANGE_REFUSE;
      else
        return cli_usage_error("bake", "--range is 'clamp' or 'refuse', not '%s'", v);
      i++;
    } else if (!strcmp(a, "--quantise") && v) {
      long q;
      if (!cli_parse_int(v, 2, 16, &q))
        return cli_usage_error("bake", "--quantise needs an integer in [2, 16], not '%s'", v);
      opts.quantise_bits = (int)q, i++;
    } else if (!strcmp(a, "--energy-audit") && v) {
      uint64_t n;
      if (!cli_parse_u64(v, &n) || n > ((uint64_t)1 << 40))
        return cli_usage_error("bake", "--energy-audit needs a count >= 0, not '%s'", v);
      opts.energy_audit = (size_t)n, i++;
    } else if (!strcmp(a, "--accuracy") && v) {
      int level = nbrdf_bake_accuracy_parse(v);
      if (level < 0)
        return cli_usage_error(
            "bake", "--accuracy is fast, fitted, specialised or compact, not '%s'", v);
      if (compact_given && level != NBRDF_BAKE_COMPACT)
        return cli_usage_error("bake", "--compact goes with --accuracy compact, not '%s'", v);
      opts.accuracy = (nbrdf_bake_accuracy)level, i++;
    } else if (!strcmp(a, "--compact") && v) {
      char *end = NULL;
      long k = strtol(v, &end, 10), w = 0;
      int ok = end != v && k >= 1 && k <= 8;
      if (ok && *end == ',') {
        const char *ws = end + 1;
        w = strtol(ws, &end, 10);
        ok = end != ws && w >= 4 && w <= 256;
      }
      if (!ok || *end)
        return cli_usage_error("bake",
                               "--compact needs K[,WIDTH]: K latent channels 1..8, WIDTH 4..256 "
                               "(e.g. 8 or 8,32), not '%s'",
                               v);
      if (opts.accuracy != NBRDF_BAKE_FAST && opts.accuracy != NBRDF_BAKE_COMPACT)
        return cli_usage_error("bake", "--compact goes with --accuracy compact, not '%s'",
                               nbrdf_bake_accuracy_name(opts.accuracy));
      opts.accuracy = NBRDF_BAKE_COMPACT, compact_given = 1;
      opts.compact_dim = (int)k, opts.compact_width = (int)w, i++;
    } else if (!strcmp(a, "--budget") && v) {
      double b;
      if (!cli_parse_double(v, &b) || !(b > 0.0) || b > 1e7)
        return cli_usage_error("bake", "--budget needs a number of seconds in (0, 1e7], not '%s'",
                               v);
      opts.budget = b, budget_given = 1, i++;
    } else if (!strcmp(a, "--seed") && v) {
      if (!cli_parse_u64(v, &opts.seed))
        return cli_usage_error("bake", "--seed needs an unsigned integer, not '%s'", v);
      i++;
    } else if (cli_progress_flag(a, &ps)) {
    } else {
      return cli_usage_error("bake", "unknown option or missing value: '%s'", a);
    }
  }
  int missing = cli_params_require("bake", &params);
  if (missing != CLI_EXIT_OK) return missing;
  opts.roughness = params.roughness;
  if (budget_given && opts.accuracy == NBRDF_BAKE_FAST)
    return cli_usage_error("bake",
                           "--budget applies to --accuracy fitted, specialised or compact, not fast");
  if (!out) return cli_usage_error("bake", "-o OUT.exr is required");
  nbrdf_model *model = NULL;
  char used[PATH_MAX];
  int loaded = cli_model_load("bake", bundle, &model, used, sizeof used);
  if (loaded != CLI_EXIT_OK) return loaded;
  cli_inputs inputs;
  cli_inputs_init(&inputs);
  cli_inputs_add_params(&inputs, &params);
  cli_inputs_add_model(&inputs, model);
  if (decoder) {
    /* The texture carries this decoder (format version 2). */
    nbrdf_model *with = NULL;
    if (nbrdf_model_with_decoder_file(model, decoder, &with, &err) != NBRDF_OK) {
      nbrdf_model_destroy(model);
      cli_inputs_free(&inputs);
      return cli_fail_error("bake", &err);
    }
    nbrdf_model_destroy(model);
    model = with;
    cli_inputs_add(&inputs, decoder);
  }
  if (cli_output_check("bake", &inputs, out) != CLI_EXIT_OK) {
    nbrdf_model_destroy(model);
    return CLI_EXIT_FAILURE;
  }
  /* The options against the model (a budget too small for the level and this decoder): a bad
   * option is a usage error, whereas nbrdf_bake's own failures are the inputs'. */
  if (nbrdf_bake_options_check(model, &opts, &err) != NBRDF_OK) {
    nbrdf_model_destroy(model);
    cli_inputs_free(&inputs);
    return cli_usage_error("bake", "%s%s", budget_given ? "--budget: " : "",
                           strncmp(err.message, "bake: ", 6) ? err.message : err.message + 6);
  }
  if (!nbrdf_model_is_trained(model))
    fprintf(stderr, "nbrdf bake: warning: bundle '%s' is untrained (random networks)\n", used);

  cli_progress_start(&ps);
  opts.progress = cli_progress;
  opts.warning = on_warning;
  opts.note = on_note;
  opts.user = &ps;
  opts.cancel = cli_cancel_flag();
  cli_cancel_watch();
  nbrdf_bake_report rep;
  nbrdf_status st = nbrdf_bake(model, &params.in, &opts, out, &rep, &err);
  cli_cancel_unwatch();
  nbrdf_model_destroy(model);
  if (st != NBRDF_OK) {
    cli_params_explain(&err);
    if (ps.bar) fputc('\n', stderr);
    if (ps.json) {
      printf("{\"event\":\"error\",\"status\":\"%s\",\"message\":", nbrdf_status_name(st));
      json_string(err.message);
      printf("}\n");
    }
    if (st == NBRDF_ERR_CANCELLED)
      return cli_fail("bake", "%s: cancelled; no file written", cli_cancel_reason());
    return cli_fail_error("bake", &err);
  }
  if (ps.json) {
    printf("{\"event\":\"done\",\"output\":");
    json_string(out);
    printf(",\"width\":%d,\"height\":%d,\"channels\":%d,\"evaluated\":%zu", rep.width,
           rep.height, rep.colour_channels, rep.evaluated);
    printf(",\"device\":");
    json_string(rep.device);
    if (rep.accuracy != NBRDF_BAKE_FAST)
      printf(",\"accuracy\":\"%s\",\"budget\":%g,\"distinct\":%zu,\"fitted_tuples\":%zu,"
             "\"heldout_tuples\":%zu,\"heldout_error\":%.5f,\"heldout_error_fast\":%.5f",
             nbrdf_bake_accuracy_name(rep.accuracy), rep.budget, rep.distinct, rep.fitted_tuples,
             rep.heldout_tuples, rep.heldout_error, rep.heldout_error_fast);
    if (rep.compact_dim)
      printf(",\"compact\":%d,\"decoder_macs\":%lld,\"variance_kept\":%.5f", rep.compact_dim,
             rep.decoder_macs, rep.compact_kept);
    printf("}\n");
  } else {
    printf("wrote %s: %d x %d %s, %zu BRDFs (%zu evaluated, %zu reused from earlier bands)\n", out,
           rep.width, rep.height, rep.colour_channels == 3 ? "rgb" : "mono", rep.brdfs,
           rep.evaluated, rep.reused);
    if (rep.audited)
      printf("energy audit: max decoded directional albedo %.4f over %zu distinct latents\n",
             rep.max_albedo, rep.audited);
    if (rep.accuracy != NBRDF_BAKE_FAST)
      printf("accuracy %s (budget %g s): %zu of %zu distinct tuples fitted; lobe error on %zu "
             "held-out tuples: median %.2f %% (fast: %.2f %%)\n",
             nbrdf_bake_accuracy_name(rep.accuracy), rep.budget, rep.fitted_tuples, rep.distinct,
             rep.heldout_tuples, 100.0 * rep.heldout_error, 100.0 * rep.heldout_error_fast);
    if (rep.compact_dim)
      printf("compact: %d latent channels per colour channel (%.2f %% of the scene's latent "
             "variance), decoder %lld multiply-adds per query\n",
             rep.compact_dim, 100.0 * rep.compact_kept, rep.decoder_macs);
    /* Above fitted the texture does not carry --decoder itself: say what became of it. */
    if (decoder && rep.compact_dim)
      printf("decoder: %s, fine-tuned to the scene, taught the compact decoder the texture "
             "carries\n",
             decoder);
    else if (decoder && rep.accuracy == NBRDF_BAKE_SPECIALISED)
      printf("decoder: %s, fine-tuned to the scene, is the decoder the texture carries\n",
             decoder);
  }
  return CLI_EXIT_OK;
}
