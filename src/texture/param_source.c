#include "texture/param_source.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "core/number.h"

struct texture_param_source {
  char name[32];
  int channels;
  float constant[3];
  texture_param_map *map; /* NULL for a constant */
  float *rows;          /* the last band read from the map */
  size_t rows_cap;      /* floats */
  char description[512];
  /* bilinear resampling (texture_param_source_resample): target size, 0 when off,
   * and the source rows [cy0, cy1) last read, kept because consecutive bands
   * share a source row and formats like PNG cannot seek backwards cheaply */
  int tw, th;
  float *src_rows;
  size_t src_cap;
  int cy0, cy1;
};

static texture_param_source *new_source(const char *name) {
  texture_param_source *s = calloc(1, sizeof *s);
  if (s) snprintf(s->name, sizeof s->name, "%s", name ? name : "parameter");
  return s;
}

nbrdf_status texture_param_source_constant(const char *name, const float *value, int channels,
                                           texture_param_source **out, nbrdf_error *err) {
  *out = NULL;
  const char *who = name ? name : "parameter";
  if (channels != 1 && channels != 3)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "%s: a constant has 1 or 3 values, not %d", who,
                     channels);
  for (int c = 0; c < channels; c++)
    if (!isfinite(value[c]) || value[c] < 0.0f)
      return core_fail(err, NBRDF_ERR_ARGUMENT, "%s: %g is not a finite value >= 0", who,
                       (double)value[c]);
  texture_param_source *s = new_source(name);
  if (!s) return core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory", who);
  s->channels = channels;
  for (int c = 0; c < 3; c++)
    s->constant[c] = value[channels == 3 ? c : 0];
  if (channels == 1)
    snprintf(s->description, sizeof s->description, "%s=%.9g", s->name, (double)value[0]);
  else
    snprintf(s->description, sizeof s->description, "%s=%.9g,%.9g,%.9g", s->name, (double)value[0],
             (double)value[1], (double)value[2]);
  *out = s;
  return NBRDF_OK;
}

nbrdf_status texture_param_source_map(const char *name, const char *path,
                                      const texture_param_map_options *opts,
                                      texture_param_source **out, nbrdf_error *err) {
  *out = NULL;
  texture_param_source *s = new_source(name);
  if (!s) return core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory", name ? name : "map");
  nbrdf_status st = texture_param_map_open(path, opts, &s->map, err);
  if (st != NBRDF_OK) {
    core_error_prefix(err, "%s: ", s->name);
    free(s);
    return st;
  }
  const texture_param_map_info *in = texture_param_map_get_info(s->map);
  s->channels = in->channels;
  snprintf(s->description, sizeof s->description, "%s=%s (%s %s %s, %s)", s->name, path,
           in->file_format, in->format_name, in->channels == 1 ? "grey" : "rgb", in->conversion);
  *out = s;
  return NBRDF_OK;
}

/* Parses "v" or "v,v,v" completely; returns the number of values, 0 if not
 * numbers, -1 if one is out of a float's range (*bad says which). */
static int parse_numbers(const char *arg, float v[3], core_number_result *bad) {
  int n = 0;
  for (const char *s = arg;;) {
    const char *comma = strchr(s, ',');
    size_t len = comma ? (size_t)(comma - s) : strlen(s);
    if (n == 3) return 0;
    core_number_result r = core_parse_float(s, len, &v[n++]);
    if (r == NBRDF_NUMBER_OVERFLOW || r == NBRDF_NUMBER_UNDERFLOW) return *bad = r, -1;
    if (r != NBRDF_NUMBER_OK) return 0;
    if (!comma) return n == 1 || n == 3 ? n : 0;
    s = comma + 1;
  }
}

