/* Importance-sampled directional albedo with a mixture of techniques
 * (albedo_quad.h). */
#include "model/albedo_quad.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "brdf/ggx.h"
#include "core/error.h"
#include "core/rng.h"
#include "core/warp.h"
#include "model/proxy.h"

/* The roughness ladder of the GGX techniques: neighbours a factor 4 apart, from
 * below the sharpest trained coat (α = 0.01) to a near-diffuse lobe. */
static const double ladder[] = {0.003, 0.012, 0.05, 0.2, 0.6};
#define N_LADDER ((int)(sizeof ladder / sizeof ladder[0]))

/* A sample below this cosine is counted as lost: its weight would be
 * cos θo / p with p → 0 only through round-off. */
#define MIN_COS 1e-7

/* Density of GGX visible-normal reflection about ωi, per solid angle of ωo:
 * D_ωi(h) / (4 |ωi·h|) = G1(ωi) D(h) / (4 cos θi) (Heitz 2018, eq. 17). */
static double ggx_reflect_pdf(double alpha, vec3 wi, vec3 wo) {
  vec3 h = v3_add(wi, wo);
  double len = v3_length(h);
  if (!(len > 0.0)) return 0.0;
  h = v3_scale(h, 1.0 / len);
  double wh = v3_dot(wi, h);
  if (wh <= 0.0 || h.z <= 0.0) return 0.0;
  return brdf_ggx_vndf_pdf(alpha, wi, h) / (4.0 * wh);
}

typedef struct technique {
  int kind; /* 0 cosine, 1 GGX, 2 proxy */
  double param;
} technique;

static double tech_pdf(const technique *t, vec3 wi, vec3 wo) {
  switch (t->kind) {
  case 0:
    return wo.z > 0.0 ? wo.z / M_PI : 0.0;
  case 1:
    return ggx_reflect_pdf(t->param, wi, wo);
  default:
    return model_proxy_gaussian_pdf(t->param, wi, wo);
  }
}

static int tech_sample(const technique *t, vec3 wi, double u1, double u2, vec3 *wo) {
  if (t->kind == 0) {
    *wo = core_warp_cosine_hemisphere(u1, u2);
    return 1;
  }
  if (t->kind == 1) {
    vec3 h;
    if (!brdf_ggx_sample_vndf(t->param, wi, u1, u2, &h)) return 0;
    *wo = v3_sub(v3_scale(h, 2.0 * v3_dot(wi, h)), wi);
    return 1;
  }
  double pdf;
  return model_proxy_sample(t->param, 0.0, wi, 0.5, u1, u2, wo, &pdf);
}

/* The product rule of model_albedo_quad_init_polar: inner rings log-polar in r
 * (the projected half vector's radius) from POLAR_RMIN to POLAR_RSPLIT, so a
 * lobe of any width around the mirror direction spans the same few rings;
 * outer rings by the midpoint rule in θh (the broad and diffuse parts); the
 * midpoint rule in φ, each ring turned half a step from the previous; the
 * centre disk r < POLAR_RMIN one node at the mirror direction. */
#define POLAR_RMIN 1e-3
#define POLAR_RSPLIT 0.25

