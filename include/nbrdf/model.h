/* The neural BRDF model of Fan et al. 2022: a bundle of three networks and the
 * latent tables of the base BRDFs, loaded from a folder models/<name>/.
 *
 * A BRDF is a latent vector of nbrdf_model_latent_dim() floats (32) per colour
 * channel; every colour channel is an independent single-channel BRDF (paper
 * §3.2), so all calls below work on rows of one latent each.
 *
 * Bundle layout (docs/MODEL_BUNDLE.md):
 *   decoder.safetensors      latent + directions -> f (no cosine)
 *   layering.safetensors     (top, bottom, A, sigma_t) -> layered latent
 *   sampler.safetensors      latent -> (sigma, w) of the pdf proxy
 *   base_tables.safetensors  latents of the top dielectric on an (alpha1, eta)
 *                            grid and of the bottom conductor on (alpha2, r0)
 *   model.json, MODEL_CARD.md
 * Each network file carries its architecture in the safetensors __metadata__;
 * loading validates the files against each other.
 *
 * The checksum is FNV-1a 64 over the bytes of the four .safetensors files in
 * the order above, as 16 lower-case hex digits; model.json must record it,
 * and a latent texture records it so that a texture baked with another model
 * is refused. model.json's statements about the networks and the tables must
 * equal the files' (docs/MODEL_BUNDLE.md, "Checksums").
 *
 * A loaded model is immutable: any call may run on one model from several
 * threads at once (each call allocates its own scratch buffers).
 *
 * A coat of roughness 0.2, IOR 1.5 over a conductor (0.3, R0 0.9), slab A = 0.8,
 * sigma_t = 1, decoded for one direction pair:
 * Example (`model` a loaded bundle, nbrdf_model_load; tests/docs compiles it):
 *   nbrdf_error err;
 *   int D = nbrdf_model_latent_dim(model);
 *   float alpha1 = 0.2f, eta = 1.5f, alpha2 = 0.3f, r0 = 0.9f, albedo = 0.8f, sigma_t = 1.0f;
 *   float top[D], bottom[D], layered[D], f;
 *   float wi[3] = {0.0f, 0.0f, 1.0f}, wo[3] = {0.6f, 0.0f, 0.8f};
 *   nbrdf_status st = nbrdf_model_base_latents(model, NBRDF_BASE_DIELECTRIC, 1, &alpha1, &eta,
 *                                              NBRDF_RANGE_CLAMP, top, NULL, &err);
 *   if (st == NBRDF_OK)
 *     st = nbrdf_model_base_latents(model, NBRDF_BASE_CONDUCTOR, 1, &alpha2, &r0,
 *                                   NBRDF_RANGE_CLAMP, bottom, NULL, &err);
 *   if (st == NBRDF_OK)
 *     st = nbrdf_model_layer(model, 1, top, bottom, &albedo, &sigma_t, layered, &err);
 *   if (st == NBRDF_OK) st = nbrdf_model_decode(model, 1, 1, layered, wi, wo, &f, &err);
 *   if (st != NBRDF_OK) fprintf(stderr, "model: %s\n", err.message);
 */
#ifndef NBRDF_MODEL_H
#define NBRDF_MODEL_H

#include <stddef.h>
#include <stdint.h>

#include "nbrdf/status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct nbrdf_model nbrdf_model;

/* Loads and validates the bundle in folder `dir`. Messages name the file
 * ("models/x/layering.safetensors: ..."). */
nbrdf_status nbrdf_model_load(const char *dir, nbrdf_model **out, nbrdf_error *err);
void nbrdf_model_destroy(nbrdf_model *model); /* NULL is allowed */

/* The default bundle, without a path. It is looked up in this order; the first place that
 * holds a model.json wins:
 *   1. $NBRDF_BUNDLE, when set and not empty. It must then be a bundle folder: a missing
 *      folder is an error naming it, never a silent fallback to the places below.
 *   2. The installed bundle, share/nbrdf/models/default of the install prefix, found at run
 *      time from the folder of the loaded libnbrdf (dladdr) and of the executable
 *      (/proc/self/exe), so a moved install still finds its own.
 *   3. models/default of the source tree the library was built from (a program run from a
 *      build folder).
 *   4. models/default in the current directory.
 * Writes the folder into `path` (NUL-terminated, `size` bytes at most). When nothing is
 * found, fails with NBRDF_ERR_IO and a message listing every place tried. */
/* Where the networks run (docs/GPU.md): the CPU (OpenBLAS), or a GPU through Vulkan compute
 * (the Vulkan loader is loaded at run time; no GPU, no loader or a build without GPU support
 * means the CPU). The options of nbrdf_bake take one; the CLI's --device and $NBRDF_DEVICE. */
