#include "bake/bake_range.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/error.h"
#include "model/material.h"

/* Rows read at a time: bounded memory whatever the width (the sources keep one band each). */
#define SCAN_TEXELS 65536

void bake_source_where(texture_param_source **src, int id, int x, int y, int c, char *buf,
                       size_t n) {
  texture_param_source *s = src[id];
  texture_param_map *m = texture_param_source_get_map(s);
  if (!m) {
    snprintf(buf, n, "%s (constant)", model_material_param_name(id));
    return;
  }
  static const char rgb[] = "RGB";
  if (texture_param_source_channels(s) == 3)
    snprintf(buf, n, "%s: texel (%d, %d) channel %c, %s", texture_param_map_path(m), x, y, rgb[c],
             model_material_param_name(id));
  else
    snprintf(buf, n, "%s: texel (%d, %d), %s", texture_param_map_path(m), x, y,
             model_material_param_name(id));
}

static int perceptual(int id, nbrdf_roughness r) {
  return r == NBRDF_ROUGHNESS_PERCEPTUAL && (id == NBRDF_BAKE_ALPHA1 || id == NBRDF_BAKE_ALPHA2);
}

static const char *units(int id, nbrdf_roughness r) {
  switch (id) {
  case NBRDF_BAKE_ALPHA1:
  case NBRDF_BAKE_ALPHA2:
    return perceptual(id, r) ? "perceptual roughness" : "GGX alpha";
  case NBRDF_BAKE_ETA:
    return "IOR";
  case NBRDF_BAKE_R0:
    return "reflectance";
  case NBRDF_BAKE_ALBEDO:
    return "albedo";
  default:
    return "optical depth";
  }
}

int bake_level_fits_alpha(nbrdf_bake_accuracy a) { return a != NBRDF_BAKE_FAST; }

void bake_taken_ranges(const nbrdf_model *model, nbrdf_bake_accuracy a, float *lo, float *hi) {
  model_material_ranges(model, lo, hi);
  if (!bake_level_fits_alpha(a)) return;
  if (lo[NBRDF_BAKE_ALPHA1] > BAKE_ALPHA_FIT_MIN) lo[NBRDF_BAKE_ALPHA1] = BAKE_ALPHA_FIT_MIN;
  if (lo[NBRDF_BAKE_ALPHA2] > BAKE_ALPHA_FIT_MIN) lo[NBRDF_BAKE_ALPHA2] = BAKE_ALPHA_FIT_MIN;
}

float bake_quantise(const float *lo, const float *hi, int id, int bits, float v) {
  return v < lo[id] ? v : model_material_quantise(lo, hi, id, bits, v);
}

/* The first refused value in the bake's order, to fail with after the report. */
typedef struct refusal {
  model_material_verdict verdict;
  int id, x, y, c;
  float typed;
} refusal;

typedef struct scan {
  const nbrdf_bake_options *o;
  float lo[MODEL_MATERIAL_PARAMS], hi[MODEL_MATERIAL_PARAMS]; /* trained */
  float take[MODEL_MATERIAL_PARAMS]; /* lower ends the level takes (bake_taken_ranges) */
  float fit[MODEL_MATERIAL_PARAMS];  /* ... and the fitting levels take */
  nbrdf_bake_range r[MODEL_MATERIAL_PARAMS];
  refusal first;
} scan;

/* One value as typed: counted into the texel's flags (below the trained range, below what
 * the fitting levels take, above), the first refusal remembered. The policy applies to the range
 * the level takes; what is below the trained range only is reported, not clamped here. */
static void value(scan *s, int id, float typed, int x, int y, int c, int *below, int *below_fit,
                  int *above) {
  float v = typed;
  model_material_verdict verdict =
      model_material_prepare(s->take, s->hi, id, s->o->roughness, s->o->range, &v, NULL);
  if (verdict == MODEL_VALUE_OK || verdict == MODEL_VALUE_CLAMPED ||
      verdict == MODEL_VALUE_OUTSIDE) {
    float a = model_material_read(id, s->o->roughness, typed);
    nbrdf_bake_range *r = &s->r[id];
    if (a < s->lo[id]) {
      *below = 1;
      if (a < s->fit[id]) *below_fit = 1;
      if (!(typed >= r->min)) r->min = typed;
    } else if (a > s->hi[id]) {
      *above = 1;
      if (!(typed <= r->max)) r->max = typed;
    }
  }
  if (verdict != MODEL_VALUE_OK && verdict != MODEL_VALUE_CLAMPED &&
      s->first.verdict == MODEL_VALUE_OK)
    s->first = (refusal){verdict, id, x, y, c, typed};
}

