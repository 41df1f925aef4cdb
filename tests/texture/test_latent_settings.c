/* The bake settings a texture records, read by whole key (src/texture/latent_settings.c):
 * verify takes the roughness convention from them. */
#include <string.h>

#include "testing.h"
#include "texture/latent_settings.h"

static void test_keys(void) {
  const char *s = "storage=half; compression=zip; tile=64; mipLevels=full; roughness=perceptual; "
                  "range=clamp";
  char v[32];
  CHECK(texture_latent_setting(s, "roughness", v, sizeof v) && !strcmp(v, "perceptual"));
  CHECK(texture_latent_setting(s, "storage", v, sizeof v) && !strcmp(v, "half"));
  CHECK(texture_latent_setting(s, "range", v, sizeof v) && !strcmp(v, "clamp"));
  /* Whole keys only: a prefix or a suffix of a key is not the key. */
  CHECK(!texture_latent_setting(s, "rough", v, sizeof v) && v[0] == '\0');
  CHECK(!texture_latent_setting(s, "ness", v, sizeof v));
  CHECK(!texture_latent_setting("xroughness=perceptual", "roughness", v, sizeof v));
  /* Truncated to the buffer. */
  char small[4];
  CHECK(texture_latent_setting(s, "roughness", small, sizeof small) && !strcmp(small, "per"));
  CHECK(!texture_latent_setting("", "roughness", v, sizeof v));
  CHECK(!texture_latent_setting(NULL, "roughness", v, sizeof v));
  CHECK(texture_latent_setting("roughness=alpha", "roughness", v, sizeof v) && !strcmp(v, "alpha"));
}

int main(void) {
  RUN(test_keys);
  return testing_finish();
}
