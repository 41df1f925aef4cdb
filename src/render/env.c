/* Environment radiance and its tabulated importance sampling (env.h). */
#include "render/env.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "texture/oiio_shim.h"

/* Sampling table resolution (cells of 1.4° x 1.4°: the sky's sun, about 2°
 * wide, spans a few cells). Image environments use their own resolution up
 * to this, each cell the brightest pixel it covers so that a small bright
 * source is never missed. */
#define TABLE_W 256
#define TABLE_H 128

struct render_env {
  nbrdf_env_kind kind;
  double value[3], scale;
  int iw, ih; /* image */
  float *image;
  vec3 sun;
  double rot_c, rot_s; /* env_rotation_deg about +y: world = R · environment */
  double *cond_cdf;    /* TABLE_H rows of TABLE_W + 1 */
  double *marg_cdf;    /* TABLE_H + 1 */
  double *cell_prob;   /* TABLE_H x TABLE_W, sums to 1 */
};

static double luminance(const double c[3]) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; }

static vec3 dir_of(double s, double t) {
  double theta = t * M_PI, phi = (s - 0.5) * 2.0 * M_PI;
  return v3(sin(theta) * sin(phi), cos(theta), -sin(theta) * cos(phi));
}

static void st_of(vec3 d, double *s, double *t) {
  *t = acos(fmin(1.0, fmax(-1.0, d.y))) / M_PI;
  *s = atan2(d.x, -d.z) / (2.0 * M_PI) + 0.5;
  if (*s >= 1.0) *s -= 1.0;
  if (*s < 0.0) *s = 0.0;
}

static void sky(const render_env *env, vec3 d, double rgb[3]) {
  static const double zenith[3] = {0.25, 0.45, 0.95}, horizon[3] = {1.0, 1.0, 1.0};
  static const double ground[3] = {0.30, 0.27, 0.24}, sun[3] = {40.0, 36.0, 30.0};
  if (d.y < 0.0) {
    memcpy(rgb, ground, sizeof ground);
  } else {
    double k = pow(1.0 - d.y, 3.0);
    for (int c = 0; c < 3; c++)
      rgb[c] = zenith[c] + (horizon[c] - zenith[c]) * k;
  }
  /* A soft sun: exp((cos γ − 1) / 5e-4) falls to 1/e at γ ≈ 1.8°. */
  double g = exp((v3_dot(d, env->sun) - 1.0) / 5e-4);
  for (int c = 0; c < 3; c++)
    rgb[c] += sun[c] * g;
}

static void image_radiance(const render_env *env, double s, double t, double rgb[3]) {
  /* Bilinear, repeating in s, clamped in t. */
  double x = s * env->iw - 0.5, y = t * env->ih - 0.5;
  double xf = floor(x), yf = floor(y), fx = x - xf, fy = y - yf;
  int x0 = ((int)xf % env->iw + env->iw) % env->iw, x1 = (x0 + 1) % env->iw;
  int y0 = (int)yf < 0 ? 0 : (int)yf, y1 = y0 + 1 >= env->ih ? env->ih - 1 : y0 + 1;
  if (y0 >= env->ih) y0 = env->ih - 1;
  const float *p00 = env->image + 3 * ((size_t)y0 * env->iw + x0);
  const float *p10 = env->image + 3 * ((size_t)y0 * env->iw + x1);
  const float *p01 = env->image + 3 * ((size_t)y1 * env->iw + x0);
  const float *p11 = env->image + 3 * ((size_t)y1 * env->iw + x1);
  for (int c = 0; c < 3; c++)
    rgb[c] = (1 - fx) * (1 - fy) * p00[c] + fx * (1 - fy) * p10[c] + (1 - fx) * fy * p01[c] +
             fx * fy * p11[c];
}

/* Rotation about +y by ±the environment's angle (counter-clockwise seen from above). */
static vec3 rotate(const render_env *env, vec3 d, double sign) {
  double c = env->rot_c, s = sign * env->rot_s;
  return v3(c * d.x + s * d.z, d.y, -s * d.x + c * d.z);
}

/* Radiance in the environment's own frame. */
static void radiance_local(const render_env *env, vec3 d, double rgb[3]) {
  if (env->kind == NBRDF_ENV_CONSTANT) {
    memcpy(rgb, env->value, 3 * sizeof(double));
  } else if (env->kind == NBRDF_ENV_SKY) {
    sky(env, d, rgb);
  } else {
    double s, t;
    st_of(d, &s, &t);
    image_radiance(env, s, t, rgb);
  }
  for (int c = 0; c < 3; c++)
    rgb[c] *= env->scale;
}

void render_env_radiance(const render_env *env, vec3 d, double rgb[3]) {
  radiance_local(env, rotate(env, d, -1.0), rgb);
}