static nbrdf_status scan_rows(scan *s, texture_param_source **src, int W, int y0, int rows, int C,
                              nbrdf_error *err) {
  texture_param_band band[MODEL_MATERIAL_PARAMS];
  for (int id = 0; id < MODEL_MATERIAL_PARAMS; id++) {
    nbrdf_status st = texture_param_source_read_band(src[id], y0, rows, &band[id], err);
    if (st != NBRDF_OK) return st;
  }
  int constant[MODEL_MATERIAL_PARAMS];
  for (int id = 0; id < MODEL_MATERIAL_PARAMS; id++)
    constant[id] = texture_param_source_is_constant(src[id]);
  for (int j = 0; j < rows; j++)
    for (int x = 0; x < W; x++) {
      int below[MODEL_MATERIAL_PARAMS] = {0}, below_fit[MODEL_MATERIAL_PARAMS] = {0},
          above[MODEL_MATERIAL_PARAMS] = {0};
      for (int c = 0; c < C; c++)
        for (int id = 0; id < MODEL_MATERIAL_PARAMS; id++) {
          /* A constant is looked at once, at the first texel (where the bake meets it first). */
          if (constant[id] && (y0 + j || x)) continue;
          value(s, id, texture_param_band_at(&band[id], x, j, c), x, y0 + j, c, &below[id],
                &below_fit[id], &above[id]);
        }
      for (int id = 0; id < MODEL_MATERIAL_PARAMS; id++) {
        s->r[id].below += (size_t)below[id], s->r[id].above += (size_t)above[id];
        s->r[id].below_fit += (size_t)below_fit[id];
      }
    }
  return NBRDF_OK;
}

nbrdf_status bake_range_check(const nbrdf_model *model, texture_param_source **src,
                              const nbrdf_bake_options *o, nbrdf_error *err) {
  int W, H;
  nbrdf_error ignored;
  /* Sizes that disagree or exceed a texture are the bake's own errors, with its words. */
  if (texture_param_sources_common_size(src, MODEL_MATERIAL_PARAMS, &W, &H, &ignored) != NBRDF_OK ||
      W > NBRDF_BAKE_SIZE_MAX || H > NBRDF_BAKE_SIZE_MAX)
    return NBRDF_OK;
  if (W == 0) W = H = 1; /* every input a constant */
  scan s = {.o = o};
  model_material_ranges(model, s.lo, s.hi);
  float take_hi[MODEL_MATERIAL_PARAMS];
  bake_taken_ranges(model, o->accuracy, s.take, take_hi);
  /* What fitting levels would take, for the message's hint even at FAST. */
  float fit_hi[MODEL_MATERIAL_PARAMS];
  bake_taken_ranges(model, NBRDF_BAKE_FITTED, s.fit, fit_hi);
  int C = 1;
  for (int id = 0; id < MODEL_MATERIAL_PARAMS; id++) {
    if (texture_param_source_channels(src[id]) == 3) C = 3;
    int p = perceptual(id, o->roughness);
    s.r[id] = (nbrdf_bake_range){
        .param = id,
        .name = model_material_param_name(id),
        .units = units(id, o->roughness),
        .constant = texture_param_source_is_constant(src[id]),
        .min = INFINITY,
        .max = -INFINITY,
        .lo = p ? sqrt((double)s.lo[id]) : (double)s.lo[id],
        .hi = p ? sqrt((double)s.hi[id]) : (double)s.hi[id],
        .policy = o->range,
        .fit_lo = p ? sqrt((double)s.fit[id]) : (double)s.fit[id],
        .accuracy = o->accuracy,
    };
  }
  int band_rows = SCAN_TEXELS / W;
  if (band_rows < 1) band_rows = 1;
  for (int y = 0; y < H; y += band_rows) {
    if (o->cancel && *o->cancel)
      return core_fail(err, NBRDF_ERR_CANCELLED, "bake: cancelled while checking ranges");
    nbrdf_status st = scan_rows(&s, src, W, y, H - y < band_rows ? H - y : band_rows, C, err);
    if (st != NBRDF_OK) return st;
  }
  for (int id = 0; id < MODEL_MATERIAL_PARAMS; id++) {
    const nbrdf_bake_range *r = &s.r[id];
    if (!r->below && !r->above) continue;
    if (o->range_report) {
      o->range_report(o->user, r);
    } else if (o->warning) {
      char msg[768];
      o->warning(o->user, nbrdf_bake_range_message(r, msg, sizeof msg));
    }
  }
  const refusal *f = &s.first;
  if (f->verdict == MODEL_VALUE_OK) return NBRDF_OK;
  char at[600];
  bake_source_where(src, f->id, f->x, f->y, f->c, at, sizeof at);
  return model_material_fail(f->verdict, s.lo, s.hi, f->id, o->roughness, at, f->typed, err);
}

/* n with thousands separated by commas ("1,204"), as people read counts. */
static void count_text(size_t n, char *buf, size_t cap) {
  char digits[32];
  int len = snprintf(digits, sizeof digits, "%zu", n), o = 0;
  for (int i = 0; i < len && (size_t)o + 2 < cap; i++) {
    if (i && (len - i) % 3 == 0) buf[o++] = ',';
    buf[o++] = digits[i];
  }
  buf[o] = '\0';
}

#define FITTERS "fitted, specialised and compact"