typedef enum nbrdf_device {
  NBRDF_DEVICE_CPU = 0,  /* OpenBLAS: the library's default */
  NBRDF_DEVICE_AUTO = 1, /* a discrete or integrated GPU where there is one (never lavapipe
                            unless $NBRDF_VK_DEVICE names it), else the CPU, with a note */
  NBRDF_DEVICE_GPU = 2   /* the device $NBRDF_VK_DEVICE names (a substring of its name;
                            "llvmpipe" is lavapipe), else the first GPU; an error when none */
} nbrdf_device;

/* "cpu", "auto", "gpu"; parse returns -1 for anything else. */
const char *nbrdf_device_name(nbrdf_device device);
int nbrdf_device_parse(const char *name);

nbrdf_status nbrdf_default_bundle_path(char *path, size_t size, nbrdf_error *err);
/* nbrdf_default_bundle_path, then nbrdf_model_load. `path_used` (may be NULL) receives the
 * folder; a load error names it. */
nbrdf_status nbrdf_model_load_default(nbrdf_model **out, char *path_used, size_t size,
                                      nbrdf_error *err);

/* model.json's "name" (e.g. "default"). */
const char *nbrdf_model_name(const nbrdf_model *model);
/* The bundle checksum, 16 hex digits (see above). */
const char *nbrdf_model_checksum(const nbrdf_model *model);
/* Latent floats per colour channel. */
int nbrdf_model_latent_dim(const nbrdf_model *model);
/* 0 for a bundle of randomly initialised networks (`nbrdf bundle init`). */
int nbrdf_model_is_trained(const nbrdf_model *model);
/* Multiply-adds per decoder query (one channel) and per layering evaluation. */
int64_t nbrdf_model_decoder_macs(const nbrdf_model *model);
int64_t nbrdf_model_layering_macs(const nbrdf_model *model);
/* The bundle's files, as "DIR/name": model.json, the four .safetensors the
 * model was read from, then MODEL_CARD.md (not read, but part of the bundle).
 * A command passes them as inputs no output may overwrite. Returns their count
 * (6); the strings live as long as the model. */
int nbrdf_model_files(const nbrdf_model *model, const char *const **paths);

/* ----------------------------------------------------------- own decoders */

/* A latent texture may carry its own decoder (latent texture format version 2,
 * docs/LATENT-TEXTURE.md), e.g. one fine-tuned on the scene's BRDFs; it then
 * must be decoded with that decoder and the bundle's other parts. A model
 * "with its own decoder" is such a pair: the bundle's layering and sampling
 * networks, tables, name and checksum (nbrdf_model_checksum is the bundle's),
 * and a decoder read from safetensors bytes. nbrdf_bake with such a model
 * embeds the decoder's bytes in the texture; nbrdf_verify, nbrdf_render and
 * nbrdf_render_lobes decode a texture with its own decoder when it has one;
 * a GPU integration packs the decoder of nbrdf_model_for_texture's model
 * (nbrdf_gpu_pack_decoder).
 *
 * The derived model keeps what it shares with `base` alive: `base` may be
 * destroyed first. Every model returned below is released with
 * nbrdf_model_destroy and is as immutable and thread-safe as a loaded one. */

/* The largest decoder a texture may carry, in bytes (64 MiB; the default
 * decoder is about 120 KB). */
#define NBRDF_DECODER_BYTES_MAX ((size_t)64 << 20)

/* `base` with its decoder replaced by the one in `bytes` (`size` bytes of a
 * decoder.safetensors file, docs/MODEL_BUNDLE.md; copied). The decoder must be
 * a valid nbrdf decoder file whose latent dimension is at most the bundle's:
 * fewer is a compact texture's decoder (issue 19), and the model then decodes
 * latents of that size (nbrdf_model_latent_dim) while refusing the calls that
 * need the bundle's (base latents, layer, proxy) with NBRDF_ERR_UNSUPPORTED.
 * `label` (e.g. a file name; NULL: "decoder") starts every message. */
nbrdf_status nbrdf_model_with_decoder(const nbrdf_model *base, const void *bytes, size_t size,
                                      const char *label, nbrdf_model **out, nbrdf_error *err);
/* The same with the bytes of the file at `path`. */
nbrdf_status nbrdf_model_with_decoder_file(const nbrdf_model *base, const char *path,
                                           nbrdf_model **out, nbrdf_error *err);

/* The model that decodes the latent texture at `texture_path`: `bundle` with
 * the texture's own decoder when it carries one, else a new reference to
 * `bundle` itself (destroy it either way). The texture must have been baked
 * with this bundle (checksum and latent dimension, NBRDF_ERR_MISMATCH). A
 * damaged embedded decoder (checksum, safetensors or shapes wrong) or a
 * version-2 texture whose decoder was dropped by a tool that copies only the
 * attributes it knows fails with NBRDF_ERR_FORMAT naming the file. */
