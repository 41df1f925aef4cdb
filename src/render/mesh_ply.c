/* PLY (ASCII and binary little-endian): element vertex with x, y, z, texture
 * coordinates (s, t; u, v; or texture_u, texture_v) and optional nx, ny, nz;
 * element face with a list vertex_indices (or vertex_index), fan-
 * triangulated. Other elements and properties are skipped. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "render/mesh.h"

enum { MAXPROP = 32, MAXELEM = 16 };

typedef struct ply_prop {
  char name[64];
  int type;     /* bytes of the value (1, 2, 4, 8) and kind below */
  int is_float; /* float / double */
  int is_signed;
  int is_list;
  int count_type, count_signed; /* list length's size in bytes */
} ply_prop;

typedef struct ply_elem {
  char name[64];
  long count;
  ply_prop prop[MAXPROP];
  int nprop;
} ply_elem;

static int type_of(const char *t, int *size, int *is_float, int *is_signed) {
  static const struct {
    const char *a, *b;
    int size, f, s;
  } types[] = {{"char", "int8", 1, 0, 1},     {"uchar", "uint8", 1, 0, 0},
               {"short", "int16", 2, 0, 1},   {"ushort", "uint16", 2, 0, 0},
               {"int", "int32", 4, 0, 1},     {"uint", "uint32", 4, 0, 0},
               {"float", "float32", 4, 1, 1}, {"double", "float64", 8, 1, 1}};
  for (size_t k = 0; k < sizeof types / sizeof types[0]; k++)
    if (!strcmp(t, types[k].a) || !strcmp(t, types[k].b)) {
      *size = types[k].size, *is_float = types[k].f, *is_signed = types[k].s;
      return 1;
    }
  return 0;
}

typedef struct ply_in {
  FILE *f;
  const char *path;
  int binary, line;
  nbrdf_error *err;
} ply_in;

/* One value (binary: of the property's type; ASCII: the next word). */
static int read_value(ply_in *in, int size, int is_float, int is_signed, double *out) {
  if (!in->binary) {
    char w[128];
    int c;
    while ((c = fgetc(in->f)) == ' ' || c == '\t' || c == '\r' || c == '\n')
      if (c == '\n') in->line++;
    if (c == EOF) {
      core_fail(in->err, NBRDF_ERR_FORMAT,
                "%s:%d: file ends inside the data (more values expected)", in->path, in->line);
      return 0;
    }
    int n = 0;
    while (c != EOF && c != ' ' && c != '\t' && c != '\r' && c != '\n' && n < 127)
      w[n++] = (char)c, c = fgetc(in->f);
    if (c == '\n') ungetc(c, in->f);
    w[n] = '\0';
    char *end;
    *out = strtod(w, &end);
    if (end == w || *end) {
      core_fail(in->err, NBRDF_ERR_FORMAT, "%s:%d: '%s' is not a number", in->path, in->line, w);
      return 0;
    }
    return 1;
  }
  unsigned char b[8];
  if (fread(b, 1, (size_t)size, in->f) != (size_t)size) {
    core_fail(in->err, NBRDF_ERR_FORMAT,
              "%s: binary data ends at byte %ld (more values expected by the header)", in->path,
              ftell(in->f));
    return 0;
  }
  uint64_t u = 0;
  for (int k = size - 1; k >= 0; k--)
    u = u << 8 | b[k]; /* little-endian */
  if (is_float) {
    if (size == 4) {
      uint32_t u32 = (uint32_t)u;
      float x;
      memcpy(&x, &u32, 4);
      *out = x;
    } else {
      double x;
      memcpy(&x, &u, 8);
      *out = x;
    }
  } else if (is_signed) {
    int64_t s = (int64_t)(u << (64 - 8 * size)) >> (64 - 8 * size);
    *out = (double)s;
  } else {
    *out = (double)u;
  }
  return 1;
}

static int find_prop(const ply_elem *e, const char *const *names) {
  for (int k = 0; k < e->nprop; k++)
    for (const char *const *n = names; *n; n++)
      if (!strcmp(e->prop[k].name, *n)) return k;
  return -1;
}

