/* The reference evaluator: how close a baked latent texture is to the
 * physics of the parameters it was baked from (docs/VERIFY.md).
 *
 * For each chosen texel and colour channel the texture's latent is decoded
 * into the lobe images of METRICS.md (64×64, θi = 0°, 30°, 60°, 80°) and
 * compared with the same images of the layered ground truth of that texel's
 * parameters (the Monte Carlo whole-lobe estimator, two independent runs
 * whose mean is the reference and whose difference is the reference's own
 * seed-to-seed error). A texel of mip level k is compared with the average
 * of the ground-truth lobe images over its level-0 footprint — the average
 * of the BRDFs, since lobe images are linear in f — which measures what
 * averaging latents costs.
 *
 * Example (`model` a loaded bundle, `in` the bake's inputs; tests/docs compiles it):
 *   nbrdf_error err;
 *   nbrdf_verify_options opts = NBRDF_VERIFY_OPTIONS_DEFAULT;
 *   nbrdf_verify_report *rep = NULL;
 *   if (nbrdf_verify(model, "tex.exr", &in, &opts, &rep, &err) == NBRDF_OK)
 *     printf("median lobe error %.2f %%\n", rep->overall.median);
 *   nbrdf_verify_report_free(rep);
 *
 * The parameter inputs are those of nbrdf_bake (nbrdf_bake_inputs). A
 * texture baked with another model (checksum) or of another format version
 * fails with NBRDF_ERR_MISMATCH / NBRDF_ERR_FORMAT before any work. */
#ifndef NBRDF_VERIFY_H
#define NBRDF_VERIFY_H

#include <signal.h>
#include <stddef.h>
#include <stdint.h>

#include "nbrdf/bake.h"
#include "nbrdf/model.h"
#include "nbrdf/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* `level` value: every mip level of the texture. */
#define NBRDF_VERIFY_ALL_LEVELS (-1)
/* `roughness` value: as the texture's bake settings record it. */
#define NBRDF_VERIFY_ROUGHNESS_FROM_TEXTURE (-1)

typedef struct nbrdf_verify_options {
  /* Texels per level: a level with at most this many is compared whole,
   * a larger one by a stratified sample of this many (one jittered texel
   * per cell of a grid). >= 1. */
  int texels;
  int level; /* mip level, or NBRDF_VERIFY_ALL_LEVELS */
  /* Random walks per lobe image and per run of the ground truth (two runs
   * per reference). Its noise falls as 1/sqrt(walks); docs/VERIFY.md. */
  int walks;
  /* At most this many level-0 texels (a regular grid over the footprint)
   * are averaged for a texel of a coarser level. */
  int footprint_max;
  uint64_t seed; /* the references' seed; the texel sample's too */
  int threads;   /* for the ground truth; 0 = all cores */
  int roughness; /* an nbrdf_roughness or NBRDF_VERIFY_ROUGHNESS_FROM_TEXTURE */
  /* Stage "verify", done/total in texels; `done` moves within a texel
   * (fractional) as its ground truth's lobe images are computed, at most
   * ~10 times a second (and once at 0 and at total); a non-zero return
   * cancels. May be NULL. */
  nbrdf_progress_fn progress;
  void *user;
  /* Cancels when non-zero; checked between chunks of the ground truth's
   * random walks, well under a second apart (docs/RELIABILITY.md). May be NULL. */
  volatile sig_atomic_t *cancel;
} nbrdf_verify_options;

#define NBRDF_VERIFY_OPTIONS_DEFAULT                                                               \
  { 256, 0, 256, 16, 0u, 0, NBRDF_VERIFY_ROUGHNESS_FROM_TEXTURE, NULL, NULL, NULL }

