/* The common triangle mesh: growth while reading, checks, normals, bounds,
 * and the reader chosen by extension (mesh.h). */
#include "render/mesh.h"

#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"

render_mesh *render_mesh_new(void) { return calloc(1, sizeof(render_mesh)); }

void render_mesh_free(render_mesh *m) {
  if (!m) return;
  free(m->p), free(m->uv), free(m->n), free(m->tri);
  free(m);
}

static int grow(void **buf, int *cap, int need, size_t elem) {
  if (need <= *cap) return 1;
  int c = *cap ? *cap : 1024;
  while (c < need) {
    if (c > (1 << 29)) return 0;
    c *= 2;
  }
  void *nb = realloc(*buf, elem * (size_t)c);
  if (!nb) return 0;
  *buf = nb, *cap = c;
  return 1;
}

int render_mesh_add_vertex(render_mesh *m, const float p[3], const float uv[2], const float *n) {
  int cap = m->cap_v, need = m->vertices + 1;
  if (need > cap) {
    int c1 = cap, c2 = cap, c3 = cap;
    if (!grow((void **)&m->p, &c1, need, 3 * sizeof(float)) ||
        !grow((void **)&m->uv, &c2, need, 2 * sizeof(float)) ||
        !grow((void **)&m->n, &c3, need, 3 * sizeof(float)))
      return 0;
    m->cap_v = c1;
  }
  int v = m->vertices++;
  memcpy(m->p + 3 * v, p, 3 * sizeof(float));
  memcpy(m->uv + 2 * v, uv, 2 * sizeof(float));
  if (n)
    memcpy(m->n + 3 * v, n, 3 * sizeof(float));
  else
    memset(m->n + 3 * v, 0, 3 * sizeof(float));
  return 1;
}

int render_mesh_add_triangle(render_mesh *m, uint32_t a, uint32_t b, uint32_t c) {
  if (!grow((void **)&m->tri, &m->cap_t, m->triangles + 1, 3 * sizeof(uint32_t))) return 0;
  uint32_t *t = m->tri + 3 * (size_t)m->triangles++;
  t[0] = a, t[1] = b, t[2] = c;
  return 1;
}

nbrdf_status render_mesh_finish(render_mesh *m, int has_normals, const char *what,
                                nbrdf_error *err) {
  if (m->triangles == 0)
    return core_fail(err, NBRDF_ERR_FORMAT, "%s: no triangles (expected a surface with faces)",
                     what);
  for (int t = 0; t < m->triangles; t++)
    for (int k = 0; k < 3; k++)
      if (m->tri[3 * (size_t)t + k] >= (uint32_t)m->vertices)
        return core_fail(err, NBRDF_ERR_FORMAT,
                         "%s: triangle %d uses vertex %u, expected 0..%d (%d vertices)", what, t,
                         m->tri[3 * (size_t)t + k], m->vertices - 1, m->vertices);
  for (int v = 0; v < m->vertices; v++)
    for (int k = 0; k < 5; k++) {
      float x = k < 3 ? m->p[3 * (size_t)v + k] : m->uv[2 * (size_t)v + k - 3];
      if (!isfinite(x))
        return core_fail(err, NBRDF_ERR_FORMAT, "%s: vertex %d has a %s that is not finite (%g)",
                         what, v, k < 3 ? "position" : "texture coordinate", (double)x);
    }
  /* Face normals, area weighted, where the file gave none (or a zero one). */
  float *acc = calloc((size_t)m->vertices * 3, sizeof(float));
  if (!acc) return core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory", what);
  for (int t = 0; t < m->triangles; t++) {
    const uint32_t *i = m->tri + 3 * (size_t)t;
    vec3 a = render_mesh_vertex(m, i[0]), b = render_mesh_vertex(m, i[1]),
         c = render_mesh_vertex(m, i[2]);
    vec3 n = v3_cross(v3_sub(b, a), v3_sub(c, a));
    for (int k = 0; k < 3; k++)
      acc[3 * i[k]] += (float)n.x, acc[3 * i[k] + 1] += (float)n.y, acc[3 * i[k] + 2] += (float)n.z;
  }
  for (int v = 0; v < m->vertices; v++) {
    float *n = m->n + 3 * (size_t)v;
    double l =
        has_normals ? sqrt((double)n[0] * n[0] + (double)n[1] * n[1] + (double)n[2] * n[2]) : 0.0;
    if (!(l > 1e-12) || !isfinite(l)) {
      n = acc + 3 * (size_t)v;
      l = sqrt((double)n[0] * n[0] + (double)n[1] * n[1] + (double)n[2] * n[2]);
    }
    float u[3] = {0.0f, 1.0f, 0.0f};
    if (l > 0.0 && isfinite(l))
      u[0] = (float)(n[0] / l), u[1] = (float)(n[1] / l), u[2] = (float)(n[2] / l);
    memcpy(m->n + 3 * (size_t)v, u, sizeof u);
  }
  free(acc);
  for (int k = 0; k < 3; k++)
    m->lo[k] = INFINITY, m->hi[k] = -INFINITY;
  for (int v = 0; v < m->vertices; v++)
    for (int k = 0; k < 3; k++) {
      double x = m->p[3 * (size_t)v + k];
      m->lo[k] = fmin(m->lo[k], x), m->hi[k] = fmax(m->hi[k], x);
    }
  return NBRDF_OK;
}

static int ends_with(const char *s, const char *ext) {
  size_t n = strlen(s), e = strlen(ext);
  if (n < e) return 0;
  for (size_t k = 0; k < e; k++)
    if (tolower((unsigned char)s[n - e + k]) != ext[k]) return 0;
  return 1;
}

nbrdf_status render_mesh_load(const char *path, render_mesh **out, nbrdf_error *err) {
  *out = NULL;
  if (ends_with(path, ".obj")) return render_mesh_read_obj(path, out, err);
  if (ends_with(path, ".ply")) return render_mesh_read_ply(path, out, err);
  if (ends_with(path, ".gltf") || ends_with(path, ".glb"))
    return render_mesh_read_gltf(path, out, err);
  return core_fail(err, NBRDF_ERR_ARGUMENT,
                   "%s: unknown mesh format (expected .gltf, .glb, .ply or .obj)", path);
}

nbrdf_status render_mesh_deliver(nbrdf_status st, render_mesh *m, int has_normals,
                                 const char *what, render_mesh **out, nbrdf_error *err) {
  if (st == NBRDF_OK) st = render_mesh_finish(m, has_normals, what, err);
  if (st != NBRDF_OK) {
    render_mesh_free(m);
    return st;
  }
  *out = m;
  return NBRDF_OK;
}
