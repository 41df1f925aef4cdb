/* nbrdf_render on a mesh: a finely tessellated unit sphere carrying the
 * built-in sphere's texture coordinates renders as the built-in sphere does
 * (same seed and samples: the difference is the tessellation), a roof's
 * shadow on a floor (shadow rays), and a mesh without texture coordinates
 * refused. Untrained bundle. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "model/bundle.h"
#include "nbrdf/bake.h"
#include "nbrdf/render.h"
#include "testing.h"

static nbrdf_model *model;

/* Unit UV sphere with u = atan2(x, z) / 2π + 1/2 and v = θ / π from the top (written as
 * OBJ's vt = 1 - v): the built-in sphere's mapping (docs/RENDER.md, "Scene"). */
static void write_sphere(const char *path, int rings, int segs) {
  FILE *f = fopen(path, "w");
  CHECK(f != NULL);
  if (!f) return;
  for (int i = 0; i <= rings; i++)
    for (int j = 0; j <= segs; j++) {
      double th = M_PI * i / rings, ph = 2 * M_PI * j / segs - M_PI;
      double x = sin(th) * sin(ph), y = cos(th), z = sin(th) * cos(ph);
      fprintf(f, "v %.9g %.9g %.9g\nvn %.9g %.9g %.9g\nvt %.9g %.9g\n", x, y, z, x, y, z,
              (double)j / segs, 1.0 - (double)i / rings);
    }
  for (int i = 0; i < rings; i++)
    for (int j = 0; j < segs; j++) {
      int a = i * (segs + 1) + j + 1, b = a + 1, c = a + segs + 1, d = c + 1;
      fprintf(f, "f %d/%d/%d %d/%d/%d %d/%d/%d\nf %d/%d/%d %d/%d/%d %d/%d/%d\n", a, a, a, c, c, c,
              d, d, d, a, a, a, d, d, d, b, b, b);
    }
  fclose(f);
}

static const char *texture = "c.exr";

static float *render(const nbrdf_render_options *o) {
  nbrdf_error err;
  float *rgb = malloc(sizeof(float) * 3 * (size_t)o->width * o->height);
  CHECK_OK(nbrdf_render(model, testing_path(texture), o, rgb, NULL, &err), &err);
  return rgb;
}

/* Both textures: the constant one, and stripes of r0 (a 16 x 8 PGM map), whose placement
 * tests the texture coordinates' orientation (u east, v from the top). */
static void test_sphere_mesh(void) {
  for (int t = 0; t < 2; t++) {
    texture = t ? "m.exr" : "c.exr";
    write_sphere(testing_path("sphere.obj"), 256, 512);
    nbrdf_render_options o = NBRDF_RENDER_OPTIONS_DEFAULT;
    o.width = o.height = 48, o.spp = 4, o.seed = 3, o.light_intensity = 20.0, o.mip = 0;
    float *ref = render(&o);
    o.scene = NBRDF_SCENE_MESH, o.mesh_path = testing_path("sphere.obj");
    /* The built-in sphere's view. */
    o.camera_set = 1;
    o.camera_pos[2] = 3.2, o.camera_up[1] = 1.0, o.fov_deg = 40.0;
    float *mesh = render(&o);
    double diff = 0.0, mean = 0.0;
    int n = 3 * o.width * o.height;
    for (int k = 0; k < n; k++)
      diff += fabs(ref[k] - mesh[k]), mean += ref[k];
    diff /= n, mean /= n;
    printf(
        "%s: sphere mesh against the built-in sphere: mean |difference| %.3g (mean value %.3g)\n",
        texture, diff, mean);
    CHECK_MSG(diff < 1e-3 * mean, "%s: mean |difference| %g, mean %g", texture, diff, mean);
    free(ref), free(mesh);
  }
  texture = "c.exr";
}

static void write_text(const char *name, const char *text) {
  FILE *f = fopen(testing_path(name), "w");
  CHECK(f != NULL);
  if (f) fputs(text, f), fclose(f);
}

