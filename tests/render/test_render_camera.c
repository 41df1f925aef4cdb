/* The renderer's camera: hits, texture coordinates, shading frames and the
 * pixel-cone lod against hand-computed values. */
#include "render/camera.h"
#include "testing.h"

static void test_sphere_centre(void) {
  render_camera cam;
  render_camera_setup(&cam, NBRDF_SCENE_SPHERE, 256, 256, 1.0);
  vec3 d = render_camera_ray(&cam, 128.0, 128.0);
  CHECK_NEAR(d.x, 0.0, 1e-12);
  CHECK_NEAR(d.z, -1.0, 1e-12);
  render_hit h;
  CHECK(render_camera_hit(&cam, d, 1024, 1024, &h));
  /* Hit at (0, 0, 1): distance 2.2, the equator facing +z, u = v = 1/2. */
  CHECK_NEAR(h.p.z, 1.0, 1e-12);
  CHECK_NEAR(h.n.z, 1.0, 1e-12);
  CHECK_NEAR(h.u, 0.5, 1e-12);
  CHECK_NEAR(h.v, 0.5, 1e-12);
  /* Footprint: 2.2 · 2 tan 20° / 256 world units; along v (π per unit of v)
   * that is the larger extent: 1024 · footprint / π texels. */
  double world = 2.2 * 2.0 * tan(20.0 * M_PI / 180.0) / 256.0;
  CHECK_NEAR(h.lod, log2(1024.0 * world / M_PI), 1e-9);
  /* The frame is orthonormal and right-handed with n outward. */
  CHECK_NEAR(v3_dot(h.t, h.b), 0.0, 1e-12);
  CHECK_NEAR(v3_dot(h.t, h.n), 0.0, 1e-12);
  vec3 c = v3_cross(h.t, h.b);
  CHECK_NEAR(v3_dot(c, h.n), 1.0, 1e-12);
  /* A corner ray misses. */
  CHECK(!render_camera_hit(&cam, render_camera_ray(&cam, 0.5, 0.5), 1024, 1024, &h));
}

static void test_plane_lod(void) {
  render_camera cam;
  render_camera_setup(&cam, NBRDF_SCENE_PLANE, 64, 64, 0.5);
  render_hit h;
  double last = -1.0;
  int hits = 0, monotone = 1;
  /* From the bottom row towards the horizon the footprint only grows. */
  for (int row = 63; row >= 0; row--) {
    if (!render_camera_hit(&cam, render_camera_ray(&cam, 32.0, row + 0.5), 256, 256, &h)) break;
    hits++;
    CHECK_NEAR(h.p.y, 0.0, 1e-9);
    if (!(h.lod >= last)) monotone = 0;
    last = h.lod;
    CHECK_NEAR(h.u, h.p.x / 0.5, 1e-12);
    CHECK_NEAR(h.v, h.p.z / 0.5, 1e-12);
  }
  CHECK(monotone);
  CHECK(hits > 10 && hits < 64); /* the horizon is in the frame */
  CHECK(last > 3.0);             /* near the horizon, coarse levels */
}

int main(void) {
  RUN(test_sphere_centre);
  RUN(test_plane_lod);
  return testing_finish();
}
