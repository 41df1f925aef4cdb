/* Model quality on the held-out sets of docs/METRICS.md (`nbrdf evaluate`): for
 * each BRDF of a set, the lobe images of the ground truth and of the neural
 * model at θi ∈ {0°, 30°, 60°, 80°}, their lobe error and albedo error.
 *
 * How the neural latent is obtained per set:
 *   rep     two-layer BRDFs projected (decoder frozen) from data-set samples;
 *   single  conductors and dielectrics projected the same way;
 *   layer   two-layer BRDFs end to end: base-table look-up + layering network;
 *   layer3  three-layer BRDFs: the layering network applied recursively;
 *   table   the `single` BRDFs from the bundle's base tables (bilinear look-up
 *           at off-grid parameters, as a bake): the tables' interpolation
 *           error on top of the projection's. References: those of `single`;
 *   tails   as layer, on two-layer BRDFs drawn only where the universal path
 *           is weakest (train/params.h, TRAIN_DRAWS_TAILS): low-IOR coats,
 *           sharp coats and both, a third each, with figures per region.
 * (layer, layer3, table and tails need a bundle; rep and single a decoder alone.)
 *
 * References: analytic BRDFs are evaluated exactly; layered ones by the
 * whole-lobe estimator with `walks` walks per image. The reference's own
 * noise is measured as the lobe error between two seeds on the first
 * `noise_brdfs` BRDFs (docs/METRICS.md asks for it beside every figure).
 * References are cached in `cache_dir` (if set) as safetensors files keyed by
 * set, count and walks, since they cost far more than the model. */
#ifndef NBRDF_EVAL_EVALUATE_H
#define NBRDF_EVAL_EVALUATE_H

#include "model/decoder.h"
#include "nbrdf/model.h"
#include "train/params.h"

typedef enum eval_set {
  EVAL_REP = 0,
  EVAL_SINGLE,
  EVAL_LAYER,
  EVAL_LAYER3,
  EVAL_TABLE,
  EVAL_TAILS,
  EVAL_TAILS_REP, /* the tails BRDFs projected: the decoder's own limit there */
  EVAL_EXTREMES,  /* named constants at the corners (evaluate_extremes.c), end to end */
  EVAL_SET_COUNT
} eval_set;

typedef struct eval_settings {
  int count;         /* BRDFs per set (docs/METRICS.md: >= 100) */
  int walks;         /* whole-lobe walks per reference image */
  int noise_brdfs;   /* BRDFs whose reference is recomputed with a second seed */
  int project_steps; /* projection steps (rep, single) */
  const char *cache_dir;
  nbrdf_progress_fn progress; /* stage "<set>: reference" / "<set>: model" */
  void *user;
} eval_settings;

#define EVAL_SETTINGS_DEFAULT                                                                      \
  { 100, 16000, 10, 1000, NULL, NULL, NULL }

/* Angles of the point-wise and albedo figures: the four of the lobe
 * error and the grazing 85° and 89° (images of their own, EVAL_N_GRAZING). */
#define EVAL_N_THETA_ALL 6
#define EVAL_N_GRAZING 2
extern const double eval_theta_all_deg[EVAL_N_THETA_ALL];

typedef struct eval_case {
  train_params params;
  double lobe_error;   /* fraction */
  double albedo_error; /* mean over the four θi */
  double max_albedo;   /* of the neural lobe images */
  /* At eval_theta_all_deg (evaluate_grazing.c); NaN where undefined: */
  double pointwise[EVAL_N_THETA_ALL];    /* median |f̂/f − 1| where f > 1 % of the peak */
  double pointwise_all;                  /* the same over the pixels of all six images */
  double mirror_error[EVAL_N_THETA_ALL]; /* |f̂/f − 1| at the mirror direction */
  double albedo[EVAL_N_THETA_ALL];       /* decoded directional albedo (albedo_quad.h) */
  double albedo_ref[EVAL_N_THETA_ALL], albedo_ref_se[EVAL_N_THETA_ALL]; /* nbrdf_brdf_albedo */
} eval_case;

/* The ground truth beyond the four lobe images, per set (cached). */
typedef struct eval_extra_ref {
  double *images;    /* n × EVAL_N_GRAZING × res² lobe images at 85°, 89° */
  double *mirror;    /* n × EVAL_N_THETA_ALL: f at the mirror direction */
  double *albedo;    /* n × EVAL_N_THETA_ALL: directional albedo */
  double *albedo_se; /* its standard error */
} eval_extra_ref;