nbrdf_status model_albedo_quad_init_polar(model_albedo_quad *q, double theta_i, int n_rings,
                                          int n_phi, nbrdf_error *err) {
  memset(q, 0, sizeof *q);
  if (!(theta_i >= 0.0 && theta_i < 0.5 * M_PI))
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "albedo quadrature: theta_i = %g rad, expected [0, pi/2)", theta_i);
  if (n_rings < 3 || n_phi < 4)
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "albedo quadrature: %d rings of %d, expected >= 3 of >= 4", n_rings, n_phi);
  const int n = n_rings * n_phi + 1;
  q->wo = malloc((size_t)n * 3 * sizeof *q->wo);
  q->weight = malloc((size_t)n * sizeof *q->weight);
  if (!q->wo || !q->weight) {
    model_albedo_quad_free(q);
    return core_fail(err, NBRDF_ERR_MEMORY, "albedo quadrature: out of memory (%d nodes)", n);
  }
  q->n = n, q->n_tech = 1, q->tech_end[0] = n, q->theta_i = theta_i;
  vec3 wi = v3(sin(theta_i), 0.0, cos(theta_i));
  q->wi[0] = wi.x, q->wi[1] = wi.y, q->wi[2] = wi.z;
  const int n_in = (2 * n_rings + 2) / 3, n_out = n_rings - n_in;
  const double s0 = log(POLAR_RMIN), ds = (log(POLAR_RSPLIT) - s0) / n_in;
  const double t0 = asin(POLAR_RSPLIT), dt = (0.5 * M_PI - t0) / n_out;
  const double dphi = 2.0 * M_PI / n_phi;
  for (int k = 0; k < n; k++) {
    double area;
    vec3 h = v3(0.0, 0.0, 1.0);
    if (k == n - 1) {
      area = M_PI * POLAR_RMIN * POLAR_RMIN;
    } else {
      int j = k / n_phi, a = k % n_phi;
      double phi = (a + 0.5 * (j & 1) + 0.25) * dphi, r;
      if (j < n_in) { /* dA = r dr dφ = r² ds dφ */
        r = exp(s0 + (j + 0.5) * ds);
        area = r * r * ds * dphi;
        h = v3(r * cos(phi), r * sin(phi), sqrt(fmax(0.0, 1.0 - r * r)));
      } else { /* r = sin θh: dA = sin θh cos θh dθh dφ */
        double th = t0 + (j - n_in + 0.5) * dt;
        r = sin(th);
        area = r * cos(th) * dt * dphi;
        h = v3(r * cos(phi), r * sin(phi), cos(th));
      }
    }
    /* dωo = 4 |ωo·h| dωh and dωh = dA / cos θh (the Jacobians of proxy.h) */
    double wh = v3_dot(wi, h), w = 0.0;
    vec3 wo = v3_sub(v3_scale(h, 2.0 * wh), wi);
    if (wh > 0.0 && h.z > 0.0 && wo.z > MIN_COS) w = wo.z * 4.0 * wh / h.z * area;
    if (!(w > 0.0) || !isfinite(w)) w = 0.0, wo = v3(0.0, 0.0, 1.0);
    q->wo[3 * k] = wo.x, q->wo[3 * k + 1] = wo.y, q->wo[3 * k + 2] = wo.z;
    q->weight[k] = w;
  }
  return NBRDF_OK;
}

/* kind: QUAD_JITTER or QUAD_LATTICE with the ladder, QUAD_PROXY the cosine and
 * proxy techniques only (jittered strata). */
enum { QUAD_JITTER, QUAD_LATTICE, QUAD_PROXY };