nbrdf_status texture_param_source_parse(const char *name, const char *arg,
                                        const texture_param_map_options *opts,
                                        texture_param_source **out, nbrdf_error *err) {
  *out = NULL;
  if (!arg || !arg[0])
    return core_fail(err, NBRDF_ERR_ARGUMENT, "%s: empty value", name ? name : "parameter");
  float v[3];
  core_number_result bad = NBRDF_NUMBER_OK;
  int n = parse_numbers(arg, v, &bad);
  if (n < 0)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "%s: '%s': a value %s for a float",
                     name ? name : "parameter", arg, core_number_problem(bad));
  if (n) return texture_param_source_constant(name, v, n, out, err);
  return texture_param_source_map(name, arg, opts, out, err);
}

int texture_param_source_is_constant(const texture_param_source *s) { return s->map == NULL; }
int texture_param_source_channels(const texture_param_source *s) { return s->channels; }

void texture_param_source_size(const texture_param_source *s, int *width, int *height) {
  const texture_param_map_info *in = s->map ? texture_param_map_get_info(s->map) : NULL;
  *width = in ? (s->tw ? s->tw : in->width) : 0;
  *height = in ? (s->th ? s->th : in->height) : 0;
}

nbrdf_status texture_param_source_resample(texture_param_source *s, int width, int height,
                                           nbrdf_error *err) {
  if (!s->map) return NBRDF_OK;
  const texture_param_map_info *in = texture_param_map_get_info(s->map);
  if (width < 1 || height < 1)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "%s: %s: cannot resample to %dx%d", s->name,
                     texture_param_map_path(s->map), width, height);
  s->tw = width == in->width && height == in->height ? 0 : width;
  s->th = s->tw ? height : 0;
  s->cy0 = s->cy1 = 0;
  if (s->tw) {
    size_t len = strlen(s->description);
    snprintf(s->description + len, sizeof s->description - len, ", bilinear %dx%d -> %dx%d",
             in->width, in->height, width, height);
  }
  return NBRDF_OK;
}

static int grow_floats(float **p, size_t *cap, size_t need) {
  if (need <= *cap) return 1;
  float *q = realloc(*p, need * sizeof(float));
  if (!q) return 0;
  *p = q;
  *cap = need;
  return 1;
}

/* Texel centres line up: target coordinate t maps to source (t + 0.5) * n / m - 0.5,
 * clamped to the edge (as OpenImageIO's and most renderers' bilinear). */
static void source_coord(int t, int n, int m, int *i0, int *i1, float *f) {
  double u = (t + 0.5) * n / m - 0.5;
  if (u <= 0) u = 0;
  int i = (int)u;
  if (i >= n - 1) i = n - 1, u = i;
  *i0 = i;
  *i1 = i + 1 < n ? i + 1 : i;
  *f = (float)(u - i);
}

/* Rows [y0, y0 + rows) of the target size into s->rows. */
static nbrdf_status read_resampled(texture_param_source *s, int y0, int rows, nbrdf_error *err) {
  const texture_param_map_info *in = texture_param_map_get_info(s->map);
  const int W = in->width, H = in->height, ch = in->channels;
  const size_t row = (size_t)W * ch;
  int a, b, unused0;
  float unused1;
  source_coord(y0, H, s->th, &a, &unused0, &unused1);
  source_coord(y0 + rows - 1, H, s->th, &unused0, &b, &unused1);
  if (!grow_floats(&s->src_rows, &s->src_cap, (size_t)(b - a + 1) * row) ||
      !grow_floats(&s->rows, &s->rows_cap, (size_t)rows * s->tw * ch))
    return core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory for %d rows", s->name, rows);
  int have = 0; /* rows [a, a + have) already in src_rows */
  if (s->cy1 > s->cy0 && a >= s->cy0 && a < s->cy1) {
    have = (s->cy1 < b + 1 ? s->cy1 : b + 1) - a;
    memmove(s->src_rows, s->src_rows + (size_t)(a - s->cy0) * row, sizeof(float) * have * row);
  }
  if (a + have <= b) {
    nbrdf_status st = texture_param_map_read_rows(s->map, a + have, b + 1 - (a + have),
                                                  s->src_rows + (size_t)have * row, err);
    if (st != NBRDF_OK) {
      s->cy0 = s->cy1 = 0;
      core_error_prefix(err, "%s: ", s->name);
      return st;
    }
  }
  s->cy0 = a, s->cy1 = b + 1;
  for (int j = 0; j < rows; j++) {
    int r0, r1;
    float fy;
    source_coord(y0 + j, H, s->th, &r0, &r1, &fy);
    const float *p0 = s->src_rows + (size_t)(r0 - a) * row,
                *p1 = s->src_rows + (size_t)(r1 - a) * row;
    float *o = s->rows + (size_t)j * s->tw * ch;
    for (int x = 0; x < s->tw; x++) {
      int c0, c1;
      float fx;
      source_coord(x, W, s->tw, &c0, &c1, &fx);
      for (int c = 0; c < ch; c++) {
        float top = p0[c0 * ch + c] + fx * (p0[c1 * ch + c] - p0[c0 * ch + c]);
        float bot = p1[c0 * ch + c] + fx * (p1[c1 * ch + c] - p1[c0 * ch + c]);
        o[x * ch + c] = top + fy * (bot - top);
      }
    }
  }
  return NBRDF_OK;
}