nbrdf_status nbrdf_model_for_texture(const nbrdf_model *bundle, const char *texture_path,
                                     nbrdf_model **out, nbrdf_error *err);

typedef struct nbrdf_decoder_info {
  int own;           /* 1: a decoder of its own; 0: the bundle's */
  size_t size;       /* own: bytes of its safetensors; else 0 */
  char checksum[17]; /* own: FNV-1a 64 of those bytes, 16 hex digits; else "" */
  const void *bytes; /* nbrdf_model_own_decoder, own: the bytes (the model's); else NULL */
} nbrdf_decoder_info;

/* Whether `model` has a decoder of its own (nbrdf_model_with_decoder, or
 * nbrdf_model_for_texture of a texture that carries one). */
void nbrdf_model_own_decoder(const nbrdf_model *model, nbrdf_decoder_info *info);
/* Whether the latent texture at `texture_path` carries its own decoder (its
 * header only is read; the checksum of the bytes is checked). `info->bytes`
 * is NULL. */
nbrdf_status nbrdf_texture_own_decoder(const char *texture_path, nbrdf_decoder_info *info,
                                       nbrdf_error *err);

/* ------------------------------------------------------------------ decoding */

/* f(ωi, ωo) WITHOUT the cosine factor for n direction pairs × `channels`
 * latents: latents [n × channels × D] (row-major: query k, channel c at
 * (k·channels + c)·D); wi, wo [n × 3] unit vectors in the shading frame
 * (z up), both with z > 0; f [n × channels], >= 0 and finite. A direction
 * that is not finite, not unit (|‖ω‖ − 1| > 1e-3) or not above the horizon
 * fails with NBRDF_ERR_ARGUMENT naming the query. */
nbrdf_status nbrdf_model_decode(const nbrdf_model *model, size_t n, int channels,
                                const float *latents, const float *wi, const float *wo, float *f,
                                nbrdf_error *err);

/* ------------------------------------------------------ the layered material
 * A dielectric coat (alpha1, eta) over a slab (albedo, sigma_t) over a conductor
 * (alpha2, r0): what the model represents and what a bake reads per texel. The
 * names keep their bake prefix (the bake was their first reader). */

/* The six parameters, in the order of the paper's layered BRDF. */
typedef enum nbrdf_bake_param_id {
  NBRDF_BAKE_ALPHA1 = 0, /* top coat GGX roughness (see nbrdf_roughness) */
  NBRDF_BAKE_ETA,        /* top coat IOR relative to outside, >= 1 */
  NBRDF_BAKE_ALPHA2,     /* bottom conductor GGX roughness */
  NBRDF_BAKE_R0,         /* bottom Schlick reflectance at normal incidence, [0, 1]; colour */
  NBRDF_BAKE_ALBEDO,     /* slab single-scattering albedo A, [0, 1]; colour */
  NBRDF_BAKE_SIGMA_T,    /* slab optical depth (unit thickness), >= 0 */
  NBRDF_BAKE_PARAM_COUNT
} nbrdf_bake_param_id;

/* How alpha1 and alpha2 values are read. */
typedef enum nbrdf_roughness {
  NBRDF_ROUGHNESS_ALPHA = 0,     /* the GGX alpha of the paper, used as given */
  NBRDF_ROUGHNESS_PERCEPTUAL = 1 /* artists' roughness r (Blender, Disney): alpha = r^2 */
} nbrdf_roughness;

/* Trained range of sigma_t (paper: {0, 1, 2, 5}); the range policy applies above it. */
#define NBRDF_BAKE_SIGMA_T_MAX 5.0f

/* ------------------------------------------------------------- base latents */

typedef enum nbrdf_base_kind {
  NBRDF_BASE_DIELECTRIC = 0, /* top coat: params (alpha1, eta) */
  NBRDF_BASE_CONDUCTOR = 1   /* bottom:   params (alpha2, r0) */
} nbrdf_base_kind;

typedef enum nbrdf_range_policy {
  NBRDF_RANGE_CLAMP = 0, /* clamp to the table's grid and flag the query */
  NBRDF_RANGE_REFUSE = 1 /* fail with NBRDF_ERR_ARGUMENT naming the parameter and query */
} nbrdf_range_policy;

/* Flags of a clamped query (bits of `clamped[k]`). */
#define NBRDF_CLAMPED_PARAM0 1u /* alpha1 / alpha2 */
#define NBRDF_CLAMPED_PARAM1 2u /* eta / r0 */

/* Latents of n base BRDFs by bilinear look-up in the model's table:
 * (p0, p1) = (alpha1, eta) for the dielectric, (alpha2, r0) for the
 * conductor; alpha is the GGX roughness used directly (no remapping), eta the
 * coat's IOR relative to outside, r0 the Schlick reflectance at normal
 * incidence. out [n × D]; clamped (may be NULL) receives the flags above.
 * NaN/Inf parameters always fail. */
