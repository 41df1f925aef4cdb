/* The renderer's triangle mesh: positions, texture coordinates and
 * (optional) vertex normals, read from glTF 2.0, PLY or OBJ (one file per
 * format: mesh_gltf.cpp, mesh_ply.c, mesh_obj.c). Indexed triangles,
 * polygons fan-triangulated by the readers. World space y up. */
#ifndef NBRDF_RENDER_MESH_H
#define NBRDF_RENDER_MESH_H

#include <stddef.h>
#include <stdint.h>

#include "core/vec3.h"
#include "nbrdf/status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct render_mesh {
  int vertices, triangles;
  float *p; /* vertices x 3 */
  /* vertices x 2: the texture's (u, v) as latent_fetch.h takes them, v from the image's top
   * row. OBJ and PLY store v from the bottom (Blender's convention) and are flipped to 1 - v
   * by their readers; glTF's v already runs from the top. */
  float *uv;
  float *n;            /* vertices x 3, unit; computed from the faces when the file has none */
  uint32_t *tri;       /* triangles x 3 vertex indices */
  double lo[3], hi[3]; /* bounds */
  int cap_v, cap_t;    /* allocated vertices / triangles (while reading) */
} render_mesh;

/* Reads `path` by its extension (.gltf, .glb, .ply, .obj; case-insensitive).
 * Errors name the file and the line (OBJ, ASCII PLY), byte offset (binary
 * PLY) or glTF item, and what was expected. A mesh without texture
 * coordinates is refused. */
nbrdf_status render_mesh_load(const char *path, render_mesh **out, nbrdf_error *err);
void render_mesh_free(render_mesh *m);

/* For the readers. */
render_mesh *render_mesh_new(void);
/* Appends a vertex / triangle; 0 when out of memory. n may be NULL. */
int render_mesh_add_vertex(render_mesh *m, const float p[3], const float uv[2], const float *n);
int render_mesh_add_triangle(render_mesh *m, uint32_t a, uint32_t b, uint32_t c);
/* Checks indices and values, fills missing or degenerate normals from the faces (area
 * weighted) and the bounds. has_normals: whether the reader stored normals. `what` names
 * the file in messages. */
nbrdf_status render_mesh_finish(render_mesh *m, int has_normals, const char *what,
                                nbrdf_error *err);

/* A reader's last step: when st is NBRDF_OK, finishes m and hands it to *out; otherwise (or
 * when finishing fails) frees m. Returns the status. */
nbrdf_status render_mesh_deliver(nbrdf_status st, render_mesh *m, int has_normals,
                                 const char *what, render_mesh **out, nbrdf_error *err);

nbrdf_status render_mesh_read_obj(const char *path, render_mesh **out, nbrdf_error *err);
nbrdf_status render_mesh_read_ply(const char *path, render_mesh **out, nbrdf_error *err);
nbrdf_status render_mesh_read_gltf(const char *path, render_mesh **out, nbrdf_error *err);

static inline vec3 render_mesh_vertex(const render_mesh *m, uint32_t i) {
  return v3(m->p[3 * i], m->p[3 * i + 1], m->p[3 * i + 2]);
}

#ifdef __cplusplus
}
#endif
#endif