static nbrdf_status quad_init(model_albedo_quad *q, double theta_i, int n, uint64_t seed,
                              double proxy_sigma, int kind, nbrdf_error *err) {
  const int lattice = kind == QUAD_LATTICE, ladder_n = kind == QUAD_PROXY ? 0 : N_LADDER;
  memset(q, 0, sizeof *q);
  if (!(theta_i >= 0.0 && theta_i < 0.5 * M_PI))
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "albedo quadrature: theta_i = %g rad, expected [0, pi/2)", theta_i);
  if (n < 16)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "albedo quadrature: %d samples, expected >= 16", n);
  if (!(proxy_sigma >= 0.0) || !isfinite(proxy_sigma))
    return core_fail(err, NBRDF_ERR_ARGUMENT, "albedo quadrature: proxy sigma = %g", proxy_sigma);
  technique tech[MODEL_ALBEDO_QUAD_MAX_TECH];
  double share[MODEL_ALBEDO_QUAD_MAX_TECH];
  int nt = 0;
  /* Shares: a fifth cosine (it alone covers the whole hemisphere), the rest
   * spread over the lobe techniques. */
  int lobes = ladder_n + (proxy_sigma > 0.0);
  if (kind == QUAD_PROXY && !(proxy_sigma > 0.0))
    return core_fail(err, NBRDF_ERR_ARGUMENT, "albedo quadrature: the proxy rule needs sigma > 0");
  tech[nt] = (technique){0, 0.0};
  /* The proxy rule: a quarter cosine (the Lambert part and the far tails). */
  share[nt++] = kind == QUAD_PROXY ? 0.25 : 0.2;
  for (int j = 0; j < ladder_n; j++) {
    tech[nt] = (technique){1, ladder[j]};
    share[nt++] = 0.8 / lobes;
  }
  if (proxy_sigma > 0.0) {
    tech[nt] =
        (technique){2, proxy_sigma < MODEL_PROXY_SIGMA_MIN ? MODEL_PROXY_SIGMA_MIN : proxy_sigma};
    share[nt++] = (kind == QUAD_PROXY ? 0.75 : 0.8) / lobes;
  }
  q->wo = malloc((size_t)n * 3 * sizeof *q->wo);
  q->weight = malloc((size_t)n * sizeof *q->weight);
  if (!q->wo || !q->weight) {
    model_albedo_quad_free(q);
    return core_fail(err, NBRDF_ERR_MEMORY, "albedo quadrature: out of memory (%d samples)", n);
  }
  q->n = n;
  q->n_tech = nt;
  q->theta_i = theta_i;
  vec3 wi = v3(sin(theta_i), 0.0, cos(theta_i));
  q->wi[0] = wi.x, q->wi[1] = wi.y, q->wi[2] = wi.z;
  /* Counts: floor of the shares, the remainder to the cosine technique. */
  int counts[MODEL_ALBEDO_QUAD_MAX_TECH], used = 0;
  for (int j = 1; j < nt; j++)
    used += counts[j] = (int)floor(share[j] * n);
  counts[0] = n - used;
  double c[MODEL_ALBEDO_QUAD_MAX_TECH];
  for (int j = 0, end = 0; j < nt; j++) {
    end += counts[j];
    q->tech_end[j] = end;
    c[j] = (double)counts[j] / n;
  }
  int k = 0;
  for (int j = 0; j < nt; j++) {
    core_rng rng;
    core_rng_init(&rng, core_hash64(seed, (uint64_t)llround(theta_i * 1e9)), (uint64_t)j);
    /* The lattice's random shift (Cranley-Patterson rotation). */
    double r1 = lattice ? core_rng_uniform(&rng) : 0.0, r2 = lattice ? core_rng_uniform(&rng) : 0.0;
    for (int s = 0; s < counts[j]; s++, k++) {
      double u1, u2;
      if (lattice) {
        /* A shifted Fibonacci lattice: stratified in u1, the golden ratio's
         * low-discrepancy sequence in u2, so every sub-rectangle of the
         * technique's unit square gets its share of the samples. */
        u1 = fmod((s + 0.5) / counts[j] + r1, 1.0);
        u2 = fmod(s * 0.6180339887498949 + r2, 1.0);
      } else {
        /* Stratified in u1 (one stratum per sample), jittered in u2. */
        u1 = (s + core_rng_uniform(&rng)) / counts[j];
        u2 = core_rng_uniform(&rng);
      }
      vec3 wo;
      double w = 0.0;
      if (tech_sample(&tech[j], wi, u1, u2, &wo) && wo.z > MIN_COS) {
        wo = v3_normalize(wo);
        double p = 0.0;
        for (int i = 0; i < nt; i++)
          p += c[i] * tech_pdf(&tech[i], wi, wo);
        if (p > 0.0) w = wo.z / (n * p);
      }
      if (!(w > 0.0) || !isfinite(w)) {
        w = 0.0;
        wo = v3(0.0, 0.0, 1.0);
      }
      q->wo[3 * k] = wo.x, q->wo[3 * k + 1] = wo.y, q->wo[3 * k + 2] = wo.z;
      q->weight[k] = w;
    }
  }
  return NBRDF_OK;
}

