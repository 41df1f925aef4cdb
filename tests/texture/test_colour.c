/* Colour conversion through OpenColorIO 2.1: the built-in sRGB curve, the
 * identity names, and user configs from a path or $OCIO. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "testing.h"
#include "texture/ocio_shim.h"

static double srgb_to_linear(double v) {
  return v <= 0.04045 ? v / 12.92 : pow((v + 0.055) / 1.055, 2.4);
}

static float convert(const texture_colour_xform *x, float v) {
  nbrdf_error e;
  float rgb[3] = {v, v, v};
  if (texture_colour_xform_apply_rgb(x, rgb, 1, &e) != NBRDF_OK) return NAN;
  return rgb[1];
}

static void test_builtin_srgb(void) {
  nbrdf_error e, *err = &e;
  texture_colour_xform *x = NULL;
  unsetenv("OCIO");
  CHECK_OK(texture_colour_xform_create("sRGB", NULL, &x, err), err);
  if (!x) return;
  CHECK(!texture_colour_xform_is_identity(x));
  CHECK(strstr(texture_colour_xform_describe(x), "built in") != NULL);
  CHECK_NEAR(convert(x, 0.5f), 0.2140, 5e-5);
  static const float points[] = {0.0f, 0.01f, 0.04045f, 0.1f, 0.25f, 0.5f, 0.75f, 0.9f, 1.0f};
  for (size_t i = 0; i < sizeof points / sizeof points[0]; i++) {
    double want = srgb_to_linear(points[i]);
    CHECK_NEAR(convert(x, points[i]), want, 1e-6);
    if (points[i] > 0.05f) CHECK_REL(convert(x, points[i]), want, 1e-6, 0);
  }
  /* Each channel independently, many pixels at once. */
  float rgb[3 * 1000];
  for (int i = 0; i < 3000; i++)
    rgb[i] = (float)(i % 1000) / 999.0f;
  CHECK_OK(texture_colour_xform_apply_rgb(x, rgb, 1000, err), err);
  double worst = 0;
  for (int i = 0; i < 3000; i++)
    worst = fmax(worst, fabs(rgb[i] - srgb_to_linear((i % 1000) / 999.0)));
  CHECK(worst < 1e-6);
  float grey[5] = {0.0f, 0.2f, 0.5f, 0.8f, 1.0f};
  CHECK_OK(texture_colour_xform_apply_grey(x, grey, 5, err), err);
  CHECK_NEAR(grey[2], 0.214041, 1e-5);
  CHECK_NEAR(grey[4], 1.0, 1e-6);
  texture_colour_xform_free(x);
}

static void test_identity_names(void) {
  nbrdf_error e, *err = &e;
  static const char *names[] = {"linear", "raw", "Raw", "data"};
  for (int i = 0; i < 4; i++) {
    texture_colour_xform *x = NULL;
    CHECK_OK(texture_colour_xform_create(names[i], NULL, &x, err), err);
    if (!x) continue;
    CHECK(texture_colour_xform_is_identity(x));
    CHECK(convert(x, 0.5f) == 0.5f);
    texture_colour_xform_free(x);
  }
  texture_colour_xform *x = NULL;
  CHECK_FAILS(texture_colour_xform_create("ACEScg", NULL, &x, err), NBRDF_ERR_ARGUMENT, err,
              "unknown colour space 'ACEScg'");
  CHECK_FAILS(texture_colour_xform_create("", NULL, &x, err), NBRDF_ERR_ARGUMENT, err, "empty");
  CHECK(x == NULL);
}

static void write_config(const char *path) {
  FILE *f = fopen(path, "w");
  if (!f) return;
  fputs("ocio_profile_version: 2\n\n"
        "roles:\n  default: lin\n  scene_linear: lin\n\n"
        "displays:\n  sRGB:\n    - !<View> {name: Raw, colorspace: lin}\n\n"
        "colorspaces:\n"
        "  - !<ColorSpace>\n    name: lin\n\n"
        "  - !<ColorSpace>\n    name: gamma22\n"
        "    to_scene_reference: !<ExponentTransform> {value: 2.2}\n",
        f);
  fclose(f);
}

static void test_user_config(void) {
  nbrdf_error e, *err = &e;
  char path[512];
  snprintf(path, sizeof path, "%s/studio.ocio", testing_tmpdir());
  write_config(path);
  texture_colour_xform *x = NULL;
  CHECK_OK(texture_colour_xform_create("gamma22", path, &x, err), err);
  if (x) {
    CHECK_NEAR(convert(x, 0.5f), pow(0.5, 2.2), 1e-6);
    CHECK(strstr(texture_colour_xform_describe(x), "studio.ocio") != NULL);
    texture_colour_xform_free(x);
    x = NULL;
  }
  /* A name the config lacks falls back to the built-ins, else fails. */
  CHECK_OK(texture_colour_xform_create("srgb", path, &x, err), err);
  if (x) CHECK_NEAR(convert(x, 0.5f), 0.214041, 1e-5);
  texture_colour_xform_free(x);
  x = NULL;
  CHECK_FAILS(texture_colour_xform_create("ACEScg", path, &x, err), NBRDF_ERR_ARGUMENT, err,
              "not in the OCIO config");
  /* $OCIO when no path is given. */
  setenv("OCIO", path, 1);
  CHECK_OK(texture_colour_xform_create("gamma22", NULL, &x, err), err);
  if (x) CHECK_NEAR(convert(x, 0.25f), pow(0.25, 2.2), 1e-6);
  texture_colour_xform_free(x);
  x = NULL;
  unsetenv("OCIO");
  char bad[600];
  snprintf(bad, sizeof bad, "%s/missing.ocio", testing_tmpdir());
  CHECK_FAILS(texture_colour_xform_create("gamma22", bad, &x, err), NBRDF_ERR_ARGUMENT, err,
              "missing.ocio");
  CHECK(x == NULL);
}

int main(void) {
  RUN(test_builtin_srgb);
  RUN(test_identity_names);
  RUN(test_user_config);
  return testing_finish();
}
