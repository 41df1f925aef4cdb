/* The bake: six layered-BRDF parameter sources (constants or maps) -> a
 * tiled, mip-mapped latent OpenEXR texture (docs/LATENT-TEXTURE.md).
 *
 * Per texel and colour channel the bake looks up the base latents (top
 * dielectric at (alpha1, eta), bottom conductor at (alpha2, r0)) in the
 * model's tables, runs the layering network with (albedo, sigma_t) and the
 * sampling network for the proxy's (sigma, w) (paper §3-§5). Rows are
 * processed a band at a time, and within a band every distinct parameter
 * tuple is evaluated once, so painted maps with few distinct values and
 * constant inputs cost (almost) nothing per texel.
 *
 * Example (`model` a loaded bundle, nbrdf_model_load; tests/docs compiles it):
 *   nbrdf_error err;
 *   nbrdf_bake_inputs in = NBRDF_BAKE_INPUTS_DEFAULT;
 *   nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_ALPHA1], 0.2f);
 *   in.param[NBRDF_BAKE_R0].path = "r0.png"; // the other four likewise
 *   nbrdf_bake_options opts = NBRDF_BAKE_OPTIONS_DEFAULT;
 *   nbrdf_bake_report rep;
 *   if (nbrdf_bake(model, &in, &opts, "out.exr", &rep, &err) != NBRDF_OK)
 *     fprintf(stderr, "bake: %s\n", err.message);
 *
 * A failed or cancelled bake leaves no output file and never touches an
 * input; the output is written to a temporary file and renamed on success.
 * nbrdf_bake may run in any thread; several bakes may share one model. */
#ifndef NBRDF_BAKE_H
#define NBRDF_BAKE_H

#include <signal.h>
#include <stddef.h>
#include <stdint.h>

#include "nbrdf/model.h"
#include "nbrdf/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The six parameters' ids (nbrdf_bake_param_id), the roughness convention
 * (nbrdf_roughness) and NBRDF_BAKE_SIGMA_T_MAX are the layered material's, declared in
 * nbrdf/model.h. */

/* "alpha1", "eta", "alpha2", "r0", "albedo", "sigma_t". */
const char *nbrdf_bake_param_name(nbrdf_bake_param_id id);

/* One parameter: a constant (path == NULL) or an image file that OpenImageIO
 * reads (1 or 3 channels; a 4th is alpha and ignored). */
typedef struct nbrdf_bake_param {
  const char *path; /* NULL: the constant below */
  float value[3];   /* constant: value[0] (grey) or value[0..2] (RGB) */
  int channels;     /* constant: 1 or 3 */
  /* Maps of r0 and albedo only: colour space of an 8/16-bit image (NULL:
   * "srgb"; half/float images are linear); alpha, eta, sigma_t are
   * non-colour data and never converted. */
  const char *colour_space;
  /* 8/16-bit images only: map [0, 1] linearly onto [lo, hi] (e.g. eta in
   * [1, 2], sigma_t in [0, 5]); float images hold physical values. */
  int remap;
  float lo, hi;
} nbrdf_bake_param;

#define NBRDF_BAKE_PARAM_DEFAULT                                                                   \
  { NULL, {0.0f, 0.0f, 0.0f}, 1, NULL, 0, 0.0f, 1.0f }

/* Maps of different sizes, or maps whose size is not the asked output size
 * (nbrdf_bake_inputs.width/height): an error naming both (NONE), or every map
 * resampled bilinearly (BILINEAR; texel centres aligned, edges clamped) to
 * the output size, or when none is asked to the largest width and the
 * largest height among them. Bilinear is not a box filter: reducing a map
 * by more than 2x skips texels. */
typedef enum nbrdf_resample { NBRDF_RESAMPLE_NONE = 0, NBRDF_RESAMPLE_BILINEAR = 1 } nbrdf_resample;

typedef struct nbrdf_bake_inputs {
  nbrdf_bake_param param[NBRDF_BAKE_PARAM_COUNT]; /* indexed by nbrdf_bake_param_id */
  const char *ocio_config; /* colour spaces of maps are looked up here; NULL: $OCIO */
  nbrdf_resample resample;
  /* Output size of level 0 in texels, 1..NBRDF_BAKE_SIZE_MAX each; 0 x 0:
   * the maps' size (1 x 1 when every input is a constant). With maps of
   * another size, resample must be BILINEAR (else an error saying so). */
  int width, height;
} nbrdf_bake_inputs;