nbrdf_status model_albedo_quad_init(model_albedo_quad *q, double theta_i, int n, uint64_t seed,
                                    double proxy_sigma, nbrdf_error *err) {
  return quad_init(q, theta_i, n, seed, proxy_sigma, QUAD_JITTER, err);
}

nbrdf_status model_albedo_quad_init_lattice(model_albedo_quad *q, double theta_i, int n,
                                            uint64_t seed, double proxy_sigma, nbrdf_error *err) {
  return quad_init(q, theta_i, n, seed, proxy_sigma, QUAD_LATTICE, err);
}

void model_albedo_quad_free(model_albedo_quad *q) {
  free(q->wo);
  free(q->weight);
  memset(q, 0, sizeof *q);
}

double model_albedo_quad_sum(const model_albedo_quad *q, const double *f, double *se) {
  double rho = 0.0, var = 0.0;
  for (int j = 0, begin = 0; j < q->n_tech; begin = q->tech_end[j++]) {
    int nj = q->tech_end[j] - begin;
    double s = 0.0, s2 = 0.0;
    for (int k = begin; k < q->tech_end[j]; k++) {
      double g = q->weight[k] * f[k];
      s += g;
      s2 += g * g;
    }
    rho += s;
    /* The n_j samples of a technique are i.i.d.: Var(Σ g) = n_j Var(g). */
    if (nj > 1) {
      double mean = s / nj;
      double v = (s2 - nj * mean * mean) / (nj - 1);
      var += nj * (v > 0.0 ? v : 0.0);
    }
  }
  if (se) *se = sqrt(var);
  return rho;
}

/* Rows per decoder pass: bounded so that a bake's audit never allocates much. */
#define MAX_ROWS 65536

static nbrdf_status decoded(const model_decoder *dec, model_runner *runner, size_t n_latents,
                            const float *latents, const float *sigma, int n_theta,
                            const double *theta_deg, int samples, uint64_t seed, int kind,
                            int polar_phi, double *rho, double *se, nbrdf_error *err) {
  if (n_latents == 0 || n_theta <= 0) return NBRDF_OK;
  /* polar_phi > 0: the polar rule, samples = rings × polar_phi + 1, one set for all latents */
  if (polar_phi > 0) sigma = NULL;
  if (samples < 16 || samples > MAX_ROWS)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "decoded albedo: %d samples, expected 16..%d",
                     samples, MAX_ROWS);
  const int D = dec->cfg.latent_dim;
  size_t per = (size_t)(MAX_ROWS / samples);
  if (per > n_latents) per = n_latents;
  size_t rows = per * (size_t)samples;
  float *lat = malloc(rows * (size_t)D * sizeof *lat);
  float *wi = malloc(rows * 3 * sizeof *wi);
  float *wo = malloc(rows * 3 * sizeof *wo);
  float *f = malloc(rows * sizeof *f);
  double *fd = malloc((size_t)samples * sizeof *fd);
  model_albedo_quad *quads = calloc(per, sizeof *quads);
  nbrdf_status st = NBRDF_OK;
  if (!lat || !wi || !wo || !f || !fd || !quads)
    st = core_fail(err, NBRDF_ERR_MEMORY, "decoded albedo: out of memory (%zu rows)", rows);
  for (int t = 0; st == NBRDF_OK && t < n_theta; t++) {
    double th = theta_deg[t] * M_PI / 180.0;
    for (size_t l0 = 0; st == NBRDF_OK && l0 < n_latents; l0 += per) {
      size_t m = n_latents - l0 < per ? n_latents - l0 : per;
      /* Without proxies every latent shares one set of directions. */
      for (size_t l = 0; st == NBRDF_OK && l < m; l++)
        if (polar_phi > 0 && l == 0)
          st = model_albedo_quad_init_polar(&quads[l], th, (samples - 1) / polar_phi, polar_phi,
                                            err);
        else if (polar_phi <= 0 && (sigma || l == 0))
          st = quad_init(&quads[l], th, samples, seed, sigma ? sigma[l0 + l] : 0.0, kind, err);
      for (size_t l = 0; st == NBRDF_OK && l < m; l++) {
        const model_albedo_quad *q = &quads[sigma ? l : 0];
        for (int k = 0; k < samples; k++) {
          size_t r = l * (size_t)samples + (size_t)k;
          memcpy(lat + r * D, latents + (l0 + l) * D, (size_t)D * sizeof *lat);
          for (int a = 0; a < 3; a++) {
            wi[3 * r + a] = (float)q->wi[a];
            wo[3 * r + a] = (float)q->wo[3 * k + a];
          }
        }
      }
      if (st == NBRDF_OK)
        st = model_decoder_eval(dec, runner, m * (size_t)samples, 1, lat, wi, wo, f, err);
      for (size_t l = 0; st == NBRDF_OK && l < m; l++) {
        const model_albedo_quad *q = &quads[sigma ? l : 0];
        for (int k = 0; k < samples; k++)
          fd[k] = f[l * (size_t)samples + (size_t)k];
        size_t o = (l0 + l) * (size_t)n_theta + (size_t)t;
        rho[o] = model_albedo_quad_sum(q, fd, se ? &se[o] : NULL);
      }
      for (size_t l = 0; l < per; l++)
        model_albedo_quad_free(&quads[l]);
    }
  }
  if (quads)
    for (size_t l = 0; l < per; l++)
      model_albedo_quad_free(&quads[l]);
  free(quads);
  free(fd);
  free(f);
  free(wo);
  free(wi);
  free(lat);
  return st;
}