/* One compared texel (all its colour channels together). */
typedef struct nbrdf_verify_texel {
  int level, x, y; /* the texel in its level */
  int footprint;   /* level-0 texels whose references were averaged (1 at level 0) */
  /* The ground truth's parameters per colour channel (after the roughness
   * mapping; for a coarser level, their mean over the footprint texels
   * used), indexed by nbrdf_bake_param_id. Mono textures use [id][0]. */
  float params[NBRDF_BAKE_PARAM_COUNT][3];
  double lobe_error;      /* METRICS.md lobe error over every channel's images, a fraction */
  double albedo_error;    /* mean |ρ̂ − ρ| over the channels and the four θi */
  double reference_noise; /* lobe error between the reference's two runs, a fraction */
  /* Energy: the largest decoded directional albedo over θi ∈ {0, 30, 60, 80,
   * 85, 89}° of its colour channels' latents (the bake's energy audit; above
   * 1.01 the model creates energy); NaN for a damaged latent. */
  double max_albedo;
} nbrdf_verify_texel;

/* Statistics of the lobe error over a set of texels (fractions). */
typedef struct nbrdf_verify_summary {
  int level; /* NBRDF_VERIFY_ALL_LEVELS for the overall summary */
  size_t texels;
  double median, p90, worst;
  double albedo_median;
  double noise_median; /* the references' own seed-to-seed lobe error, median */
} nbrdf_verify_summary;

typedef struct nbrdf_verify_report {
  int width, height, levels, colours; /* the texture */
  int walks;                          /* per image per run */
  uint64_t seed;
  size_t n_texels;
  nbrdf_verify_texel *texels; /* in the order compared: by level, then row, column */
  int n_levels;
  nbrdf_verify_summary *per_level; /* one per level compared */
  nbrdf_verify_summary overall;
  size_t references;      /* distinct ground-truth BRDFs estimated (2 runs each) */
  size_t decoded;         /* distinct latents decoded into lobe images */
  size_t decoder_queries; /* decoder evaluations (one colour channel each) */
  size_t clamped;         /* parameters moved into the ground truth's range, per look-up */
  /* Look-ups (as `clamped`) whose alpha1 or alpha2 is below the model's trained range
   * (alpha_trained_min for alpha1): the ground truth is still that of the values as given.
   * alpha_clamped_by_texture: the texture is at the fast level (or fell back to it), whose
   * latents stand for such alpha clamped to the trained minimum; else a fitting level fitted
   * them as given (docs/BAKE.md, "Sharp coats"). */
  size_t below_trained_alpha;
  int alpha_clamped_by_texture;
  double alpha_trained_min;
  /* Every tile of every level is read first; texels (any level) holding a
   * non-finite latent are counted here, the first one located. */
  size_t nonfinite;
  int nonfinite_level, nonfinite_x, nonfinite_y;
  double reference_seconds, decode_seconds; /* wall clock */
  /* The decoder the texture was decoded with: its own (format version 2,
   * nbrdf_model_for_texture) or the bundle's. */
  nbrdf_decoder_info decoder; /* .bytes is NULL */
  double max_albedo;                        /* the largest max_albedo of the compared texels */
} nbrdf_verify_report;

/* Verifies `texture` against `inputs` with `model`. `options` NULL means
 * defaults. On success *report is the caller's (free it with
 * nbrdf_verify_report_free). The maps must have the texture's size, or be
 * resampled to it as the bake did (inputs->resample BILINEAR; width/height
 * 0 means the texture's size), and their colour channels its colour mode;
 * constants fit any texture. */
nbrdf_status nbrdf_verify(const nbrdf_model *model, const char *texture,
                          const nbrdf_bake_inputs *inputs, const nbrdf_verify_options *options,
                          nbrdf_verify_report **report, nbrdf_error *err);
void nbrdf_verify_report_free(nbrdf_verify_report *report); /* NULL is allowed */

/* The report as JSON (docs/VERIFY.md lists the fields), written to a
 * temporary file and renamed. `worst` texels are listed in full (all when
 * 0). */
nbrdf_status nbrdf_verify_write_json(const nbrdf_verify_report *report, const char *texture,
                                     size_t worst, const char *path, nbrdf_error *err);

/* An 8-bit PNG of `level` (its size, scaled up by an integer factor to at
 * least 256 pixels wide): compared texels coloured by lobe error from
 * dark blue (0) through yellow to red (>= scale, a fraction; <= 0 means the
 * worst texel), texels not compared in grey. */
nbrdf_status nbrdf_verify_write_heatmap(const nbrdf_verify_report *report, int level, double scale,
                                        const char *path, nbrdf_error *err);

#ifdef __cplusplus
}
#endif
#endif