/* The largest width and height of a latent texture. */
#define NBRDF_BAKE_SIZE_MAX 65536

#define NBRDF_BAKE_INPUTS_DEFAULT                                                                  \
  {                                                                                                \
    {NBRDF_BAKE_PARAM_DEFAULT, NBRDF_BAKE_PARAM_DEFAULT, NBRDF_BAKE_PARAM_DEFAULT,                 \
     NBRDF_BAKE_PARAM_DEFAULT, NBRDF_BAKE_PARAM_DEFAULT, NBRDF_BAKE_PARAM_DEFAULT},                \
        NULL, NBRDF_RESAMPLE_NONE, 0, 0                                                            \
  }

/* Sets a grey constant. */
void nbrdf_bake_param_constant(nbrdf_bake_param *p, float value);
/* A command-line argument: "0.3" (grey) or "0.8,0.5,0.2" (RGB) is a
 * constant (decimal numbers, white space around them allowed; no hex, inf or
 * nan), anything else the path of an existing file (kept as a pointer into
 * `arg`; write "./0.5" for a file named like a number). NBRDF_ERR_ARGUMENT,
 * naming the parameter, for a number that overflows or underflows a float
 * and for text that is neither numbers nor an existing file. */
nbrdf_status nbrdf_bake_param_parse(const char *name, const char *arg, nbrdf_bake_param *p,
                                    nbrdf_error *err);

typedef enum nbrdf_bake_storage { NBRDF_BAKE_HALF = 0, NBRDF_BAKE_FLOAT = 1 } nbrdf_bake_storage;

/* Lossless EXR compression of the texture (docs/BAKE.md, "Benchmark"): ZIP
 * is the smallest everywhere and shrinks painted textures ~100x, but saves
 * only ~15 % on all-distinct latents for ~40 % of such a bake's CPU time;
 * RLE and NONE write fastest. */
typedef enum nbrdf_bake_compression {
  NBRDF_BAKE_ZIP = 0,
  NBRDF_BAKE_PIZ,
  NBRDF_BAKE_RLE,
  NBRDF_BAKE_UNCOMPRESSED
} nbrdf_bake_compression;

/* Accuracy levels (docs/BAKE.md, "Accuracy levels"):
 * - FAST: the universal networks only (today's bake; bytes unchanged).
 * - FITTED: the scene's representative tuples get their layered ground truth
 *   (random walk) and are projected into latents with the frozen universal
 *   decoder, starting from the network's latents; the correction is carried
 *   to every texel over parameter space. Every reader decodes the result.
 * - SPECIALISED: as FITTED, then a copy of the decoder is fine-tuned on the
 *   scene's ground truth together with the latents; the texture carries that
 *   decoder (latent texture format 2; nbrdf_model_for_texture decodes it).
 * - COMPACT: as SPECIALISED, then the scene's latents are stored in
 *   compact_dim principal coordinates per colour channel (<= 8, against the
 *   bundle's 32) and a small decoder (compact_width wide, about 1,900
 *   multiply-adds per query at 8 x 32) is distilled for the scene from the
 *   specialised one and the ground truth; the texture carries it. A texture
 *   a renderer decodes fast, at about a third of the channels.
 * - AUTO: the cheapest of the above that meets max_error (docs/BAKE.md, "auto"): the fast
 *   level's held-out error is measured first; above max_error the bake climbs fitted, then
 *   specialised (then compact, when compact_dim is given), each at the budget, and stops at
 *   the first that meets it.
 * A level whose held-out error is worse than fast's on the same tuples (beyond
 * BAKE_FALLBACK_MARGIN, 0.25 percentage points) falls back to fast: the texture is fast's,
 * a warning and the header say so. */
typedef enum nbrdf_bake_accuracy {
  NBRDF_BAKE_FAST = 0,
  NBRDF_BAKE_FITTED = 1,
  NBRDF_BAKE_SPECIALISED = 2,
  NBRDF_BAKE_COMPACT = 3,
  NBRDF_BAKE_AUTO = 4
} nbrdf_bake_accuracy;

/* Default budgets in seconds of the deterministic cost model (not wall
 * clock: the same inputs and budget give the same bake on any machine). */
#define NBRDF_BAKE_BUDGET_FITTED 120.0
#define NBRDF_BAKE_BUDGET_SPECIALISED 300.0
#define NBRDF_BAKE_BUDGET_COMPACT 400.0

/* "fast", "fitted", "specialised", "compact", "auto"; parse returns -1 for anything else. */
const char *nbrdf_bake_accuracy_name(nbrdf_bake_accuracy a);
int nbrdf_bake_accuracy_parse(const char *name);

