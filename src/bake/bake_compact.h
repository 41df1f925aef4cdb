/* The compact accuracy level: a scene's texels span a small family
 * of BRDFs, so its latents are stored in K coordinates per colour channel
 * (c = P (z - mean), K <= 8) of the scene's specialised latents z and decoded
 * by a small decoder distilled for the scene (docs/BAKE.md, "Compact").
 *
 * Why a linear map rather than a nonlinear encoder: a mip texel (the mean of
 * level-0 texels) is then exactly the coordinates of the mean latent, so mip
 * levels stay valid; the proxy of a mip texel is predicted from the
 * least-squares reconstruction mean + B c. P starts as the whitened principal
 * axes of the scene's latents (unit-scale inputs for the small decoder) and
 * learns together with the student.
 *
 * The student learns from two kinds of rows through model/autodecoder.h: the
 * fitted tuples' layered ground truth (so it is not only a copy of the
 * teacher's error), and the specialised teacher's values on up to
 * BAKE_COMPACT_TEACHER tuples chosen across the scene, at the directions of
 * the nearest fitted tuple's ground truth (where its lobe is), at directions
 * the tuple's proxy draws, and at ωi uniform over the hemisphere. */
#ifndef NBRDF_BAKE_BAKE_COMPACT_H
#define NBRDF_BAKE_BAKE_COMPACT_H

#include <signal.h>
#include <stddef.h>

#include "bake/bake_fit.h"
#include "core/progress.h"
#include "model/decoder.h"
#include "texture/latent_layout.h"
#include "train/samples.h"

#define BAKE_COMPACT_MAX_DIM MODEL_COMPACT_MAX_DIM
#define BAKE_COMPACT_DEFAULT_DIM 8
#define BAKE_COMPACT_DEFAULT_WIDTH 32
#define BAKE_COMPACT_TEACHER 512

typedef struct bake_compact {
  int dim;        /* K */
  int work_dim;   /* D, the bundle's latent dimension */
  float *mean;    /* [D] */
  float *basis;   /* [D x K]: z ≈ mean + basis c (least squares after the distillation) */
  float *project; /* [K x D]: c = project (z - mean) */
  double kept;    /* fraction of the scene latents' variance mean + basis c keeps */
  model_decoder *student;
  double loss_truth, loss_teacher; /* final distillation losses (L1 of log1p) */
} bake_compact;

/* The K whitened principal coordinates of n latents [n x D] (the projection's start). */
nbrdf_status bake_compact_basis(const float *z, size_t n, int D, int K, bake_compact *c,
                                nbrdf_error *err);
void bake_compact_free(bake_compact *c);

/* c[K] of one latent z[D]; z[D] from c[K]. */
void bake_compact_reduce(const bake_compact *c, const float *z, float *coords);
void bake_compact_expand(const bake_compact *c, const float *coords, float *z);

typedef struct bake_compact_settings {
  int width;     /* student hidden width */
  int steps;     /* distillation steps */
  int rows;      /* rows drawn per BRDF per step */
  uint64_t seed;
  core_ticker *ticker; /* stage "distil", done/total in steps; may be NULL */
  volatile sig_atomic_t *cancel;
} bake_compact_settings;

/* Everything after the specialised fit: the scene's latents (network + the
 * carried correction `corr`, whose decoder is the teacher) of the n_fit fitted
 * tuples `fit` (their ground truth `truth`, one BRDF each) and of the n_scene
 * tuples `scene` the teacher speaks for; the principal start of the
 * projection; the student and the projection learned together (stage
 * "distil"); the reconstruction basis. */
nbrdf_status bake_compact_build(const nbrdf_model *model, const bake_correction *corr,
                                const bake_tuple *fit, size_t n_fit, const train_samples *truth,
                                const bake_tuple *scene, size_t n_scene, int dim,
                                const bake_compact_settings *s, bake_compact *c,
                                nbrdf_error *err);

/* n texels from the work layout (latent D + proxy) to the compact layout
 * (K + proxy), both in logical order. */
void bake_compact_texels(const bake_compact *c, const texture_latent_layout *work,
                         const float *in, const texture_latent_layout *out_layout, float *out,
                         size_t n);

#endif