static nbrdf_status read_header(ply_in *in, ply_elem *el, int *nel) {
  char line[1024];
  *nel = 0;
  if (!fgets(line, sizeof line, in->f) || strncmp(line, "ply", 3))
    return core_fail(in->err, NBRDF_ERR_FORMAT, "%s:1: expected 'ply' (not a PLY file)", in->path);
  in->line = 1;
  int have_format = 0;
  while (fgets(line, sizeof line, in->f)) {
    in->line++;
    char a[64] = "", b[64] = "", c[64] = "", d[64] = "", e[64] = "";
    int n = sscanf(line, "%63s %63s %63s %63s %63s", a, b, c, d, e);
    if (n <= 0 || !strcmp(a, "comment") || !strcmp(a, "obj_info")) continue;
    if (!strcmp(a, "end_header")) {
      if (!have_format)
        return core_fail(in->err, NBRDF_ERR_FORMAT, "%s: no 'format' line in the header", in->path);
      return NBRDF_OK;
    }
    if (!strcmp(a, "format")) {
      if (!strcmp(b, "ascii"))
        in->binary = 0;
      else if (!strcmp(b, "binary_little_endian"))
        in->binary = 1;
      else
        return core_fail(in->err, NBRDF_ERR_UNSUPPORTED,
                         "%s:%d: format '%s', expected ascii or binary_little_endian", in->path,
                         in->line, b);
      have_format = 1;
    } else if (!strcmp(a, "element") && n == 3) {
      if (*nel == MAXELEM)
        return core_fail(in->err, NBRDF_ERR_FORMAT, "%s:%d: more than %d elements", in->path,
                         in->line, MAXELEM);
      ply_elem *x = &el[(*nel)++];
      memset(x, 0, sizeof *x);
      snprintf(x->name, sizeof x->name, "%s", b);
      char *end;
      x->count = strtol(c, &end, 10);
      if (*end || x->count < 0 || x->count > (1L << 30))
        return core_fail(in->err, NBRDF_ERR_FORMAT, "%s:%d: element count '%s', expected 0..2^30",
                         in->path, in->line, c);
    } else if (!strcmp(a, "property") && *nel > 0) {
      ply_elem *x = &el[*nel - 1];
      if (x->nprop == MAXPROP)
        return core_fail(in->err, NBRDF_ERR_FORMAT, "%s:%d: more than %d properties", in->path,
                         in->line, MAXPROP);
      ply_prop *p = &x->prop[x->nprop++];
      memset(p, 0, sizeof *p);
      int ok;
      if (!strcmp(b, "list") && n == 5) {
        p->is_list = 1;
        int f;
        ok = type_of(c, &p->count_type, &f, &p->count_signed) && !f &&
             type_of(d, &p->type, &p->is_float, &p->is_signed);
        snprintf(p->name, sizeof p->name, "%s", e);
      } else {
        ok = n == 3 && type_of(b, &p->type, &p->is_float, &p->is_signed);
        snprintf(p->name, sizeof p->name, "%s", c);
      }
      if (!ok)
        return core_fail(in->err, NBRDF_ERR_FORMAT,
                         "%s:%d: property line not understood (expected 'property TYPE NAME' or "
                         "'property list COUNT_TYPE TYPE NAME')",
                         in->path, in->line);
    } else {
      return core_fail(in->err, NBRDF_ERR_FORMAT, "%s:%d: unexpected header line '%s'", in->path,
                       in->line, a);
    }
  }
  return core_fail(in->err, NBRDF_ERR_FORMAT, "%s: the header has no 'end_header'", in->path);
}