nbrdf_status model_albedo_decoded(const model_decoder *dec, model_runner *runner, size_t n_latents,
                                  const float *latents, const float *sigma, int n_theta,
                                  const double *theta_deg, int samples, uint64_t seed, double *rho,
                                  double *se, nbrdf_error *err) {
  return decoded(dec, runner, n_latents, latents, sigma, n_theta, theta_deg, samples, seed,
                 QUAD_JITTER, 0, rho, se, err);
}

nbrdf_status model_albedo_decoded_lattice(const model_decoder *dec, model_runner *runner,
                                          size_t n_latents, const float *latents,
                                          const float *sigma, int n_theta, const double *theta_deg,
                                          int samples, uint64_t seed, double *rho,
                                          nbrdf_error *err) {
  return decoded(dec, runner, n_latents, latents, sigma, n_theta, theta_deg, samples, seed,
                 QUAD_LATTICE, 0, rho, NULL, err);
}

nbrdf_status model_albedo_decoded_proxy(const model_decoder *dec, model_runner *runner,
                                        size_t n_latents, const float *latents, const float *sigma,
                                        int n_theta, const double *theta_deg, int samples,
                                        uint64_t seed, double *rho, double *se, nbrdf_error *err) {
  if (!sigma)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "decoded albedo: the proxy rule needs sigma");
  return decoded(dec, runner, n_latents, latents, sigma, n_theta, theta_deg, samples, seed,
                 QUAD_PROXY, 0, rho, se, err);
}

nbrdf_status model_albedo_decoded_polar(const model_decoder *dec, model_runner *runner,
                                        size_t n_latents, const float *latents, int n_theta,
                                        const double *theta_deg, int n_rings, int n_phi,
                                        double *rho, nbrdf_error *err) {
  if (n_rings < 3 || n_phi < 4)
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "decoded albedo: %d rings of %d, expected >= 3 of >= 4", n_rings, n_phi);
  return decoded(dec, runner, n_latents, latents, NULL, n_theta, theta_deg, n_rings * n_phi + 1, 0,
                 QUAD_JITTER, n_phi, rho, NULL, err);
}
