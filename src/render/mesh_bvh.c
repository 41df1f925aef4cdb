/* Binned-SAH BVH and ray traversal (mesh_bvh.h). Triangles are copied in
 * leaf order as (v0, e1, e2) so that a leaf's tests read contiguous memory. */
#include "render/mesh_bvh.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"

#define BINS 16
#define LEAF 4

typedef struct bvh_node {
  float lo[3], hi[3];
  int first; /* leaf: first triangle (in order[]); inner: right child (left is this + 1) */
  int count; /* leaf: triangles; 0: inner */
} bvh_node;

struct render_bvh {
  const render_mesh *mesh;
  bvh_node *node;
  int nodes;
  int *order; /* leaf order -> mesh triangle */
  float *tri; /* per leaf-ordered triangle: v0, e1, e2 (9 floats) */
};

typedef struct box {
  float lo[3], hi[3];
} box;

static void box_empty(box *b) {
  for (int k = 0; k < 3; k++)
    b->lo[k] = FLT_MAX, b->hi[k] = -FLT_MAX;
}
static void box_add_box(box *b, const box *o) {
  for (int k = 0; k < 3; k++)
    b->lo[k] = fminf(b->lo[k], o->lo[k]), b->hi[k] = fmaxf(b->hi[k], o->hi[k]);
}
static float box_area(const box *b) {
  float d[3];
  for (int k = 0; k < 3; k++)
    d[k] = b->hi[k] > b->lo[k] ? b->hi[k] - b->lo[k] : 0.0f;
  return 2.0f * (d[0] * d[1] + d[1] * d[2] + d[2] * d[0]);
}

typedef struct build {
  render_bvh *bvh;
  box *tb;    /* per triangle bounds */
  float *cen; /* per triangle centroid x3 */
  int cap;
} build;

static int new_node(build *b) {
  render_bvh *h = b->bvh;
  if (h->nodes == b->cap) {
    int c = b->cap * 2;
    bvh_node *n = realloc(h->node, sizeof(bvh_node) * (size_t)c);
    if (!n) return -1;
    h->node = n, b->cap = c;
  }
  return h->nodes++;
}

/* Builds the subtree of order[first, first + count) at node ni; 0 when out of memory. */
static int build_node(build *b, int ni, int first, int count) {
  render_bvh *h = b->bvh;
  int *ord = h->order;
  box bb, cb;
  box_empty(&bb), box_empty(&cb);
  for (int i = first; i < first + count; i++) {
    box_add_box(&bb, &b->tb[ord[i]]);
    const float *c = b->cen + 3 * (size_t)ord[i];
    box p = {{c[0], c[1], c[2]}, {c[0], c[1], c[2]}};
    box_add_box(&cb, &p);
  }
  memcpy(h->node[ni].lo, bb.lo, sizeof bb.lo), memcpy(h->node[ni].hi, bb.hi, sizeof bb.hi);
  h->node[ni].first = first, h->node[ni].count = count;
  if (count <= LEAF) return 1;
  /* Binned SAH over the centroid bounds, all three axes. */
  float best = FLT_MAX;
  int best_axis = -1, best_split = 0;
  for (int a = 0; a < 3; a++) {
    float ext = cb.hi[a] - cb.lo[a];
    if (!(ext > 0.0f)) continue;
    box bin[BINS];
    int cnt[BINS] = {0};
    for (int k = 0; k < BINS; k++)
      box_empty(&bin[k]);
    for (int i = first; i < first + count; i++) {
      int k = (int)((b->cen[3 * (size_t)ord[i] + a] - cb.lo[a]) / ext * BINS);
      k = k < 0 ? 0 : (k >= BINS ? BINS - 1 : k);
      cnt[k]++, box_add_box(&bin[k], &b->tb[ord[i]]);
    }
    float left_area[BINS];
    int left_n[BINS];
    box acc;
    box_empty(&acc);
    int n = 0;
    for (int k = 0; k < BINS - 1; k++) {
      box_add_box(&acc, &bin[k]), n += cnt[k];
      left_area[k] = box_area(&acc), left_n[k] = n;
    }
    box_empty(&acc), n = 0;
    for (int k = BINS - 1; k > 0; k--) {
      box_add_box(&acc, &bin[k]), n += cnt[k];
      float cost = left_n[k - 1] * left_area[k - 1] + n * box_area(&acc);
      if (left_n[k - 1] && n && cost < best) best = cost, best_axis = a, best_split = k;
    }
  }
  int mid;
  if (best_axis < 0 || best >= count * box_area(&bb)) {
    if (count <= 16 && best_axis >= 0) return 1; /* splitting would not pay */
    /* All centroids together (or no gain): split the list in half. */
    mid = first + count / 2;
  } else {
    int a = best_axis;
    float ext = cb.hi[a] - cb.lo[a];
    int i = first, j = first + count - 1;
    while (i <= j) {
      int k = (int)((b->cen[3 * (size_t)ord[i] + a] - cb.lo[a]) / ext * BINS);
      k = k < 0 ? 0 : (k >= BINS ? BINS - 1 : k);
      if (k < best_split)
        i++;
      else {
        int t = ord[i];
        ord[i] = ord[j], ord[j--] = t;
      }
    }
    mid = i;
    if (mid == first || mid == first + count) mid = first + count / 2;
  }
  int l = new_node(b);
  if (l < 0) return 0;
  if (!build_node(b, l, first, mid - first)) return 0;
  int r = new_node(b);
  if (r < 0) return 0;
  h->node[ni].first = r, h->node[ni].count = 0;
  return build_node(b, r, mid, first + count - mid);
}

