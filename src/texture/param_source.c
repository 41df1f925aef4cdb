#include "texture/param_source.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"

struct nbrdf_param_source {
  char name[32];
  int channels;
  float constant[3];
  nbrdf_param_map *map; /* NULL for a constant */
  float *rows;          /* the last band read from the map */
  size_t rows_cap;      /* floats */
  char description[512];
};

static nbrdf_param_source *new_source(const char *name) {
  nbrdf_param_source *s = calloc(1, sizeof *s);
  if (s) snprintf(s->name, sizeof s->name, "%s", name ? name : "parameter");
  return s;
}

nbrdf_status nbrdf_param_source_constant(const char *name, const float *value, int channels,
                                         nbrdf_param_source **out, nbrdf_error *err) {
  *out = NULL;
  const char *who = name ? name : "parameter";
  if (channels != 1 && channels != 3)
    return nbrdf_fail(err, NBRDF_ERR_ARGUMENT, "%s: a constant has 1 or 3 values, not %d", who,
                      channels);
  for (int c = 0; c < channels; c++)
    if (!isfinite(value[c]) || value[c] < 0.0f)
      return nbrdf_fail(err, NBRDF_ERR_ARGUMENT, "%s: %g is not a finite value >= 0", who,
                        (double)value[c]);
  nbrdf_param_source *s = new_source(name);
  if (!s) return nbrdf_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory", who);
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

nbrdf_status nbrdf_param_source_map(const char *name, const char *path,
                                    const nbrdf_param_map_options *opts, nbrdf_param_source **out,
                                    nbrdf_error *err) {
  *out = NULL;
  nbrdf_param_source *s = new_source(name);
  if (!s) return nbrdf_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory", name ? name : "map");
  nbrdf_status st = nbrdf_param_map_open(path, opts, &s->map, err);
  if (st != NBRDF_OK) {
    nbrdf_error_prefix(err, "%s: ", s->name);
    free(s);
    return st;
  }
  const nbrdf_param_map_info *in = nbrdf_param_map_get_info(s->map);
  s->channels = in->channels;
  snprintf(s->description, sizeof s->description, "%s=%s (%s %s %s, %s)", s->name, path,
           in->file_format, in->format_name, in->channels == 1 ? "grey" : "rgb", in->conversion);
  *out = s;
  return NBRDF_OK;
}

/* Parses "v" or "v,v,v" completely; returns the number of values, or 0. */
static int parse_numbers(const char *arg, float v[3]) {
  const char *p = arg;
  int n = 0;
  while (n < 3) {
    char *end;
    errno = 0;
    double d = strtod(p, &end);
    if (end == p || errno == ERANGE) return 0;
    v[n++] = (float)d;
    while (*end == ' ')
      end++;
    if (*end == '\0') return n == 1 || n == 3 ? n : 0;
    if (*end != ',') return 0;
    p = end + 1;
  }
  return 0;
}

nbrdf_status nbrdf_param_source_parse(const char *name, const char *arg,
                                      const nbrdf_param_map_options *opts, nbrdf_param_source **out,
                                      nbrdf_error *err) {
  *out = NULL;
  if (!arg || !arg[0])
    return nbrdf_fail(err, NBRDF_ERR_ARGUMENT, "%s: empty value", name ? name : "parameter");
  float v[3];
  int n = parse_numbers(arg, v);
  if (n) return nbrdf_param_source_constant(name, v, n, out, err);
  return nbrdf_param_source_map(name, arg, opts, out, err);
}

int nbrdf_param_source_is_constant(const nbrdf_param_source *s) { return s->map == NULL; }
int nbrdf_param_source_channels(const nbrdf_param_source *s) { return s->channels; }

void nbrdf_param_source_size(const nbrdf_param_source *s, int *width, int *height) {
  const nbrdf_param_map_info *in = s->map ? nbrdf_param_map_get_info(s->map) : NULL;
  *width = in ? in->width : 0;
  *height = in ? in->height : 0;
}

float nbrdf_param_source_value(const nbrdf_param_source *s, int c) {
  return s->map || c < 0 || c > 2 ? 0.0f : s->constant[c];
}

const char *nbrdf_param_source_describe(const nbrdf_param_source *s) { return s->description; }
nbrdf_param_map *nbrdf_param_source_get_map(nbrdf_param_source *s) { return s->map; }

nbrdf_status nbrdf_param_source_read_band(nbrdf_param_source *s, int y0, int rows,
                                          nbrdf_param_band *band, nbrdf_error *err) {
  band->channels = s->channels;
  if (!s->map) {
    band->data = s->constant;
    band->row_stride = band->texel_stride = 0;
    return NBRDF_OK;
  }
  const nbrdf_param_map_info *in = nbrdf_param_map_get_info(s->map);
  size_t need = rows > 0 ? (size_t)rows * in->width * in->channels : 0;
  if (need > s->rows_cap) {
    float *p = realloc(s->rows, need * sizeof(float));
    if (!p)
      return nbrdf_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory for %d rows", s->name, rows);
    s->rows = p;
    s->rows_cap = need;
  }
  nbrdf_status st = nbrdf_param_map_read_rows(s->map, y0, rows, s->rows, err);
  if (st != NBRDF_OK) {
    nbrdf_error_prefix(err, "%s: ", s->name);
    return st;
  }
  band->data = s->rows;
  band->texel_stride = in->channels;
  band->row_stride = (ptrdiff_t)in->width * in->channels;
  return NBRDF_OK;
}

void nbrdf_param_source_free(nbrdf_param_source *s) {
  if (!s) return;
  nbrdf_param_map_close(s->map);
  free(s->rows);
  free(s);
}

nbrdf_status nbrdf_param_sources_common_size(nbrdf_param_source *const *sources, int n, int *width,
                                             int *height, nbrdf_error *err) {
  const nbrdf_param_source *first = NULL;
  *width = *height = 0;
  for (int i = 0; i < n; i++) {
    const nbrdf_param_source *s = sources[i];
    if (!s || !s->map) continue;
    int w, h;
    nbrdf_param_source_size(s, &w, &h);
    if (!first) {
      first = s;
      *width = w;
      *height = h;
    } else if (w != *width || h != *height) {
      return nbrdf_fail(err, NBRDF_ERR_MISMATCH, "%s: %s is %dx%d, but %s: %s is %dx%d", s->name,
                        nbrdf_param_map_path(s->map), w, h, first->name,
                        nbrdf_param_map_path(first->map), *width, *height);
    }
  }
  return NBRDF_OK;
}