/* Cell importance: the brightest of a few radiance samples in the cell. */
static double cell_value(const render_env *env, int i, int j) {
  double best = 0.0, rgb[3];
  if (env->kind == NBRDF_ENV_IMAGE) {
    int x0 = i * env->iw / TABLE_W, x1 = (i + 1) * env->iw / TABLE_W;
    int y0 = j * env->ih / TABLE_H, y1 = (j + 1) * env->ih / TABLE_H;
    if (x1 <= x0) x1 = x0 + 1;
    if (y1 <= y0) y1 = y0 + 1;
    for (int y = y0; y < y1 && y < env->ih; y++)
      for (int x = x0; x < x1 && x < env->iw; x++) {
        const float *p = env->image + 3 * ((size_t)y * env->iw + x);
        double c[3] = {p[0], p[1], p[2]};
        best = fmax(best, luminance(c));
      }
    return best;
  }
  for (int k = 0; k < 4; k++) {
    double s = (i + 0.25 + 0.5 * (k & 1)) / TABLE_W, t = (j + 0.25 + 0.5 * (k >> 1)) / TABLE_H;
    radiance_local(env, dir_of(s, t), rgb);
    best = fmax(best, luminance(rgb));
  }
  return best;
}

static nbrdf_status build_table(render_env *env, nbrdf_error *err) {
  env->cell_prob = malloc(sizeof(double) * TABLE_W * TABLE_H);
  env->cond_cdf = malloc(sizeof(double) * TABLE_H * (TABLE_W + 1));
  env->marg_cdf = malloc(sizeof(double) * (TABLE_H + 1));
  if (!env->cell_prob || !env->cond_cdf || !env->marg_cdf)
    return core_fail(err, NBRDF_ERR_MEMORY, "environment table: out of memory");
  double total = 0.0, floor_v;
  for (int j = 0; j < TABLE_H; j++) {
    double sin_t = sin((j + 0.5) / TABLE_H * M_PI);
    for (int i = 0; i < TABLE_W; i++) {
      double v = cell_value(env, i, j);
      env->cell_prob[j * TABLE_W + i] = (isfinite(v) && v > 0.0 ? v : 0.0) * sin_t;
      total += env->cell_prob[j * TABLE_W + i];
    }
  }
  /* The floor: 1% of the mean, times sin θ, so that no direction is unsampled. */
  floor_v = total > 0.0 ? 0.01 * total / (TABLE_W * TABLE_H) : 1.0;
  total = 0.0;
  for (int j = 0; j < TABLE_H; j++) {
    double sin_t = sin((j + 0.5) / TABLE_H * M_PI);
    for (int i = 0; i < TABLE_W; i++)
      total += env->cell_prob[j * TABLE_W + i] += floor_v * sin_t;
  }
  env->marg_cdf[0] = 0.0;
  for (int j = 0; j < TABLE_H; j++) {
    double *cdf = env->cond_cdf + (size_t)j * (TABLE_W + 1), row = 0.0;
    cdf[0] = 0.0;
    for (int i = 0; i < TABLE_W; i++)
      cdf[i + 1] = cdf[i] + (env->cell_prob[j * TABLE_W + i] /= total);
    row = cdf[TABLE_W];
    for (int i = 1; i <= TABLE_W; i++)
      cdf[i] /= row;
    env->marg_cdf[j + 1] = env->marg_cdf[j] + row;
  }
  return NBRDF_OK;
}

/* Index k with cdf[k] <= u < cdf[k + 1] (n cells). */
static int find(const double *cdf, int n, double u) {
  int lo = 0, hi = n - 1;
  while (lo < hi) {
    int mid = (lo + hi + 1) / 2;
    if (cdf[mid] <= u)
      lo = mid;
    else
      hi = mid - 1;
  }
  return lo;
}

static double cell_pdf(const render_env *env, int i, int j, double t) {
  double sin_t = sin(t * M_PI);
  if (!(sin_t > 1e-9)) return 0.0;
  /* Uniform in (s, t) within the cell; dω = 2π² sin θ ds dt. */
  return env->cell_prob[j * TABLE_W + i] * TABLE_W * TABLE_H / (2.0 * M_PI * M_PI * sin_t);
}