nbrdf_status render_bvh_build(const render_mesh *m, render_bvh **out, nbrdf_error *err) {
  *out = NULL;
  int n = m->triangles;
  render_bvh *h = calloc(1, sizeof *h);
  build b = {h, NULL, NULL, 2 * n + 1};
  if (h) {
    h->mesh = m;
    h->order = malloc(sizeof(int) * (size_t)n);
    h->node = malloc(sizeof(bvh_node) * (size_t)b.cap);
    h->tri = malloc(sizeof(float) * 9 * (size_t)n);
    b.tb = malloc(sizeof(box) * (size_t)n), b.cen = malloc(sizeof(float) * 3 * (size_t)n);
  }
  int ok = h && h->order && h->node && h->tri && b.tb && b.cen;
  for (int t = 0; ok && t < n; t++) {
    h->order[t] = t;
    box_empty(&b.tb[t]);
    for (int k = 0; k < 3; k++) {
      const float *p = m->p + 3 * (size_t)m->tri[3 * (size_t)t + k];
      box pb = {{p[0], p[1], p[2]}, {p[0], p[1], p[2]}};
      box_add_box(&b.tb[t], &pb);
    }
    for (int a = 0; a < 3; a++)
      b.cen[3 * (size_t)t + a] = 0.5f * (b.tb[t].lo[a] + b.tb[t].hi[a]);
  }
  if (ok) h->nodes = 1, ok = build_node(&b, 0, 0, n);
  for (int i = 0; ok && i < n; i++) {
    const uint32_t *v = m->tri + 3 * (size_t)h->order[i];
    const float *p0 = m->p + 3 * (size_t)v[0], *p1 = m->p + 3 * (size_t)v[1],
                *p2 = m->p + 3 * (size_t)v[2];
    float *d = h->tri + 9 * (size_t)i;
    for (int k = 0; k < 3; k++)
      d[k] = p0[k], d[3 + k] = p1[k] - p0[k], d[6 + k] = p2[k] - p0[k];
  }
  free(b.tb), free(b.cen);
  if (!ok) {
    render_bvh_free(h);
    return core_fail(err, NBRDF_ERR_MEMORY, "mesh: out of memory building the BVH of %d triangles",
                     n);
  }
  *out = h;
  return NBRDF_OK;
}

void render_bvh_free(render_bvh *h) {
  if (!h) return;
  free(h->node), free(h->order), free(h->tri), free(h);
}

int render_bvh_nodes(const render_bvh *h) { return h->nodes; }

/* Moller-Trumbore on (v0, e1, e2), float; returns t or -1. */
static inline float tri_test(const float *d, const float o[3], const float r[3], float *b1,
                             float *b2) {
  const float *e1 = d + 3, *e2 = d + 6;
  float p[3] = {r[1] * e2[2] - r[2] * e2[1], r[2] * e2[0] - r[0] * e2[2],
                r[0] * e2[1] - r[1] * e2[0]};
  float det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
  if (fabsf(det) < 1e-20f) return -1.0f;
  float inv = 1.0f / det;
  float s[3] = {o[0] - d[0], o[1] - d[1], o[2] - d[2]};
  float u = (s[0] * p[0] + s[1] * p[1] + s[2] * p[2]) * inv;
  if (u < 0.0f || u > 1.0f) return -1.0f;
  float q[3] = {s[1] * e1[2] - s[2] * e1[1], s[2] * e1[0] - s[0] * e1[2],
                s[0] * e1[1] - s[1] * e1[0]};
  float v = (r[0] * q[0] + r[1] * q[1] + r[2] * q[2]) * inv;
  if (v < 0.0f || u + v > 1.0f) return -1.0f;
  *b1 = u, *b2 = v;
  return (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) * inv;
}