nbrdf_status render_mesh_read_ply(const char *path, render_mesh **out, nbrdf_error *err) {
  *out = NULL;
  nbrdf_error local;
  if (!err) err = &local;
  ply_in in = {.path = path, .err = err};
  in.f = fopen(path, "rb");
  if (!in.f) return core_fail(err, NBRDF_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
  ply_elem el[MAXELEM];
  int nel = 0;
  render_mesh *m = render_mesh_new();
  nbrdf_status st =
      m ? read_header(&in, el, &nel) : core_fail(err, NBRDF_ERR_MEMORY, "out of memory");
  static const char *const xs[] = {"x", NULL}, *const ys[] = {"y", NULL}, *const zs[] = {"z", NULL};
  static const char *const us[] = {"s", "u", "texture_u", "texture_s", NULL};
  static const char *const vs[] = {"t", "v", "texture_v", "texture_t", NULL};
  static const char *const nxs[] = {"nx", NULL}, *const nys[] = {"ny", NULL},
                           *const nzs[] = {"nz", NULL};
  static const char *const idx[] = {"vertex_indices", "vertex_index", NULL};
  int has_normals = 0, seen_vertex = 0, seen_face = 0;
  double *vals = NULL;
  in.line++; /* ASCII: the first data line follows end_header */
  for (int e = 0; st == NBRDF_OK && e < nel; e++) {
    ply_elem *x = &el[e];
    int is_v = !strcmp(x->name, "vertex"), is_f = !strcmp(x->name, "face");
    int pi[8] = {-1, -1, -1, -1, -1, -1, -1, -1}, fi = -1;
    if (is_v) {
      seen_vertex = 1;
      pi[0] = find_prop(x, xs), pi[1] = find_prop(x, ys), pi[2] = find_prop(x, zs);
      pi[3] = find_prop(x, us), pi[4] = find_prop(x, vs);
      pi[5] = find_prop(x, nxs), pi[6] = find_prop(x, nys), pi[7] = find_prop(x, nzs);
      if (pi[0] < 0 || pi[1] < 0 || pi[2] < 0) {
        st = core_fail(err, NBRDF_ERR_FORMAT, "%s: element vertex has no x, y, z properties", path);
        break;
      }
      if (pi[3] < 0 || pi[4] < 0) {
        st = core_fail(err, NBRDF_ERR_FORMAT,
                       "%s: element vertex has no texture coordinates (expected properties s, t "
                       "or u, v; the latent texture needs a UV map)",
                       path);
        break;
      }
      has_normals = pi[5] >= 0 && pi[6] >= 0 && pi[7] >= 0;
    }
    if (is_f) {
      seen_face = 1;
      fi = find_prop(x, idx);
      if (fi < 0 || !x->prop[fi].is_list) {
        st = core_fail(err, NBRDF_ERR_FORMAT,
                       "%s: element face has no list property vertex_indices", path);
        break;
      }
    }
    free(vals);
    vals = malloc(sizeof(double) * MAXPROP);
    if (!vals) {
      st = core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory", path);
      break;
    }
    for (long r = 0; st == NBRDF_OK && r < x->count; r++) {
      for (int k = 0; st == NBRDF_OK && k < x->nprop; k++) {
        ply_prop *p = &x->prop[k];
        if (!p->is_list) {
          if (!read_value(&in, p->type, p->is_float, p->is_signed, &vals[k])) st = err->status;
          continue;
        }
        double cnt;
        if (!read_value(&in, p->count_type, 0, p->count_signed, &cnt)) {
          st = err->status;
          break;
        }
        if (cnt < 0 || cnt > 1e6) {
          st = core_fail(err, NBRDF_ERR_FORMAT, "%s:%d: %s %ld has a list of %g items", path,
                         in.line, x->name, r, cnt);
          break;
        }
        uint32_t first = 0, prev = 0;
        for (int j = 0; j < (int)cnt; j++) {
          double v;
          if (!read_value(&in, p->type, p->is_float, p->is_signed, &v)) {
            st = err->status;
            break;
          }
          if (k != fi || !is_f) continue;
          if (!(v >= 0 && v < 4294967295.0)) {
            st = core_fail(err, NBRDF_ERR_FORMAT, "%s:%d: face %ld has vertex index %g", path,
                           in.line, r, v);
            break;
          }
          uint32_t vi = (uint32_t)v;
          if (j == 0) first = vi;
          if (j >= 2 && !render_mesh_add_triangle(m, first, prev, vi)) {
            st = core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory", path);
            break;
          }
          prev = vi;
        }
        if (st == NBRDF_OK && is_f && k == fi && cnt < 3)
          st = core_fail(err, NBRDF_ERR_FORMAT,
                         "%s:%d: face %ld has %g corner(s), expected 3 or more", path, in.line, r,
                         cnt);
      }
      if (st == NBRDF_OK && is_v) {
        float pp[3], uv[2], nn[3];
        for (int k = 0; k < 3; k++)
          pp[k] = (float)vals[pi[k]];
        uv[0] = (float)vals[pi[3]], uv[1] = 1.0f - (float)vals[pi[4]];
        if (has_normals)
          for (int k = 0; k < 3; k++)
            nn[k] = (float)vals[pi[5 + k]];
        if (!render_mesh_add_vertex(m, pp, uv, has_normals ? nn : NULL))
          st = core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory", path);
      }
    }
  }
  free(vals);
  fclose(in.f);
  if (st == NBRDF_OK && (!seen_vertex || !seen_face))
    st = core_fail(err, NBRDF_ERR_FORMAT, "%s: expected elements vertex and face in the header",
                   path);
  return render_mesh_deliver(st, m, has_normals, path, out, err);
}
