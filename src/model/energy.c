/* The energy penalty of energy.h. */
#include "model/energy.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "core/number.h"
#include "core/rng.h"
#include "model/albedo_quad.h"
#include "model/encoding.h"

/* Latents per decoder pass (rows = this × n_theta × samples). */
#define LATENTS_PER_PASS 8

struct model_energy {
  const model_decoder *dec;
  model_energy_options o;
  int rows_per_latent; /* n_theta × samples */
  model_runner runner; /* TRAIN mode, LATENTS_PER_PASS latents */
  float *wi, *wo;      /* [rows_per_latent × 3]: this step's directions */
  double *weight;      /* [rows_per_latent]: quadrature weights */
  float *dy, *dx;      /* [batch], [batch × inputs] */
  double *f;           /* [samples] */
};

nbrdf_status model_energy_parse_angles(const char *text, const char *option,
                                       model_energy_options *o, nbrdf_error *err) {
  char buf[256];
  if (strlen(text) >= sizeof buf)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "%s: list too long", option);
  strcpy(buf, text);
  int n = 0;
  for (char *save = NULL, *tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
    char *end = NULL;
    double v = strtod(tok, &end);
    if (end == tok || *end != '\0' || !(v >= 0.0 && v < 90.0))
      return core_fail(err, NBRDF_ERR_ARGUMENT, "%s: '%s' is not an angle in degrees in [0, 90)",
                       option, tok);
    if (n == MODEL_ENERGY_MAX_THETA)
      return core_fail(err, NBRDF_ERR_ARGUMENT, "%s: at most %d angles", option,
                       MODEL_ENERGY_MAX_THETA);
    o->theta_deg[n++] = v;
  }
  if (n == 0) return core_fail(err, NBRDF_ERR_ARGUMENT, "%s: no angle given", option);
  o->n_theta = n;
  return NBRDF_OK;
}

void model_energy_destroy(model_energy *e) {
  if (!e) return;
  model_runner_destroy(&e->runner);
  free(e->wi), free(e->wo), free(e->weight), free(e->dy), free(e->dx), free(e->f);
  free(e);
}

nbrdf_status model_energy_create(const model_decoder *dec, const model_energy_options *o,
                                 model_energy **out, nbrdf_error *err) {
  *out = NULL;
  if (!(o->lambda >= 0.0f) || !isfinite(o->lambda))
    return core_fail(err, NBRDF_ERR_ARGUMENT, "energy penalty: lambda = %g, expected >= 0",
                     (double)o->lambda);
  model_energy_options own = *o;
  if (o->polar_rings > 0) {
    if (o->polar_rings < 3 || o->polar_phi < 4 || o->polar_rings * o->polar_phi + 1 > 4096)
      return core_fail(err, NBRDF_ERR_ARGUMENT,
                       "energy penalty: a polar rule of %d rings of %d (>= 3 of >= 4, at most "
                       "4,095 nodes)",
                       o->polar_rings, o->polar_phi);
    own.samples = o->polar_rings * o->polar_phi + 1;
  }
  o = &own;
  if (o->n_theta < 1 || o->n_theta > MODEL_ENERGY_MAX_THETA || o->samples < 16 || o->samples > 4096)
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "energy penalty: %d angles (1..%d) and %d samples (16..4096)", o->n_theta,
                     MODEL_ENERGY_MAX_THETA, o->samples);
  for (int t = 0; t < o->n_theta; t++)
    if (!(o->theta_deg[t] >= 0.0 && o->theta_deg[t] < 90.0))
      return core_fail(err, NBRDF_ERR_ARGUMENT, "energy penalty: angle %g is outside [0, 90)",
                       o->theta_deg[t]);
  model_energy *e = calloc(1, sizeof *e);
  if (!e) return core_fail(err, NBRDF_ERR_MEMORY, "energy penalty: out of memory");
  e->dec = dec, e->o = *o;
  e->rows_per_latent = o->n_theta * o->samples;
  size_t R = (size_t)e->rows_per_latent, batch = R * LATENTS_PER_PASS;
  size_t in = (size_t)model_decoder_inputs(dec);
  nbrdf_status st = model_runner_create(dec->nn, (int)batch, NBRDF_NN_TRAIN, &e->runner, err);
  if (!st) {
    e->wi = malloc(3 * R * sizeof *e->wi);
    e->wo = malloc(3 * R * sizeof *e->wo);
    e->weight = malloc(R * sizeof *e->weight);
    e->dy = malloc(batch * sizeof *e->dy);
    e->dx = malloc(batch * in * sizeof *e->dx);
    e->f = malloc((size_t)o->samples * sizeof *e->f);
    if (!e->wi || !e->wo || !e->weight || !e->dy || !e->dx || !e->f)
      st = core_fail(err, NBRDF_ERR_MEMORY, "energy penalty: out of memory");
  }
  if (st) {
    model_energy_destroy(e);
    return st;
  }
  *out = e;
  return NBRDF_OK;
}

