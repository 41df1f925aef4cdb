/* Wavefront OBJ: v, vt, vn and f (v, v/vt, v//vn, v/vt/vn, negative indices
 * relative to the end); polygons fan-triangulated; other statements (o, g,
 * s, usemtl, mtllib, l, p) ignored. Each distinct v/vt/vn corner becomes one
 * vertex. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "render/mesh.h"

typedef struct fbuf {
  float *v;
  int n, cap, dim;
} fbuf;

static int fbuf_push(fbuf *b, const float *x) {
  if (b->n == b->cap) {
    int c = b->cap ? 2 * b->cap : 1024;
    float *nv = realloc(b->v, sizeof(float) * (size_t)c * b->dim);
    if (!nv) return 0;
    b->v = nv, b->cap = c;
  }
  memcpy(b->v + (size_t)b->n++ * b->dim, x, sizeof(float) * b->dim);
  return 1;
}

/* Corner (v, vt, vn) -> mesh vertex, open addressing. */
typedef struct corner_map {
  int64_t *key; /* packed indices + 1, 0 empty */
  int *val;
  size_t cap, n;
} corner_map;

static uint64_t mix(uint64_t x) {
  x ^= x >> 33, x *= 0xff51afd7ed558ccdULL, x ^= x >> 33;
  return x;
}

static int map_grow(corner_map *m) {
  size_t cap = m->cap ? 2 * m->cap : 4096;
  int64_t *k = calloc(cap * 3, sizeof(int64_t));
  int *v = malloc(sizeof(int) * cap);
  if (!k || !v) return free(k), free(v), 0;
  for (size_t i = 0; i < m->cap; i++)
    if (m->key[3 * i]) {
      size_t h = mix((uint64_t)m->key[3 * i] * 31 + (uint64_t)m->key[3 * i + 1] * 17 +
                     (uint64_t)m->key[3 * i + 2]) &
                 (cap - 1);
      while (k[3 * h])
        h = (h + 1) & (cap - 1);
      memcpy(k + 3 * h, m->key + 3 * i, 3 * sizeof(int64_t)), v[h] = m->val[i];
    }
  free(m->key), free(m->val);
  m->key = k, m->val = v, m->cap = cap;
  return 1;
}

/* Returns the slot of (a, b, c) (each index + 1, 0 none); *found whether it was there. */
static int map_find(corner_map *m, const int64_t k3[3], size_t *slot) {
  if (2 * (m->n + 1) > m->cap && !map_grow(m)) return -1;
  size_t h = mix((uint64_t)k3[0] * 31 + (uint64_t)k3[1] * 17 + (uint64_t)k3[2]) & (m->cap - 1);
  while (m->key[3 * h]) {
    if (!memcmp(m->key + 3 * h, k3, 3 * sizeof(int64_t))) return *slot = h, 1;
    h = (h + 1) & (m->cap - 1);
  }
  *slot = h;
  return 0;
}

typedef struct obj_state {
  const char *path;
  int line;
  fbuf v, vt, vn;
  corner_map map;
  render_mesh *m;
  int any_vn;
  nbrdf_error *err;
} obj_state;

/* Resolves one index as written (1-based, or negative from the end) against n items. */
static int resolve(obj_state *s, long i, int n, const char *kind, const char *tok, int *out) {
  long r = i > 0 ? i - 1 : n + i;
  if (i == 0 || r < 0 || r >= n) {
    core_fail(s->err, NBRDF_ERR_FORMAT,
              "%s:%d: face corner '%s' refers to %s %ld, expected 1..%d or -1..-%d", s->path,
              s->line, tok, kind, i, n, n);
    return 0;
  }
  *out = (int)r;
  return 1;
}

static int corner(obj_state *s, char *tok, uint32_t *vertex) {
  char *end, *p = tok;
  long iv = strtol(p, &end, 10), it = 0, in = 0;
  int ok = end != p;
  if (ok && *end == '/') {
    p = end + 1;
    if (*p != '/') {
      it = strtol(p, &end, 10);
      ok = end != p;
    } else {
      end = p;
    }
    if (ok && *end == '/') {
      p = end + 1;
      in = strtol(p, &end, 10);
      ok = end != p;
    }
  }
  if (!ok || *end) {
    core_fail(s->err, NBRDF_ERR_FORMAT,
              "%s:%d: face corner '%s' is not v, v/vt, v//vn or v/vt/vn (1-based integers)",
              s->path, s->line, tok);
    return 0;
  }
  if (it == 0) {
    core_fail(s->err, NBRDF_ERR_FORMAT,
              "%s:%d: face corner '%s' has no texture coordinate (expected v/vt or v/vt/vn; "
              "the latent texture needs a UV map)",
              s->path, s->line, tok);
    return 0;
  }
  int a, b, c = -1;
  if (!resolve(s, iv, s->v.n, "vertex", tok, &a) || !resolve(s, it, s->vt.n, "vt", tok, &b))
    return 0;
  if (in && !resolve(s, in, s->vn.n, "vn", tok, &c)) return 0;
  int64_t key[3] = {a + 1, b + 1, c + 1};
  size_t slot;
  int f = map_find(&s->map, key, &slot);
  if (f < 0) return core_fail(s->err, NBRDF_ERR_MEMORY, "%s: out of memory", s->path), 0;
  if (f) return *vertex = (uint32_t)s->map.val[slot], 1;
  const float *t = s->vt.v + 2 * (size_t)b;
  float uv[2] = {t[0], 1.0f - t[1]};
  if (!render_mesh_add_vertex(s->m, s->v.v + 3 * (size_t)a, uv,
                              c >= 0 ? s->vn.v + 3 * (size_t)c : NULL))
    return core_fail(s->err, NBRDF_ERR_MEMORY, "%s: out of memory", s->path), 0;
  if (c >= 0) s->any_vn = 1;
  memcpy(s->map.key + 3 * slot, key, sizeof key);
  s->map.val[slot] = s->m->vertices - 1, s->map.n++;
  *vertex = (uint32_t)(s->m->vertices - 1);
  return 1;
}