static void test_shadow_and_errors(void) {
  write_text("nouv.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  nbrdf_render_options o = NBRDF_RENDER_OPTIONS_DEFAULT;
  o.scene = NBRDF_SCENE_MESH, o.mesh_path = testing_path("nouv.obj");
  nbrdf_error err;
  float *px = malloc(sizeof(float) * 3 * 256 * 256);
  CHECK(nbrdf_render(model, testing_path("c.exr"), &o, px, NULL, &err) == NBRDF_ERR_FORMAT);
  CHECK_MSG(strstr(err.message, "no texture coordinate") != NULL, "%s", err.message);
  free(px);
  /* A floor under a small roof, a point light straight above, a black environment; the
   * camera between floor and roof looks down at the floor's centre, in the roof's shadow:
   * black with the roof, lit without it. */
  static const char floor_obj[] = "v -2 0 -2\nv 2 0 -2\nv 2 0 2\nv -2 0 2\n"
                                  "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 4/4 3/3 2/2 1/1\n";
  char roof[1024];
  snprintf(roof, sizeof roof,
           "%sv -0.5 0.5 -0.5\nv 0.5 0.5 -0.5\nv 0.5 0.5 0.5\nv -0.5 0.5 0.5\n"
           "f 8/4 7/3 6/2 5/1\n",
           floor_obj);
  write_text("floor.obj", floor_obj);
  write_text("roof.obj", roof);
  o.env = NBRDF_ENV_CONSTANT, o.env_value[0] = o.env_value[1] = o.env_value[2] = 0.0f;
  o.light_pos[1] = 5.0, o.light_intensity = 50.0;
  o.width = o.height = 8, o.spp = 2;
  o.camera_set = 1, o.camera_pos[1] = 0.3, o.camera_up[2] = -1.0, o.fov_deg = 40.0;
  o.mesh_path = testing_path("floor.obj");
  float *lit = render(&o);
  o.mesh_path = testing_path("roof.obj");
  float *shadowed = render(&o);
  double a = 0.0, b = 0.0;
  for (int k = 0; k < 3 * 64; k++)
    a += lit[k], b += shadowed[k];
  CHECK_MSG(a > 0.1 * 3 * 64, "floor without the roof: mean %g", a / (3 * 64));
  CHECK_MSG(b == 0.0, "floor in the roof's shadow: mean %g, expected 0", b / (3 * 64));
  free(lit), free(shadowed);
}

int main(void) {
  nbrdf_error e;
  CHECK_OK(model_bundle_init_random(testing_path("bundle"), "mesh-test", 1, "small", &e), &e);
  CHECK_OK(nbrdf_model_load(testing_path("bundle"), &model, &e), &e);
  if (!model) return testing_finish();
  nbrdf_bake_inputs in = NBRDF_BAKE_INPUTS_DEFAULT;
  const float v[6] = {0.1f, 1.5f, 0.3f, 0.9f, 0.8f, 1.0f};
  for (int k = 0; k < NBRDF_BAKE_PARAM_COUNT; k++)
    nbrdf_bake_param_constant(&in.param[k], v[k]);
  CHECK_OK(nbrdf_bake(model, &in, NULL, testing_path("c.exr"), NULL, &e), &e);
  FILE *f = fopen(testing_path("r0.pgm"), "wb");
  if (f) {
    fprintf(f, "P5\n16 8\n255\n");
    for (int y = 0; y < 8; y++)
      for (int x = 0; x < 16; x++)
        fputc(y < 2 ? 250 : (x < 4 ? 40 : 140 + 6 * x), f);
    fclose(f);
  }
  in.param[NBRDF_BAKE_R0].path = testing_path("r0.pgm");
  CHECK_OK(nbrdf_bake(model, &in, NULL, testing_path("m.exr"), NULL, &e), &e);
  RUN(test_sphere_mesh);
  RUN(test_shadow_and_errors);
  nbrdf_model_destroy(model);
  return testing_finish();
}
