/* Pinhole camera, sphere and plane intersection, pixel-cone footprint. */
#include "render/camera.h"

#include <math.h>

void render_camera_setup(render_camera *cam, nbrdf_render_scene scene, int width, int height,
                         double plane_repeat) {
  vec3 at;
  double fov_deg;
  if (scene == NBRDF_SCENE_PLANE) {
    cam->pos = v3(0.0, 1.0, 2.5), at = v3(0.0, 0.0, -2.0), fov_deg = 50.0;
  } else {
    cam->pos = v3(0.0, 0.0, 3.2), at = v3(0.0, 0.0, 0.0), fov_deg = 40.0;
  }
  cam->forward = v3_normalize(v3_sub(at, cam->pos));
  cam->right = v3_normalize(v3_cross(cam->forward, v3(0.0, 1.0, 0.0)));
  cam->up = v3_cross(cam->right, cam->forward);
  cam->tan_half = tan(0.5 * fov_deg * M_PI / 180.0);
  cam->width = width, cam->height = height;
  cam->scene = scene;
  cam->plane_repeat = plane_repeat > 0.0 ? plane_repeat : 1.0;
  cam->mesh = NULL, cam->bvh = NULL, cam->eps = 1e-6;
}

int render_camera_look(render_camera *cam, const double pos[3], const double target[3],
                       const double up[3], double fov_deg) {
  vec3 p = v3(pos[0], pos[1], pos[2]), f = v3_sub(v3(target[0], target[1], target[2]), p);
  vec3 u = v3(up[0], up[1], up[2]);
  if (!(v3_length(f) > 0.0) || !v3_is_finite(f)) return 0;
  f = v3_normalize(f);
  vec3 r = v3_cross(f, u);
  if (!(v3_length(r) > 1e-9 * (v3_length(u) + 1e-300)) || !v3_is_finite(r)) return 0;
  cam->pos = p, cam->forward = f, cam->right = v3_normalize(r);
  cam->up = v3_cross(cam->right, cam->forward);
  if (fov_deg > 0.0) cam->tan_half = tan(0.5 * fov_deg * M_PI / 180.0);
  return 1;
}

void render_camera_set_mesh(render_camera *cam, const render_mesh *mesh, const render_bvh *bvh) {
  cam->mesh = mesh, cam->bvh = bvh;
  vec3 lo = v3(mesh->lo[0], mesh->lo[1], mesh->lo[2]),
       hi = v3(mesh->hi[0], mesh->hi[1], mesh->hi[2]);
  vec3 c = v3_scale(v3_add(lo, hi), 0.5);
  double radius = 0.5 * v3_length(v3_sub(hi, lo));
  if (!(radius > 0.0)) radius = 1.0;
  /* Shadow rays start this far off the surface: beyond the float rounding of the BVH's
   * triangle tests (~1e-7 of the coordinates' magnitude), a tiny fraction of the mesh. */
  double mag = 0.0;
  for (int k = 0; k < 3; k++)
    mag = fmax(mag, fmax(fabs(mesh->lo[k]), fabs(mesh->hi[k])));
  cam->eps = fmax(1e-5 * radius, 1e-5 * mag);
  /* The bounding sphere fills the frame's height with a 10 % margin. */
  double fov = 40.0, dist = 1.1 * radius / sin(0.5 * fov * M_PI / 180.0);
  vec3 dir = v3_normalize(v3(0.0, 0.3, 1.0));
  double pos[3] = {c.x + dir.x * dist, c.y + dir.y * dist, c.z + dir.z * dist};
  double at[3] = {c.x, c.y, c.z}, up[3] = {0.0, 1.0, 0.0};
  render_camera_look(cam, pos, at, up, fov);
}

int render_camera_occluded(const render_camera *cam, const render_hit *hit, vec3 d, double tmax) {
  if (cam->scene != NBRDF_SCENE_MESH) return 0;
  /* Leave the surface on the side d points to. */
  double side = v3_dot(d, hit->ng) >= 0.0 ? 1.0 : -1.0;
  vec3 o = v3_add(hit->p, v3_scale(hit->ng, side * cam->eps));
  return render_bvh_occluded(cam->bvh, o, d, 0.0, tmax);
}

vec3 render_camera_ray(const render_camera *cam, double px, double py) {
  double aspect = (double)cam->width / cam->height;
  double x = (2.0 * px / cam->width - 1.0) * cam->tan_half * aspect;
  double y = (1.0 - 2.0 * py / cam->height) * cam->tan_half;
  return v3_normalize(v3_add(cam->forward, v3_add(v3_scale(cam->right, x), v3_scale(cam->up, y))));
}

int render_camera_hit(const render_camera *cam, vec3 dir, int tex_w, int tex_h, render_hit *h) {
  double t, du, dv;
  /* Pixel cone: a pixel subtends about 2·tan_half / height radians; at
   * distance t its footprint is t times that, stretched by 1/cos on a
   * slanted surface (capped, so grazing hits pick the coarsest level
   * rather than an infinite lod). */
  double spread = 2.0 * cam->tan_half / cam->height;
  if (cam->scene == NBRDF_SCENE_MESH) return render_mesh_hit(cam, cam->pos, dir, tex_w, tex_h, h);
  if (cam->scene == NBRDF_SCENE_PLANE) {
    if (!(dir.y < -1e-9)) return 0;
    t = -cam->pos.y / dir.y;
    h->p = v3_add(cam->pos, v3_scale(dir, t));
    h->n = v3(0.0, 1.0, 0.0);
    h->t = v3(1.0, 0.0, 0.0), h->b = v3(0.0, 0.0, -1.0); /* t × b = n */
    h->ng = h->n;
    h->u = h->p.x / cam->plane_repeat, h->v = h->p.z / cam->plane_repeat;
    double cosv = fmax(-dir.y, 1e-6);
    du = dv = t * spread / cosv / cam->plane_repeat;
  } else {
    /* |pos + t·dir|² = 1 with |dir| = 1. */
    double b = v3_dot(cam->pos, dir), c = v3_dot(cam->pos, cam->pos) - 1.0;
    double disc = b * b - c;
    if (disc < 0.0) return 0;
    t = -b - sqrt(disc);
    if (!(t > 0.0)) return 0;
    h->p = v3_add(cam->pos, v3_scale(dir, t));
    h->n = v3_normalize(h->p);
    double theta = acos(fmin(1.0, fmax(-1.0, h->n.y)));
    double phi = atan2(h->n.x, h->n.z);
    h->u = phi / (2.0 * M_PI) + 0.5, h->v = theta / M_PI;
    double sin_theta = fmax(sin(theta), 1e-4);
    /* Tangent along increasing u (east), bitangent completes a right-handed frame. */
    h->t = v3_normalize(v3(cos(phi), 0.0, -sin(phi)));
    h->b = v3_cross(h->n, h->t);
    h->ng = h->n;
    double cosv = fmax(-v3_dot(dir, h->n), 1e-6);
    double world = t * spread / cosv;
    du = world / (2.0 * M_PI * sin_theta), dv = world / M_PI;
  }
  double texels = fmax(du * tex_w, dv * tex_h);
  h->lod = texels > 1.0 ? log2(texels) : 0.0;
  return 1;
}