/* Reads `want` floats (vt: 2 or 3 given, the third ignored). */
static int floats(obj_state *s, char *rest, float *x, int want, int allow_extra, const char *what) {
  char *p = rest, *end;
  int k = 0;
  for (;; k++) {
    while (*p == ' ' || *p == '\t')
      p++;
    if (!*p) break;
    errno = 0;
    double d = strtod(p, &end);
    if (end == p) break;
    if (k < want) x[k] = (float)d;
    p = end;
  }
  while (*p == ' ' || *p == '\t')
    p++;
  if (k < want || (*p && *p != '#') || (k > want + allow_extra)) {
    core_fail(s->err, NBRDF_ERR_FORMAT, "%s:%d: '%s' expects %d number(s)%s", s->path, s->line,
              what, want, allow_extra ? " (one more allowed)" : "");
    return 0;
  }
  return 1;
}

nbrdf_status render_mesh_read_obj(const char *path, render_mesh **out, nbrdf_error *err) {
  *out = NULL;
  nbrdf_error local;
  if (!err) err = &local;
  FILE *f = fopen(path, "r");
  if (!f) return core_fail(err, NBRDF_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
  obj_state s = {.path = path, .err = err};
  s.v.dim = 3, s.vt.dim = 2, s.vn.dim = 3;
  s.m = render_mesh_new();
  nbrdf_status st = s.m ? NBRDF_OK : core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory", path);
  char line[65536];
  while (st == NBRDF_OK && fgets(line, sizeof line, f)) {
    s.line++;
    size_t n = strlen(line);
    if (n == sizeof line - 1 && line[n - 1] != '\n') {
      st = core_fail(err, NBRDF_ERR_FORMAT, "%s:%d: line longer than %zu bytes", path, s.line,
                     sizeof line - 2);
      break;
    }
    while (n && (line[n - 1] == '\n' || line[n - 1] == '\r'))
      line[--n] = '\0';
    char *p = line;
    while (*p == ' ' || *p == '\t')
      p++;
    float x[3] = {0, 0, 0};
    int ok = 1;
    if (!strncmp(p, "v ", 2) || !strncmp(p, "v\t", 2)) {
      ok = floats(&s, p + 2, x, 3, 3, "v") && fbuf_push(&s.v, x);
    } else if (!strncmp(p, "vt ", 3) || !strncmp(p, "vt\t", 3)) {
      ok = floats(&s, p + 3, x, 2, 1, "vt") && fbuf_push(&s.vt, x);
    } else if (!strncmp(p, "vn ", 3) || !strncmp(p, "vn\t", 3)) {
      ok = floats(&s, p + 3, x, 3, 0, "vn") && fbuf_push(&s.vn, x);
    } else if (!strncmp(p, "f ", 2) || !strncmp(p, "f\t", 2)) {
      uint32_t first = 0, prev = 0;
      int k = 0;
      for (char *tok = strtok(p + 2, " \t"); ok && tok && *tok != '#';
           tok = strtok(NULL, " \t"), k++) {
        uint32_t v;
        ok = corner(&s, tok, &v);
        if (!ok) break;
        if (k == 0) first = v;
        if (k >= 2 && !render_mesh_add_triangle(s.m, first, prev, v))
          ok = 0, core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory", path);
        prev = v;
      }
      if (ok && k < 3)
        ok = 0, core_fail(err, NBRDF_ERR_FORMAT,
                          "%s:%d: a face has %d corner(s), expected 3 or more", path, s.line, k);
    }
    if (!ok) st = err->status != NBRDF_OK ? err->status : NBRDF_ERR_FORMAT;
  }
  if (st == NBRDF_OK && ferror(f))
    st = core_fail(err, NBRDF_ERR_IO, "%s: read error: %s", path, strerror(errno));
  fclose(f);
  if (st == NBRDF_OK && s.m->triangles == 0)
    st = core_fail(err, NBRDF_ERR_FORMAT, "%s: no faces ('f' lines with v/vt corners expected)",
                   path);
  free(s.v.v), free(s.vt.v), free(s.vn.v), free(s.map.key), free(s.map.val);
  return render_mesh_deliver(st, s.m, s.any_vn, path, out, err);
}