nbrdf_status nbrdf_model_base_latents(const nbrdf_model *model, nbrdf_base_kind kind, size_t n,
                                      const float *p0, const float *p1, nbrdf_range_policy policy,
                                      float *out, unsigned char *clamped, nbrdf_error *err);

/* The table grid: node counts and axis values (owned by the model). */
void nbrdf_model_base_grid(const nbrdf_model *model, nbrdf_base_kind kind, int *n0,
                           const float **axis0, int *n1, const float **axis1);

/* ----------------------------------------------------------------- layering */

/* Layered latents of n (top, bottom) pairs [n × D] each, with the slab's
 * single-scattering albedo A ∈ [0, 1] and optical depth sigma_t >= 0 (unit
 * thickness; the paper trains σT ∈ {0, 1, 2, 5}); out [n × D] must not alias
 * the inputs. Three layers: pass a layered latent as `bottom`. */
nbrdf_status nbrdf_model_layer(const nbrdf_model *model, size_t n, const float *top,
                               const float *bottom, const float *albedo, const float *sigma_t,
                               float *out, nbrdf_error *err);

/* ------------------------------------------------------- importance sampling */

/* Proxy parameters of n latents: sigma > 0, w ∈ [0, 1] (paper Eq. 6). */
nbrdf_status nbrdf_model_proxy_params(const nbrdf_model *model, size_t n, const float *latents,
                                      float *sigma, float *w, nbrdf_error *err);

/* The proxy pdf p(ωo | ωi) = (1 − w) p_G + w cos θo / π per unit solid angle
 * where p_G places the half vector h = normalize(ωi + ωo) by an isotropic 2-D Gaussian of
 * standard deviation sigma over its projection (h.x, h.y) on the unit disk, truncated to the
 * disk, converted to solid angle by the half-vector Jacobian (docs/SAMPLING_AND_COST.md).
 * 0 when either direction is at or below the horizon. */
double nbrdf_proxy_pdf(double sigma, double w, const double wi[3], const double wo[3]);
/* Draws ωo from three uniforms u ∈ [0, 1)³ (u[0] picks the lobe). Returns 1
 * with *pdf = nbrdf_proxy_pdf(ωo) > 0, or 0 when the reflected direction
 * falls below the horizon (the sample is lost; *pdf = 0). */
int nbrdf_proxy_sample(double sigma, double w, const double wi[3], const double u[3], double wo[3],
                       double *pdf);

/* --------------------------------------------------------------- projection */

typedef enum nbrdf_loss {
  NBRDF_LOSS_L1_LOG1P = 0, /* |log(1 + f̂) − log(1 + f)|: default, far better on sharp lobes */
  NBRDF_LOSS_L1 = 1        /* |f̂ − f|: the paper's */
} nbrdf_loss;

typedef struct nbrdf_project_options {
  int steps;           /* Adam steps */
  int rows_per_brdf;   /* samples drawn per BRDF per step */
  float learning_rate; /* Adam, on the latents */
  nbrdf_loss loss;
  int init_from_out; /* non-zero: start from the latents in `out`; else from zero */
  uint64_t seed;
} nbrdf_project_options;

#define NBRDF_PROJECT_OPTIONS_DEFAULT                                                              \
  { 1000, 256, 1e-2f, NBRDF_LOSS_L1_LOG1P, 0, 0u }

/* Projects n_brdfs single-channel BRDFs into latents with the decoder frozen,
 * all optimised together in one batch. BRDF b's samples are rows
 * offsets[b] .. offsets[b+1]−1 of wi, wo [rows × 3] (unit, z > 0) and
 * f [rows] (>= 0, finite, without cosine); offsets[0] = 0 and every BRDF has at
 * least one sample. out [n_brdfs × D]; final_loss (may be NULL) receives each
 * BRDF's mean loss over all its samples after the last step. */
nbrdf_status nbrdf_model_project(const nbrdf_model *model, size_t n_brdfs, const size_t *offsets,
                                 const float *wi, const float *wo, const float *f,
                                 const nbrdf_project_options *options, float *out,
                                 double *final_loss, nbrdf_error *err);

/* ------------------------------------------------------------ interpolation */

/* out = Σ_k weights[k] · latents[k] / Σ_k weights[k] over `count` latents of
 * `dim` floats (the paper's latent interpolation; mip levels average 2×2
 * texels this way). Weights must be finite and >= 0 with a positive sum; they
 * need not sum to 1. */
nbrdf_status nbrdf_latent_interpolate(size_t count, int dim, const float *latents,
                                      const double *weights, float *out, nbrdf_error *err);

#ifdef __cplusplus
}
#endif
#endif