/* One parameter's values outside the model's trained range, found by the range check that
 * nbrdf_bake runs over every source before any network work (docs/BAKE.md, "Range check").
 * Values are in the units the user typed: perceptual roughness r for alpha1 and alpha2 under
 * NBRDF_ROUGHNESS_PERCEPTUAL (the range as sqrt of alpha's), IOR for eta. */
typedef struct nbrdf_bake_range {
  int param;         /* NBRDF_BAKE_ALPHA1 ... NBRDF_BAKE_SIGMA_T */
  const char *name;  /* "alpha1", "eta", ... */
  const char *units; /* "perceptual roughness", "GGX alpha", "IOR", "reflectance", "albedo",
                      * "optical depth" */
  int constant;      /* the source is a constant: it counts as one texel */
  /* Texels (each once, whatever its channels) below lo and above hi; min is the lowest value
   * below, max the highest above (each meaningful only when its count is non-zero). */
  size_t below, above;
  double min, max;
  double lo, hi;             /* the trained range */
  nbrdf_range_policy policy; /* CLAMP: baked as lo or hi; REFUSE: the bake fails after the report */
  /* alpha1 and alpha2: the lowest value (units as lo) that the levels fitting their own ground
   * truth (FITTED, SPECIALISED, COMPACT, and AUTO when it climbs there) take as given, below
   * lo (GGX alpha NBRDF_GT_ALPHA_MIN); FAST still bakes what is below lo as lo. Any other
   * parameter: lo. below_fit counts the texels below fit_lo (counted in `below` too). */
  double fit_lo;
  size_t below_fit;
  nbrdf_bake_accuracy accuracy; /* the level asked for: what the message says happens */
} nbrdf_bake_range;

/* The report's line in words, e.g. "alpha1 (perceptual roughness): 1,204 texels below 0.1
 * (min 0.02) will be baked as 0.1", or at a fitting level "alpha1 (GGX alpha): 0.002 is below
 * 0.01: fast bakes it as 0.01; fitted, specialised and compact fit it as given". Returns `buf`. */
const char *nbrdf_bake_range_message(const nbrdf_bake_range *range, char *buf, size_t cap);