float texture_param_source_value(const texture_param_source *s, int c) {
  return s->map || c < 0 || c > 2 ? 0.0f : s->constant[c];
}

const char *texture_param_source_describe(const texture_param_source *s) { return s->description; }
texture_param_map *texture_param_source_get_map(texture_param_source *s) { return s->map; }

nbrdf_status texture_param_source_read_band(texture_param_source *s, int y0, int rows,
                                            texture_param_band *band, nbrdf_error *err) {
  band->channels = s->channels;
  if (!s->map) {
    band->data = s->constant;
    band->row_stride = band->texel_stride = 0;
    return NBRDF_OK;
  }
  const texture_param_map_info *in = texture_param_map_get_info(s->map);
  if (s->tw) {
    if (y0 < 0 || rows < 1 || rows > s->th - y0)
      return core_fail(err, NBRDF_ERR_ARGUMENT, "%s: rows %d..%d of a map %d rows high", s->name,
                       y0, y0 + rows - 1, s->th);
    nbrdf_status st = read_resampled(s, y0, rows, err);
    band->data = s->rows;
    band->texel_stride = in->channels;
    band->row_stride = (ptrdiff_t)s->tw * in->channels;
    return st;
  }
  size_t need = rows > 0 ? (size_t)rows * in->width * in->channels : 0;
  if (need > s->rows_cap) {
    float *p = realloc(s->rows, need * sizeof(float));
    if (!p) return core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory for %d rows", s->name, rows);
    s->rows = p;
    s->rows_cap = need;
  }
  nbrdf_status st = texture_param_map_read_rows(s->map, y0, rows, s->rows, err);
  if (st != NBRDF_OK) {
    core_error_prefix(err, "%s: ", s->name);
    return st;
  }
  band->data = s->rows;
  band->texel_stride = in->channels;
  band->row_stride = (ptrdiff_t)in->width * in->channels;
  return NBRDF_OK;
}

void texture_param_source_free(texture_param_source *s) {
  if (!s) return;
  texture_param_map_close(s->map);
  free(s->rows);
  free(s->src_rows);
  free(s);
}

nbrdf_status texture_param_sources_common_size(texture_param_source *const *sources, int n,
                                               int *width, int *height, nbrdf_error *err) {
  const texture_param_source *first = NULL;
  *width = *height = 0;
  for (int i = 0; i < n; i++) {
    const texture_param_source *s = sources[i];
    if (!s || !s->map) continue;
    int w, h;
    texture_param_source_size(s, &w, &h);
    if (!first) {
      first = s;
      *width = w;
      *height = h;
    } else if (w != *width || h != *height) {
      return core_fail(err, NBRDF_ERR_MISMATCH,
                       "%s: %s is %dx%d, but %s: %s is %dx%d" TEXTURE_RESAMPLE_ADVICE,
                       s->name, texture_param_map_path(s->map), w, h, first->name,
                       texture_param_map_path(first->map), *width, *height);
    }
  }
  return NBRDF_OK;
}
