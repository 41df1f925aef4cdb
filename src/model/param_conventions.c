#include "model/param_conventions.h"

#include <string.h>

double model_roughness_alpha(nbrdf_roughness convention, double r) {
  return convention == NBRDF_ROUGHNESS_PERCEPTUAL ? r * r : r;
}

const char *model_roughness_name(nbrdf_roughness convention) {
  return convention == NBRDF_ROUGHNESS_PERCEPTUAL ? "perceptual" : "alpha";
}

int model_roughness_parse(const char *name) {
  if (!strcmp(name, "alpha")) return NBRDF_ROUGHNESS_ALPHA;
  if (!strcmp(name, "perceptual")) return NBRDF_ROUGHNESS_PERCEPTUAL;
  return -1;
}