typedef struct nbrdf_bake_options {
  nbrdf_bake_storage storage; /* half (default) or float latents */
  int mip_levels;             /* 0: the full mip chain; 1: level 0 only */
  int tile_size;              /* EXR tile edge, 8..1024 (64) */
  nbrdf_roughness roughness;
  /* Values outside what the model was trained on (alpha1, eta outside the
   * dielectric table, alpha2 outside the conductor table, sigma_t above
   * NBRDF_BAKE_SIGMA_T_MAX): CLAMP moves them onto the range; REFUSE fails
   * naming the file and texel. Either way every parameter outside is
   * reported first, before any network work (range_report).
   * r0 or albedo above 1 are never physical and always fail. */
  nbrdf_range_policy range;
  /* Called with stage "bake", done/total in rows; `done` moves within a band
   * (fractional rows) as its tuples go through the networks and its rows
   * are written (stage "audit", the same count of rows, while the energy
   * audit measures the band's tuples), at most ~10 times a second (and once at 0 and at total);
   * a non-zero return cancels. May be NULL. */
  nbrdf_progress_fn progress;
  void *user;
  /* Cancels when it becomes non-zero (a signal handler or another thread
   * may set it); checked between chunks of a few thousand tuples or a few
   * rows, well under a second apart (docs/RELIABILITY.md). May be NULL. */
  volatile sig_atomic_t *cancel;
  /* Receives warnings (clamped values), one line each without a newline. May be NULL. */
  void (*warning)(void *user, const char *message);
  /* A fit made before (nbrdf/fit.h, nbrdf_fit_open): the bake runs no fitting and applies
   * that fit's correction and decoder (budget, seed and compact_* are the fit's then, and
   * accuracy is FAST or the fit's level); nbrdf_fit_check's refusals first. NULL (default):
   * the level fits the texture's own tuples, then bakes, in one call. */
  const struct nbrdf_fit *fit;
  /* Distinct tuples remembered across bands of rows (each band evaluates its
   * own distinct tuples once; this carries them on, for painted maps that
   * repeat them everywhere). NBRDF_BAKE_TUPLE_CACHE_DEFAULT (65,536: about
   * 11 MB at latent_dim 32); 0 turns it off. The texels are the same bits
   * either way. */
  size_t tuple_cache;
  /* 0 (default): parameters used as read. 2..16: each parameter is rounded
   * to one of 2^bits levels over the model's trained range (alpha evenly in
   * sqrt(alpha), sigma_t in log(1 + sigma_t), the others linearly), so that
   * maps with smoothly varying values collapse onto fewer distinct tuples.
   * docs/BAKE.md, "Quantisation", measures the trade. */
  int quantise_bits;
  nbrdf_bake_compression compression; /* ZIP (default) */
  /* Energy audit (docs/BAKE.md, "Energy audit"): the maximum over θi of the
   * decoded directional albedo of each distinct latent the bake evaluates,
   * for the first `energy_audit` of them (NBRDF_BAKE_ENERGY_AUDIT_DEFAULT,
   * 16,384; a latent is measured only where no bound from a measured neighbour
   * in parameter space clears it); the worst goes into the
   * header as nbrdf:maxAlbedo, and above 1.01 `warning` names its texel and parameters. 0 turns it
   * off. The texels are the same either way. */
  size_t energy_audit;
  nbrdf_bake_accuracy accuracy;       /* FAST (default) */
  /* FITTED and SPECIALISED: seconds of the deterministic cost model the
   * ground truth and the fit may take (<= 0: the level's default,
   * NBRDF_BAKE_BUDGET_*). A budget too small for the level fails with
   * NBRDF_ERR_ARGUMENT saying what it could do. Progress then also reports
   * stages "ground truth" and "fit" before "bake". */
  double budget;
  uint64_t seed; /* random walks and tuple selection of FITTED/SPECIALISED/COMPACT */
  /* COMPACT: latent channels per colour channel (1..8; 0: 8) and the small
   * decoder's width (4..256; 0: 32). */
  int compact_dim, compact_width;
  /* Where the networks run (docs/GPU.md): CPU (default), AUTO (a GPU where there is one) or
   * GPU (an error without one). On a GPU the bake hands the layering and sampling networks
   * and the energy audit's decoder batches of ~1e5 tuples; the texels agree with the CPU's
   * within float rounding (not bit for bit). */
  nbrdf_device device;
  /* Receives one line saying where the networks run (AUTO and GPU only; e.g. "no GPU for
   * the networks (...): they run on the CPU"). May be NULL. */
  void (*note)(void *user, const char *message);
  /* Receives the range check's findings, one call per parameter with values outside the
   * trained range, all of them before any network work and before a REFUSE fails. NULL: each
   * goes to `warning` as nbrdf_bake_range_message's line. */
  void (*range_report)(void *user, const nbrdf_bake_range *range);
  /* Optional: a fingerprint of what the caller made the texture from (its inputs' sizes and
   * times, the options: any text), stored in the header as nbrdf:inputs, so that a later
   * run can tell a texture that is up to date from a stale one (a tile set's resumed bake).
   * NULL (default): no attribute, the file as without it. */
  const char *inputs;
  /* AUTO: the held-out lobe error to meet, in percent (verify's metric; > 0, required). */
  double max_error;
  /* AUTO: when no level within the budget meets max_error, fail (NBRDF_ERR_UNSUPPORTED, no
   * file) instead of baking the best level reached with a warning. */
  int require;
  /* Non-zero: a level worse than fast on its held-out tuples is baked anyway (with the
   * warning) instead of falling back to fast: for measuring the levels themselves. */
  int no_fallback;
  /* SPECIALISED and COMPACT: the weight of the energy term in the decoder fine-tune (docs/BAKE.md,
   * "Sharp coats"): 0 (default) NBRDF_BAKE_FIT_ENERGY_DEFAULT, < 0 off (for measuring what it
   * does; the held-out check's energy guard still falls back). */
  double fit_energy;
} nbrdf_bake_options;

#define NBRDF_BAKE_FIT_ENERGY_DEFAULT 0.1

#define NBRDF_BAKE_ENERGY_AUDIT_DEFAULT 16384

#define NBRDF_BAKE_TUPLE_CACHE_DEFAULT 65536

#define NBRDF_BAKE_OPTIONS_DEFAULT                                                                 \
  {                                                                                                \
    NBRDF_BAKE_HALF, 0, 64, NBRDF_ROUGHNESS_ALPHA, NBRDF_RANGE_CLAMP, NULL, NULL, NULL, NULL, NULL,\
        NBRDF_BAKE_TUPLE_CACHE_DEFAULT, 0, NBRDF_BAKE_ZIP, NBRDF_BAKE_ENERGY_AUDIT_DEFAULT,        \
        NBRDF_BAKE_FAST, 0.0, 1u, 0, 0, NBRDF_DEVICE_CPU, NULL, NULL, NULL, 0.0, 0, 0, 0.0       \
  }