/* Below the trained range, for alpha1 and alpha2 (fit_lo < lo): what each level does. At a
 * fitting level (or auto) values down to fit_lo pass whatever the policy, fast would bake
 * them as lo, and the policy applies below fit_lo; at fast, the fitting levels are hinted. */
static void below_fit(const nbrdf_bake_range *r, char *buf, size_t cap) {
  const int refuse = r->policy == NBRDF_RANGE_REFUSE;
  if (!bake_level_fits_alpha(r->accuracy)) {
    char what[160], count[48];
    count_text(r->below, count, sizeof count);
    if (r->constant)
      snprintf(what, sizeof what, "%g is below %g%s", r->min, r->lo, refuse ? " (" : " and");
    else
      snprintf(what, sizeof what, "%s texel%s below %g (min %g%s", count, r->below == 1 ? "" : "s",
               r->lo, r->min, refuse ? "; " : ")");
    if (refuse)
      snprintf(buf, cap, "%strained range [%g, %g]; " FITTERS " take down to %.3g as given)",
               what, r->lo, r->hi, r->fit_lo);
    else
      snprintf(buf, cap, "%s will be baked as %g (" FITTERS " fit down to %.3g as given)", what,
               r->lo, r->fit_lo);
    return;
  }
  if (r->constant) {
    if (r->below_fit == 0)
      snprintf(buf, cap, "%g is below %g: fast bakes it as %g; " FITTERS " fit it as given", r->min,
               r->lo, r->lo);
    else if (refuse)
      snprintf(buf, cap, "%g is below %.3g, the lowest " FITTERS " take (trained range [%g, %g])",
               r->min, r->fit_lo, r->lo, r->hi);
    else
      snprintf(buf, cap,
               "%g is below %.3g, the lowest " FITTERS " take: they fit it as %.3g (fast bakes it "
               "as "
               "%g)",
               r->min, r->fit_lo, r->fit_lo, r->lo);
    return;
  }
  char count[48];
  count_text(r->below, count, sizeof count);
  const int one = r->below == 1;
  int len = snprintf(
      buf, cap, "%s texel%s below %g (min %g): fast bakes %s as %g; " FITTERS " fit %s as given",
      count, one ? "" : "s", r->lo, r->min, one ? "it" : "them", r->lo, one ? "it" : "them");
  if (r->below_fit == 0 || len < 0 || (size_t)len >= cap) return;
  count_text(r->below_fit, count, sizeof count);
  if (refuse)
    snprintf(buf + len, cap - (size_t)len, ", but %s below %.3g, the lowest they take, %s refused",
             count, r->fit_lo, r->below_fit == 1 ? "is" : "are");
  else
    snprintf(buf + len, cap - (size_t)len, ", and %s below %.3g as %.3g", count, r->fit_lo,
             r->fit_lo);
}

static void side(const nbrdf_bake_range *r, int below, char *buf, size_t cap) {
  /* fit_lo 0: a report made without it (zero-initialised), worded as before. */
  if (below && r->fit_lo > 0.0 && r->fit_lo < r->lo) {
    below_fit(r, buf, cap);
    return;
  }
  const char *where = below ? "below" : "above";
  double bound = below ? r->lo : r->hi, seen = below ? r->min : r->max;
  size_t n = below ? r->below : r->above;
  if (r->constant) {
    if (r->policy == NBRDF_RANGE_REFUSE)
      snprintf(buf, cap, "%g is %s %g (trained range [%g, %g])", seen, where, bound, r->lo, r->hi);
    else
      snprintf(buf, cap, "%g is %s %g and will be baked as %g", seen, where, bound, bound);
    return;
  }
  char count[48];
  count_text(n, count, sizeof count);
  if (r->policy == NBRDF_RANGE_REFUSE)
    snprintf(buf, cap, "%s texel%s %s %g (%s %g; trained range [%g, %g])", count, n == 1 ? "" : "s",
             where, bound, below ? "min" : "max", seen, r->lo, r->hi);
  else
    snprintf(buf, cap, "%s texel%s %s %g (%s %g) will be baked as %g", count, n == 1 ? "" : "s",
             where, bound, below ? "min" : "max", seen, bound);
}

const char *nbrdf_bake_range_message(const nbrdf_bake_range *r, char *buf, size_t cap) {
  char lo[320] = "", hi[160] = "";
  if (r->below) side(r, 1, lo, sizeof lo);
  if (r->above) side(r, 0, hi, sizeof hi);
  int len = snprintf(buf, cap, "%s (%s): %s%s%s", r->name, r->units, lo,
                     r->below && r->above ? "; " : "", hi);
  /* eta = 1 (no coat) is the usual value below the range: say how to get it. */
  if (r->param == NBRDF_BAKE_ETA && r->below && r->lo > 1.0 && len > 0 && (size_t)len < cap)
    snprintf(buf + len, cap - (size_t)len,
             " (a bundle whose base tables start at eta = 1, `nbrdf train tables --eta-min 1`, "
             "takes eta = 1, no coat, unclamped)");
  return buf;
}