/* This step's directions and weights, the same for every latent. */
static nbrdf_status make_directions(model_energy *e, int64_t step, nbrdf_error *err) {
  int S = e->o.samples;
  for (int t = 0; t < e->o.n_theta; t++) {
    model_albedo_quad q;
    double th = e->o.theta_deg[t] * (M_PI / 180.0);
    nbrdf_status st =
        e->o.polar_rings > 0
            ? model_albedo_quad_init_polar(&q, th, e->o.polar_rings, e->o.polar_phi, err)
            : model_albedo_quad_init(&q, th, S, core_hash64(e->o.seed, (uint64_t)step), 0.0, err);
    if (st) return st;
    for (int k = 0; k < S; k++) {
      size_t r = (size_t)t * S + (size_t)k;
      for (int a = 0; a < 3; a++)
        e->wi[3 * r + a] = (float)q.wi[a], e->wo[3 * r + a] = (float)q.wo[3 * k + a];
      e->weight[r] = q.weight[k];
    }
    model_albedo_quad_free(&q);
  }
  return NBRDF_OK;
}

/* ∂f̂/∂o of the decoder's output transform (decoder.h); 0 where it clamps. */
static double df_do(model_output output, float o) {
  if (output == MODEL_OUTPUT_LOG1P) return (o > 0.0f && o < 80.0f) ? exp((double)o) : 0.0;
  return o > 0.0f ? 1.0 : 0.0;
}

nbrdf_status model_energy_add(model_energy *e, size_t n, const float *latents, const float *ceiling,
                              const float *floor, int64_t step, float *grad_latent,
                              float *grad_weights, double *penalty, double *albedo,
                              nbrdf_error *err) {
  if (penalty) *penalty = 0.0;
  if (n == 0) return NBRDF_OK;
  nbrdf_status st = make_directions(e, step, err);
  if (st) return st;
  const model_decoder *dec = e->dec;
  const int T = e->o.n_theta, S = e->o.samples;
  const size_t D = (size_t)dec->cfg.latent_dim, in = (size_t)model_decoder_inputs(dec);
  const size_t R = (size_t)e->rows_per_latent;
  const double scale = (double)e->o.lambda / ((double)n * T);
  const int backprop = grad_latent || grad_weights;
  double total = 0.0;
  for (size_t l0 = 0; l0 < n && !st; l0 += LATENTS_PER_PASS) {
    size_t m = n - l0 < LATENTS_PER_PASS ? n - l0 : LATENTS_PER_PASS;
    for (size_t l = 0; l < m; l++) {
      float *x = e->runner.x + l * R * in;
      for (size_t r = 0; r < R; r++)
        memcpy(x + r * in, latents + (l0 + l) * D, D * sizeof *x);
      model_encode(&dec->cfg.encoding, R, e->wi, e->wo, x + D, in);
    }
    st = nn_forward(dec->nn, e->runner.ws, e->runner.x, (int)(m * R), e->runner.y, err);
    if (st) break;
    int active = 0;
    for (size_t l = 0; l < m; l++)
      for (int t = 0; t < T; t++) {
        size_t r0 = l * R + (size_t)t * S;
        double rho = 0.0;
        for (int k = 0; k < S; k++)
          rho += e->weight[(size_t)t * S + k] *
                 (double)model_output_to_f(dec->cfg.output, e->runner.y[r0 + k]);
        if (albedo) albedo[(l0 + l) * T + t] = rho;
        double excess = rho - (double)ceiling[(l0 + l) * T + t];
        double deficit = floor ? (double)floor[(l0 + l) * T + t] - rho : 0.0;
        /* sign of ∂P/∂ρ̂: +1 above the ceiling, −1 below the floor, 0 between */
        double sign = excess > 0.0 ? 1.0 : deficit > 0.0 ? -1.0 : 0.0;
        active |= sign != 0.0;
        total += scale * (excess > 0.0 ? excess : deficit > 0.0 ? deficit : 0.0);
        for (int k = 0; k < S; k++)
          e->dy[r0 + k] = sign != 0.0 ? (float)(sign * scale * e->weight[(size_t)t * S + k] *
                                                df_do(dec->cfg.output, e->runner.y[r0 + k]))
                                      : 0.0f;
      }
    /* A pass with no latent outside its bounds has a zero gradient. */
    if (!backprop || !active) continue;
    st = nn_backward(dec->nn, e->runner.ws, e->dy, grad_latent ? e->dx : NULL, grad_weights, err);
    if (st || !grad_latent) continue;
    for (size_t l = 0; l < m; l++) {
      float *g = grad_latent + (l0 + l) * D;
      for (size_t r = 0; r < R; r++) {
        const float *d = e->dx + (l * R + r) * in;
        for (size_t j = 0; j < D; j++)
          g[j] += d[j];
      }
    }
  }
  if (penalty) *penalty = total;
  return st;
}