double render_env_sample(const render_env *env, double u1, double u2, vec3 *d) {
  u2 *= env->marg_cdf[TABLE_H];
  int j = find(env->marg_cdf, TABLE_H, u2);
  double pj = env->marg_cdf[j + 1] - env->marg_cdf[j];
  double fy = pj > 0.0 ? (u2 - env->marg_cdf[j]) / pj : 0.5;
  const double *cdf = env->cond_cdf + (size_t)j * (TABLE_W + 1);
  int i = find(cdf, TABLE_W, u1);
  double pi = cdf[i + 1] - cdf[i];
  double fx = pi > 0.0 ? (u1 - cdf[i]) / pi : 0.5;
  double s = (i + fmin(fmax(fx, 0.0), 1.0)) / TABLE_W;
  double t = (j + fmin(fmax(fy, 0.0), 1.0)) / TABLE_H;
  *d = rotate(env, dir_of(s, t), 1.0);
  return cell_pdf(env, i, j, t);
}

double render_env_pdf(const render_env *env, vec3 d) {
  double s, t;
  st_of(rotate(env, d, -1.0), &s, &t);
  int i = (int)(s * TABLE_W), j = (int)(t * TABLE_H);
  if (i >= TABLE_W) i = TABLE_W - 1;
  if (j >= TABLE_H) j = TABLE_H - 1;
  return cell_pdf(env, i, j, t);
}

static nbrdf_status load_image(render_env *env, const char *path, nbrdf_error *err) {
  texture_image_in *in = NULL;
  texture_image_info info;
  nbrdf_status st = texture_image_open(path, 0, &in, &info, err);
  if (st != NBRDF_OK) return st;
  int colour = info.channels >= 3 && info.alpha_channel != 1 && info.alpha_channel != 2 ? 3 : 1;
  float *raw = malloc(sizeof(float) * (size_t)info.width * info.height * colour);
  env->image = malloc(sizeof(float) * 3 * (size_t)info.width * info.height);
  if (!raw || !env->image) st = core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory", path);
  if (st == NBRDF_OK) st = texture_image_read_rows(in, 0, 0, info.height, 0, colour, raw, err);
  texture_image_close(in);
  for (size_t p = 0; st == NBRDF_OK && p < (size_t)info.width * info.height; p++)
    for (int c = 0; c < 3; c++) {
      float v = raw[p * colour + (colour == 3 ? c : 0)];
      if (!isfinite(v) || v < 0.0f)
        st = core_fail(err, NBRDF_ERR_FORMAT,
                       "%s: pixel (%zu, %zu) is %g (radiance must be "
                       "finite and >= 0)",
                       path, p % (size_t)info.width, p / (size_t)info.width, (double)v);
      env->image[3 * p + c] = v;
    }
  free(raw);
  env->iw = info.width, env->ih = info.height;
  return st;
}

nbrdf_status render_env_create(const nbrdf_render_options *opts, render_env **out,
                               nbrdf_error *err) {
  *out = NULL;
  render_env *env = calloc(1, sizeof *env);
  if (!env) return core_fail(err, NBRDF_ERR_MEMORY, "environment: out of memory");
  env->kind = opts->env;
  env->scale = opts->env_scale;
  env->sun = v3_normalize(v3(0.5, 0.55, 0.45));
  double rot = opts->env_rotation_deg * M_PI / 180.0;
  env->rot_c = cos(rot), env->rot_s = sin(rot);
  for (int c = 0; c < 3; c++)
    env->value[c] = opts->env_value[c];
  nbrdf_status st = NBRDF_OK;
  if (!isfinite(opts->env_rotation_deg))
    st = core_fail(err, NBRDF_ERR_ARGUMENT, "environment rotation is not finite");
  else if (!(opts->env_scale >= 0.0f) || !isfinite(opts->env_scale))
    st = core_fail(err, NBRDF_ERR_ARGUMENT, "environment scale %g is not finite and >= 0",
                   (double)opts->env_scale);
  else if (env->kind == NBRDF_ENV_CONSTANT) {
    for (int c = 0; c < 3; c++)
      if (!(opts->env_value[c] >= 0.0f) || !isfinite(opts->env_value[c]))
        st = core_fail(err, NBRDF_ERR_ARGUMENT, "constant environment %g is not finite and >= 0",
                       (double)opts->env_value[c]);
  } else if (env->kind == NBRDF_ENV_IMAGE) {
    if (!opts->env_path)
      st = core_fail(err, NBRDF_ERR_ARGUMENT, "environment image: no path given");
    else
      st = load_image(env, opts->env_path, err);
  } else if (env->kind != NBRDF_ENV_SKY) {
    st = core_fail(err, NBRDF_ERR_ARGUMENT, "unknown environment kind %d", (int)env->kind);
  }
  if (st == NBRDF_OK) st = build_table(env, err);
  if (st != NBRDF_OK) {
    render_env_free(env);
    return st;
  }
  *out = env;
  return NBRDF_OK;
}

void render_env_free(render_env *env) {
  if (!env) return;
  free(env->image);
  free(env->cond_cdf);
  free(env->marg_cdf);
  free(env->cell_prob);
  free(env);
}
