/* The renderer's pinhole camera and its one object (sphere or plane): ray
 * generation, intersection, texture coordinates, shading frame and the
 * pixel footprint that picks the mip level (a pixel-cone estimate). World
 * space is y-up. */
#ifndef NBRDF_RENDER_CAMERA_H
#define NBRDF_RENDER_CAMERA_H

#include "core/vec3.h"
#include "nbrdf/render.h"
#include "render/mesh_bvh.h"

typedef struct render_camera {
  vec3 pos, forward, right, up;
  double tan_half; /* tan of half the vertical field of view */
  int width, height;
  nbrdf_render_scene scene;
  double plane_repeat;
  /* NBRDF_SCENE_MESH (render_camera_set_mesh): the mesh, its BVH, and the offset of
   * shadow-ray origins (a small fraction of the mesh's size). */
  const render_mesh *mesh;
  const render_bvh *bvh;
  double eps;
} render_camera;

typedef struct render_hit {
  vec3 p, n, t, b; /* position; shading frame (t, b, n), n the outward normal */
  vec3 ng;         /* geometric normal on the camera's side (mesh shadow-ray offsets) */
  double u, v;     /* texture coordinates (latent_fetch.h), not wrapped */
  double lod;      /* log2 of the footprint in level-0 texels */
} render_hit;

/* The fixed view of each scene: the sphere fills most of the frame; the
 * plane recedes to the horizon (where mip-mapping matters). */
void render_camera_setup(render_camera *cam, nbrdf_render_scene scene, int width, int height,
                         double plane_repeat);
/* The mesh scene: sets the mesh and frames its bounding sphere from +z, a little above
 * (40 degrees), unless render_camera_look overrides the view afterwards. */
void render_camera_set_mesh(render_camera *cam, const render_mesh *mesh, const render_bvh *bvh);
/* Places the camera at pos looking at target, up roughly up, vertical field of view
 * fov_deg (0 keeps the current one). 0 when the three do not make a view (pos == target,
 * up along the view direction). */
int render_camera_look(render_camera *cam, const double pos[3], const double target[3],
                       const double up[3], double fov_deg);
/* Whether the ray leaving the hit along world direction d (unit) meets the object again
 * closer than tmax (the mesh's self-shadowing; never for the convex sphere and the plane). */
int render_camera_occluded(const render_camera *cam, const render_hit *hit, vec3 d, double tmax);
/* Mesh hit of the ray from org along dir (mesh_hit.c). */
int render_mesh_hit(const render_camera *cam, vec3 org, vec3 dir, int tex_w, int tex_h,
                    render_hit *hit);
/* Direction (unit) through the image point (px + jx, py + jy), pixel units,
 * rows from the top. */
vec3 render_camera_ray(const render_camera *cam, double px, double py);
/* Intersects the ray from the camera along `dir`; 0 on a miss. tex_w, tex_h:
 * size of the texture's level 0 (for the lod). */
int render_camera_hit(const render_camera *cam, vec3 dir, int tex_w, int tex_h, render_hit *hit);

static inline vec3 render_to_local(const render_hit *h, vec3 d) {
  return v3(v3_dot(d, h->t), v3_dot(d, h->b), v3_dot(d, h->n));
}
static inline vec3 render_to_world(const render_hit *h, vec3 d) {
  return v3_add(v3_add(v3_scale(h->t, d.x), v3_scale(h->b, d.y)), v3_scale(h->n, d.z));
}

#endif