typedef struct eval_result {
  eval_set set;
  int n;
  eval_case *cases;
  double median, p90, worst, median_albedo_error, max_albedo, ref_noise;
  int worst_index, median_index, max_albedo_index;
  double *ref, *approx; /* n × 4 × 64 × 64 lobe images, for plots */
  /* Per θi of eval_theta_all_deg: median point-wise and mirror errors over the
   * set, and the largest decoded albedo and excess ρ̂ − ρ over its BRDFs. */
  double median_pointwise[EVAL_N_THETA_ALL], median_mirror[EVAL_N_THETA_ALL];
  double median_pointwise_all;
  double max_decoded_albedo[EVAL_N_THETA_ALL], max_albedo_excess[EVAL_N_THETA_ALL];
  int max_decoded_albedo_index, max_decoded_albedo_theta; /* the largest ρ̂ of all */
  /* The median's 90 % bootstrap interval (eval/median_interval.h). */
  double median_lo, median_hi;
  /* tails only: median and p90 lobe error per region (train_tails_region), n of each. */
  double region_median[TRAIN_TAILS_REGIONS], region_p90[TRAIN_TAILS_REGIONS];
  double region_median_lo[TRAIN_TAILS_REGIONS], region_median_hi[TRAIN_TAILS_REGIONS];
  int region_n[TRAIN_TAILS_REGIONS];
  double seconds_reference, seconds_model;
} eval_result;

const char *eval_set_name(eval_set set);
/* The extremes set: its size, the name and the parameters of case `index`. */
#define EVAL_EXTREMES_COUNT 9
const char *eval_extremes_name(int index);
void eval_extremes_params(int index, train_params *p);
/* The most BRDFs a set has (0: any number). */
int eval_set_size_max(eval_set set);
/* Whether a set reports per-region figures (tails, tails-rep). */
int eval_set_has_regions(eval_set set);
/* The set whose reference images a set uses (table: single's; tails-rep: tails'). */
eval_set eval_set_reference_of(eval_set set);
/* The held-out family a set draws from (train/params.h). */
train_heldout eval_set_heldout(eval_set set);
/* BRDF `index` of a set: its held-out family, kind and distribution. */
void eval_set_draw(eval_set set, uint64_t index, train_params *p);
int eval_set_parse(const char *name, eval_set *set);

/* `model` may be NULL for rep and single (then `dec` is used). */
nbrdf_status eval_run(const nbrdf_model *model, model_decoder *dec, eval_set set,
                      const eval_settings *s, eval_result *out, nbrdf_error *err);
void eval_result_free(eval_result *r);

/* Lobe error, albedo error and maximum albedo (into cases[k]) of n latents
 * [n × D] against reference lobe images ref [n × 4 × res²]; the decoded images
 * go to approx (same shape) unless it is NULL. */
nbrdf_status eval_score_latents(model_decoder *dec, size_t n, const float *lat, const double *ref,
                                double *approx, eval_case *cases, nbrdf_error *err);

/* A decoder's f for one latent: the callback (lobe/lobe.h's lobe_images)
 * that evaluates n queries in one decoder pass, directions in float. */
typedef struct eval_decoder_lobe {
  model_decoder *dec;
  model_runner *runner;
  const float *latent;
} eval_decoder_lobe;
nbrdf_status eval_decoder_lobe_fn(void *user, size_t n, const nbrdf_query *q, double *f,
                                  nbrdf_error *err);

/* Lobe images of one BRDF at n_theta angles (degrees), with `walks` walks per
 * image when it is layered; hook (may be NULL) ticks between chunks. */
struct brdf_layered_lobe_hook;
nbrdf_status eval_images_of(const train_params *p, uint64_t seed, int walks,
                            const struct brdf_layered_lobe_hook *hook, int n_theta,
                            const double *theta_deg, double *out, nbrdf_error *err);

/* The extra references of one set (evaluate_grazing.c; cached beside the
 * images); allocated here, freed by eval_extra_ref_free. */
nbrdf_status eval_reference_extra(eval_set set, const eval_settings *s, eval_extra_ref *out,
                                  nbrdf_error *err);
void eval_extra_ref_free(eval_extra_ref *x);

/* Point-wise errors, mirror errors and decoded albedo of n latents (into
 * cases[k]) against ref [n × 4 × res²] and the extra references. `model` (may
 * be NULL) adds each latent's proxy lobe to the albedo quadrature. */
nbrdf_status eval_score_extra(const nbrdf_model *model, model_decoder *dec, size_t n,
                              const float *lat, const double *ref, const eval_extra_ref *x,
                              eval_case *cases, nbrdf_error *err);
/* The set's summary of those figures (into r). */
void eval_summarise_extra(eval_result *r);

/* Ground-truth lobe images of one set (cached); images [count × 4 × res²]. */
nbrdf_status eval_reference(eval_set set, const eval_settings *s, double *images, double *noise,
                            nbrdf_error *err);

/* JSON summary of results, and lobe plots (ref | model | difference) of the
 * worst and median case of each set into plot_dir (may be NULL). */
nbrdf_status eval_write_json(const char *path, const char *model_label, const eval_settings *s,
                             const eval_result *r, int n_results, nbrdf_error *err);
nbrdf_status eval_write_plots(const char *plot_dir, const eval_result *r, int n_results,
                              nbrdf_error *err);

#endif
