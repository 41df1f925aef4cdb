/* A bounding volume hierarchy over a render_mesh's triangles (binned SAH,
 * up to 4 triangles a leaf) for the renderer's camera and shadow rays. */
#ifndef NBRDF_RENDER_MESH_BVH_H
#define NBRDF_RENDER_MESH_BVH_H

#include "render/mesh.h"

typedef struct render_bvh render_bvh;

typedef struct render_ray_hit {
  int tri;       /* triangle index in the mesh, -1: none */
  double t;      /* distance along the (unit) direction */
  double b1, b2; /* barycentrics of the triangle's second and third vertex */
} render_ray_hit;

nbrdf_status render_bvh_build(const render_mesh *mesh, render_bvh **out, nbrdf_error *err);
void render_bvh_free(render_bvh *bvh);
/* Nodes in the tree (for tests and messages). */
int render_bvh_nodes(const render_bvh *bvh);

/* Closest hit with t in (tmin, tmax); 0 on a miss. */
int render_bvh_intersect(const render_bvh *bvh, vec3 org, vec3 dir, double tmin, double tmax,
                         render_ray_hit *hit);
/* Whether anything is hit with t in (tmin, tmax) (shadow rays). */
int render_bvh_occluded(const render_bvh *bvh, vec3 org, vec3 dir, double tmin, double tmax);

/* Moller-Trumbore against one triangle of the mesh (also the tests' brute force). */
int render_triangle_intersect(const render_mesh *mesh, int tri, vec3 org, vec3 dir, double tmin,
                              double tmax, render_ray_hit *hit);

#endif