/* What a finished bake did (optional output of nbrdf_bake). */
typedef struct nbrdf_bake_report {
  int width, height;   /* level 0 */
  int colour_channels; /* 1 (mono) or 3 (RGB) */
  size_t brdfs;        /* texels x colour channels */
  size_t evaluated;    /* tuples evaluated by the networks (distinct per band, summed) */
  size_t reused;       /* distinct tuples of a band taken from the cross-band cache */
  size_t clamped;      /* texel channels with a clamped parameter */
  size_t audited;      /* distinct latents of the energy audit */
  double max_albedo;   /* their largest decoded directional albedo (NaN: none audited) */
  /* FITTED / SPECIALISED (0 for FAST): */
  nbrdf_bake_accuracy accuracy;
  double budget;          /* the budget used, cost-model seconds */
  size_t distinct;        /* distinct tuples of the maps (the selection's candidates) */
  size_t fitted_tuples;   /* tuples whose ground truth the fit used */
  size_t heldout_tuples;  /* tuples held out of the fit for the error estimate */
  double heldout_error;   /* median lobe error (fraction) on the held-out tuples */
  double heldout_error_fast; /* the same tuples with the universal networks alone */
  /* COMPACT (0 otherwise): latent channels per colour channel, the decoder's
   * multiply-adds per query, and the variance of the scene's latents they keep. */
  int compact_dim;
  long long decoder_macs;
  double compact_kept;
  char device[128]; /* where the networks ran: "cpu" or the GPU's name */
  /* The accuracy asked for (AUTO or a level); `accuracy` above is the texture's. */
  nbrdf_bake_accuracy requested;
  /* The level asked for (or auto's best) was worse than fast on its held-out tuples beyond
   * the margin, or created energy (creates_energy below): the texture is fast's (accuracy
   * FAST; heldout_error is the level's). */
  int fell_back;
  /* AUTO: the target (percent), whether a level met it, every level tried in order (fast
   * first) with its held-out median (fraction), and when none met it the budget that would
   * likely reach it (0: more budget is unlikely to help). */
  double max_error;
  int met, tried;
  nbrdf_bake_accuracy tried_level[4];
  double tried_error[4];
  double suggested_budget;
  /* Of `audited`, the latents the energy audit measured with the decoder (the
   * others were cleared by a bound from a measured neighbour), and the
   * process CPU seconds the audit took. */
  size_t audit_measured;
  double audit_seconds;
  /* FITTED / SPECIALISED / COMPACT: the held-out check's energy guard (docs/BAKE.md,
   * "Held-out check"): the largest decoded directional albedo of the level's latents over the
   * fit_albedo_tuples fitted and held-out tuples, fast's on the same tuples, and whether the
   * level creates energy there (above max(1.01, fast's + 0.03): it then falls back, or auto
   * does not choose it). fit_albedo_tuples 0: not measured (a fit file from before). */
  size_t fit_albedo_tuples;
  double fit_max_albedo, fit_max_albedo_fast;
  int creates_energy;
} nbrdf_bake_report;

/* Bakes `inputs` with `model` into `out_path`. All maps must share one
 * size (the error names the two that differ) unless resampled; the output
 * is inputs->width x height when given, else the maps' size, else (every
 * input a constant) 1 x 1. The texture is mono when every source has one channel,
 * else RGB (each channel its own BRDF; a grey source serves all three).
 * `options` NULL means defaults; `report` may be NULL. */
/* The checks nbrdf_bake makes of `options` before it reads any input, with
 * this model (its decoder's cost): NBRDF_ERR_ARGUMENT naming the option, e.g.
 * a budget too small for the accuracy level's smallest plan. A tool calls it
 * to tell a bad option (a usage error) from a failure of the inputs. */
nbrdf_status nbrdf_bake_options_check(const nbrdf_model *model, const nbrdf_bake_options *options,
                                      nbrdf_error *err);

nbrdf_status nbrdf_bake(const nbrdf_model *model, const nbrdf_bake_inputs *inputs,
                        const nbrdf_bake_options *options, const char *out_path,
                        nbrdf_bake_report *report, nbrdf_error *err);

#ifdef __cplusplus
}
#endif
#endif