static inline int slab(const bvh_node *n, const float o[3], const float inv[3], float tmin,
                       float tmax, float *tnear) {
  for (int a = 0; a < 3; a++) {
    float t0 = (n->lo[a] - o[a]) * inv[a], t1 = (n->hi[a] - o[a]) * inv[a];
    if (t0 > t1) {
      float t = t0;
      t0 = t1, t1 = t;
    }
    tmin = t0 > tmin ? t0 : tmin;
    tmax = t1 < tmax ? t1 : tmax;
    if (tmin > tmax) return 0;
  }
  *tnear = tmin;
  return 1;
}

static int traverse(const render_bvh *h, vec3 org, vec3 dir, double tmin, double tmax, int any,
                    render_ray_hit *hit) {
  float o[3] = {(float)org.x, (float)org.y, (float)org.z};
  float r[3] = {(float)dir.x, (float)dir.y, (float)dir.z}, inv[3];
  for (int a = 0; a < 3; a++)
    inv[a] = 1.0f / (fabsf(r[a]) > 1e-30f ? r[a] : copysignf(1e-30f, r[a]));
  float lo = (float)tmin, best = (float)tmax, tn;
  int stack[128], sp = 0, found = -1;
  float fb1 = 0, fb2 = 0;
  if (!slab(&h->node[0], o, inv, lo, best, &tn)) return 0;
  stack[sp++] = 0;
  while (sp) {
    const bvh_node *n = &h->node[stack[--sp]];
    if (n->count) {
      for (int i = n->first; i < n->first + n->count; i++) {
        float b1 = 0.0f, b2 = 0.0f, t = tri_test(h->tri + 9 * (size_t)i, o, r, &b1, &b2);
        if (t > lo && t < best) {
          best = t, found = i, fb1 = b1, fb2 = b2;
          if (any) return 1;
        }
      }
      continue;
    }
    int a = (int)(n - h->node) + 1, b = n->first;
    float ta, tb;
    int ha = slab(&h->node[a], o, inv, lo, best, &ta),
        hb = slab(&h->node[b], o, inv, lo, best, &tb);
    if (ha && hb) {
      /* nearer child on top */
      if (ta < tb)
        stack[sp++] = b, stack[sp++] = a;
      else
        stack[sp++] = a, stack[sp++] = b;
    } else if (ha) {
      stack[sp++] = a;
    } else if (hb) {
      stack[sp++] = b;
    }
    if (sp > 126) return found >= 0; /* a degenerate tree deeper than the stack: give up */
  }
  if (found < 0) return 0;
  if (hit) hit->tri = h->order[found], hit->t = best, hit->b1 = fb1, hit->b2 = fb2;
  return 1;
}

int render_bvh_intersect(const render_bvh *h, vec3 org, vec3 dir, double tmin, double tmax,
                         render_ray_hit *hit) {
  return traverse(h, org, dir, tmin, tmax, 0, hit);
}

int render_bvh_occluded(const render_bvh *h, vec3 org, vec3 dir, double tmin, double tmax) {
  return traverse(h, org, dir, tmin, tmax, 1, NULL);
}

int render_triangle_intersect(const render_mesh *m, int tri, vec3 org, vec3 dir, double tmin,
                              double tmax, render_ray_hit *hit) {
  const uint32_t *v = m->tri + 3 * (size_t)tri;
  float d[9];
  for (int k = 0; k < 3; k++) {
    d[k] = m->p[3 * v[0] + k];
    d[3 + k] = m->p[3 * v[1] + k] - d[k], d[6 + k] = m->p[3 * v[2] + k] - d[k];
  }
  float o[3] = {(float)org.x, (float)org.y, (float)org.z},
        r[3] = {(float)dir.x, (float)dir.y, (float)dir.z};
  float b1 = 0.0f, b2 = 0.0f, t = tri_test(d, o, r, &b1, &b2);
  if (!(t > (float)tmin && t < (float)tmax)) return 0;
  hit->tri = tri, hit->t = t, hit->b1 = b1, hit->b2 = b2;
  return 1;
}
