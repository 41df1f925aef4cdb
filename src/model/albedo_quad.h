/* Directional albedo ρ(θi) = ∫ f(ωi, ωo) cos θo dωo by a quadrature that
 * resolves the sharpest lobes a model can produce.
 *
 * A lobe image (src/lobe) integrates ρ by the midpoint rule on 64² pixels: an
 * α = 0.01 lobe at θi = 85° is narrower than a pixel there, so the image
 * under- or over-counts it by tens of percent. Here ρ is an importance-sampled
 * Monte Carlo estimate with a fixed set of directions per θi and seed, drawn
 * by several techniques and combined with the balance heuristic (Veach 1997,
 * §9.2.2, the one-sample "mixture" form: every sample is weighted by the
 * mixture density p(ωo) = Σ_j c_j p_j(ωo), c_j = n_j / N):
 *   - cosine-weighted hemisphere (diffuse parts, the far tails);
 *   - GGX visible-normal reflection about ωi at a ladder of roughnesses
 *     α ∈ {0.003, 0.012, 0.05, 0.2, 0.6}, so a lobe of any width around the
 *     mirror direction finds a technique within a factor 4 of its own width,
 *     whatever the BRDF is (its true α is unknown for a latent);
 *   - optionally the latent's own proxy Gaussian (σ of the sampling network).
 * The estimate is linear in the sampled values, ρ̂ = Σ_k weight_k f(ωi, ωo_k),
 * so it is differentiable through f (training's energy penalty, energy.h) and
 * the same directions can serve any BRDF (decoder or ground truth).
 *
 * Samples that reflect below the horizon are kept with weight 0 and ωo = the
 * normal, so a caller can evaluate every row without special cases; the
 * estimator stays unbiased because p is the density over the whole sphere. */
#ifndef NBRDF_MODEL_ALBEDO_QUAD_H
#define NBRDF_MODEL_ALBEDO_QUAD_H

#include <stddef.h>
#include <stdint.h>

#include "model/decoder.h"
#include "nbrdf/status.h"

#define MODEL_ALBEDO_QUAD_MAX_TECH 8

typedef struct model_albedo_quad {
  int n;                                    /* directions */
  int n_tech;                               /* techniques used */
  int tech_end[MODEL_ALBEDO_QUAD_MAX_TECH]; /* samples of technique j: [end_{j-1}, end_j) */
  double theta_i;                           /* radians */
  double wi[3];                             /* (sin θi, 0, cos θi) */
  double *wo;                               /* [n × 3] */
  double *weight;                           /* [n]: cos θo / (N p(ωo)); 0 for a lost sample */
} model_albedo_quad;

/* Builds the directions for θi (radians, [0, π/2)) with n >= 16 samples from
 * the random stream `seed`; proxy_sigma > 0 adds the proxy's Gaussian lobe as
 * a technique (0: none). Deterministic for (θi, n, seed, proxy_sigma). */
nbrdf_status model_albedo_quad_init(model_albedo_quad *q, double theta_i, int n, uint64_t seed,
                                    double proxy_sigma, nbrdf_error *err);
/* The same with each technique's (u1, u2) on a randomly shifted Fibonacci
 * lattice instead of jittered strata: no longer i.i.d. (quad_sum's se does not
 * apply), but far less spread for the smooth integrands of a decoded lobe at
 * equal n (bench/bench_audit_margin.c measures it against brute force). */
nbrdf_status model_albedo_quad_init_lattice(model_albedo_quad *q, double theta_i, int n,
                                            uint64_t seed, double proxy_sigma, nbrdf_error *err);
/* A deterministic product rule instead of samples (no seed, one technique):
 * n_rings × n_phi nodes over the disk of projected half vectors plus one at the
 * mirror direction, rings log-spaced in radius near the mirror (a lobe of any
 * width, down to α ≈ 0.003, falls on several of them) and evenly spaced in θh
 * beyond. The audit uses it where the lattice needed 5× the queries for the
 * same spread against brute force (bench/bench_audit_quad.c, docs/BAKE.md). */
nbrdf_status model_albedo_quad_init_polar(model_albedo_quad *q, double theta_i, int n_rings,
                                          int n_phi, nbrdf_error *err);
void model_albedo_quad_free(model_albedo_quad *q); /* zeroes it */

/* ρ̂ = Σ weight_k f[k] from the values f[k] = f(ωi, ωo_k) (no cosine), and its
 * standard error from the spread within each technique (se may be NULL). */
double model_albedo_quad_sum(const model_albedo_quad *q, const double *f, double *se);

/* Decoded directional albedo of n_latents single-channel latents [n_latents × D]
 * at n_theta angles theta_deg (degrees): rho[l · n_theta + t] (and se, may be
 * NULL). sigma [n_latents] (may be NULL) adds each latent's proxy lobe. One
 * decoder pass per angle over all latents (`runner` INFER or TRAIN of `dec`). */
nbrdf_status model_albedo_decoded(const model_decoder *dec, model_runner *runner, size_t n_latents,
                                  const float *latents, const float *sigma, int n_theta,
                                  const double *theta_deg, int samples, uint64_t seed, double *rho,
                                  double *se, nbrdf_error *err);

/* model_albedo_decoded on the lattice directions of model_albedo_quad_init_lattice. */
nbrdf_status model_albedo_decoded_lattice(const model_decoder *dec, model_runner *runner,
                                          size_t n_latents, const float *latents,
                                          const float *sigma, int n_theta, const double *theta_deg,
                                          int samples, uint64_t seed, double *rho,
                                          nbrdf_error *err);

/* model_albedo_decoded with two techniques only, cosine (a quarter of the
 * samples) and each latent's proxy Gaussian (sigma required, every entry > 0),
 * on jittered strata: the sampling network's pdf proxy as a screen
 * (bench/bench_audit_screen.c measures it against the polar rule). */
nbrdf_status model_albedo_decoded_proxy(const model_decoder *dec, model_runner *runner,
                                        size_t n_latents, const float *latents, const float *sigma,
                                        int n_theta, const double *theta_deg, int samples,
                                        uint64_t seed, double *rho, double *se, nbrdf_error *err);

/* model_albedo_decoded on the nodes of model_albedo_quad_init_polar (the same
 * nodes for every latent: n_rings × n_phi + 1 decoder queries per angle). */
nbrdf_status model_albedo_decoded_polar(const model_decoder *dec, model_runner *runner,
                                        size_t n_latents, const float *latents, int n_theta,
                                        const double *theta_deg, int n_rings, int n_phi,
                                        double *rho, nbrdf_error *err);

#endif
