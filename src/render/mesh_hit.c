/* A camera ray against the mesh: the BVH's closest triangle, then the
 * shading point as the sphere and plane give it (camera.h): interpolated
 * texture coordinates and normal, a tangent along increasing u (from the
 * triangle's UV derivatives), and the pixel-cone lod. Two-sided: a back face
 * is shaded from the side the camera sees. */
#include <math.h>

#include "render/camera.h"

int render_mesh_hit(const render_camera *cam, vec3 org, vec3 dir, int tex_w, int tex_h,
                    render_hit *h) {
  const render_mesh *m = cam->mesh;
  render_ray_hit rh;
  if (!render_bvh_intersect(cam->bvh, org, dir, 0.0, INFINITY, &rh)) return 0;
  const uint32_t *v = m->tri + 3 * (size_t)rh.tri;
  double w0 = 1.0 - rh.b1 - rh.b2, w[3] = {w0, rh.b1, rh.b2};
  vec3 p0 = render_mesh_vertex(m, v[0]), p1 = render_mesh_vertex(m, v[1]),
       p2 = render_mesh_vertex(m, v[2]);
  vec3 e1 = v3_sub(p1, p0), e2 = v3_sub(p2, p0);
  vec3 ng = v3_cross(e1, e2);
  double area2 = v3_length(ng);
  if (!(area2 > 0.0)) return 0;
  ng = v3_scale(ng, 1.0 / area2);
  h->p = v3_add(org, v3_scale(dir, rh.t));
  vec3 n = v3(0, 0, 0);
  double uv[2] = {0, 0};
  for (int k = 0; k < 3; k++) {
    const float *vn = m->n + 3 * (size_t)v[k], *vt = m->uv + 2 * (size_t)v[k];
    n = v3_add(n, v3_scale(v3(vn[0], vn[1], vn[2]), w[k]));
    uv[0] += w[k] * vt[0], uv[1] += w[k] * vt[1];
  }
  double nl = v3_length(n);
  n = nl > 1e-12 ? v3_scale(n, 1.0 / nl) : ng;
  /* Seen from behind: both normals turn to the camera's side. */
  if (v3_dot(ng, dir) > 0.0) ng = v3_neg(ng);
  if (v3_dot(n, ng) < 0.0) n = v3_neg(n);
  h->ng = ng, h->n = n;
  h->u = uv[0], h->v = uv[1];
  /* dp/du from the UV derivatives (the tangent of normal mapping); any frame where they
   * are degenerate (the BRDF is isotropic: the frame's azimuth does not matter). */
  const float *t0 = m->uv + 2 * (size_t)v[0], *t1 = m->uv + 2 * (size_t)v[1],
              *t2 = m->uv + 2 * (size_t)v[2];
  double du1 = t1[0] - t0[0], dv1 = t1[1] - t0[1], du2 = t2[0] - t0[0], dv2 = t2[1] - t0[1];
  double det = du1 * dv2 - du2 * dv1;
  vec3 t = v3(0, 0, 0);
  if (fabs(det) > 1e-20) t = v3_scale(v3_sub(v3_scale(e1, dv2), v3_scale(e2, dv1)), 1.0 / det);
  t = v3_sub(t, v3_scale(n, v3_dot(t, n)));
  double tl = v3_length(t);
  if (tl > 1e-12 && isfinite(tl)) {
    h->t = v3_scale(t, 1.0 / tl);
    h->b = v3_cross(h->n, h->t);
  } else {
    v3_basis(n, &h->t, &h->b);
  }
  /* Pixel cone as for the sphere, converted to texels by the triangle's UV-to-world scale. */
  double spread = 2.0 * cam->tan_half / cam->height;
  double cosv = fmax(fabs(v3_dot(dir, ng)), 1e-6);
  double world = rh.t * spread / cosv;
  double uv_scale = sqrt(fabs(det) / area2); /* texture units per world unit */
  double texels = world * uv_scale * (tex_w > tex_h ? tex_w : tex_h);
  h->lod = texels > 1.0 && isfinite(texels) ? log2(texels) : 0.0;
  return 1;
}
