/* The renderer's pinhole camera and its one object (sphere or plane): ray
 * generation, intersection, texture coordinates, shading frame and the
 * pixel footprint that picks the mip level (a pixel-cone estimate). World
 * space is y-up. */
#ifndef NBRDF_RENDER_CAMERA_H
#define NBRDF_RENDER_CAMERA_H

#include "core/vec3.h"
#include "nbrdf/render.h"

typedef struct render_camera {
  vec3 pos, forward, right, up;
  double tan_half; /* tan of half the vertical field of view */
  int width, height;
  nbrdf_render_scene scene;
  double plane_repeat;
} render_camera;

typedef struct render_hit {
  vec3 p, n, t, b; /* position; shading frame (t, b, n), n the outward normal */
  double u, v;     /* texture coordinates (latent_fetch.h), not wrapped */
  double lod;      /* log2 of the footprint in level-0 texels */
} render_hit;

/* The fixed view of each scene: the sphere fills most of the frame; the
 * plane recedes to the horizon (where mip-mapping matters). */
void render_camera_setup(render_camera *cam, nbrdf_render_scene scene, int width, int height,
                         double plane_repeat);
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
