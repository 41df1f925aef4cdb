// The OpenColorIO side of ocio_shim.h.
#include "texture/ocio_shim.h"

#include "texture/ocio_shim.hpp"

#include <cctype>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>

extern "C" {
#include "core/error.h"
}

namespace OCIO = OCIO_NAMESPACE;

struct texture_colour_xform {
  std::string description;
  OCIO::ConstCPUProcessorRcPtr cpu; /* null for the identity */
};

namespace {

bool equals_nocase(const char *a, const char *b) {
  for (; *a && *b; a++, b++)
    if (std::tolower((unsigned char)*a) != std::tolower((unsigned char)*b)) return false;
  return *a == *b;
}

bool is_identity_name(const char *name) {
  return equals_nocase(name, "linear") || equals_nocase(name, "raw") || equals_nocase(name, "data");
}

OCIO::ConstCPUProcessorRcPtr exact_cpu(const OCIO::ConstProcessorRcPtr &p) {
  // No lossy optimisation: the curve must match IEC 61966-2-1 to float precision.
  return p->getOptimizedCPUProcessor(OCIO::BIT_DEPTH_F32, OCIO::BIT_DEPTH_F32,
                                     OCIO::OPTIMIZATION_LOSSLESS);
}

} // namespace

const char *texture_ocio::config_path(const char *given) {
  const char *config = given ? given : std::getenv("OCIO");
  return config && config[0] ? config : nullptr;
}

OCIO::ConstProcessorRcPtr texture_ocio::srgb_curve(OCIO::TransformDirection direction) {
  OCIO::ExponentWithLinearTransformRcPtr t = OCIO::ExponentWithLinearTransform::Create();
  const double gamma[4] = {2.4, 2.4, 2.4, 1.0};
  const double offset[4] = {0.055, 0.055, 0.055, 0.0};
  t->setGamma(gamma);
  t->setOffset(offset);
  t->setDirection(direction);
  return OCIO::Config::CreateRaw()->getProcessor(t);
}

void texture_ocio::apply_rgb(const OCIO::CPUProcessor &cpu, float *rgb, std::size_t n) {
  // One row per call keeps the width within OCIO's long, whatever n is.
  const std::size_t chunk = 1 << 20;
  for (std::size_t i = 0; i < n; i += chunk) {
    std::size_t m = n - i < chunk ? n - i : chunk;
    OCIO::PackedImageDesc desc(rgb + 3 * i, (long)m, 1, 3);
    cpu.apply(desc);
  }
}

extern "C" nbrdf_status texture_colour_xform_create(const char *colour_space, const char *config_path,
                                                  texture_colour_xform **out, nbrdf_error *err) {
  *out = nullptr;
  if (!colour_space || !colour_space[0])
    return core_fail(err, NBRDF_ERR_ARGUMENT, "colour space name is empty");
  const char *config = texture_ocio::config_path(config_path);
  try {
    std::unique_ptr<texture_colour_xform> x(new texture_colour_xform);
    if (config) {
      OCIO::ConstConfigRcPtr cfg = OCIO::Config::CreateFromFile(config);
      if (cfg->getColorSpace(colour_space)) {
        if (!cfg->hasRole(OCIO::ROLE_SCENE_LINEAR))
          return core_fail(err, NBRDF_ERR_ARGUMENT, "OCIO config %s has no scene_linear role",
                           config);
        x->cpu = exact_cpu(cfg->getProcessor(colour_space, OCIO::ROLE_SCENE_LINEAR));
        x->description = std::string(colour_space) + " (" + config + ") -> scene_linear";
        *out = x.release();
        return NBRDF_OK;
      }
    }
    if (equals_nocase(colour_space, "srgb")) {
      x->cpu = exact_cpu(texture_ocio::srgb_curve(OCIO::TRANSFORM_DIR_FORWARD));
      x->description = "sRGB (built in) -> linear";
    } else if (is_identity_name(colour_space)) {
      x->description = "linear (no conversion)";
    } else if (config) {
      return core_fail(err, NBRDF_ERR_ARGUMENT, "colour space '%s' is not in the OCIO config %s",
                       colour_space, config);
    } else {
      return core_fail(err, NBRDF_ERR_ARGUMENT,
                       "unknown colour space '%s' (built in: srgb, linear, raw; for others "
                       "give an OCIO config or set $OCIO)",
                       colour_space);
    }
    *out = x.release();
    return NBRDF_OK;
  } catch (const std::exception &e) {
    return core_fail(err, NBRDF_ERR_ARGUMENT, "colour space '%s'%s%s: %s", colour_space,
                     config ? " in OCIO config " : "", config ? config : "", e.what());
  }
}

extern "C" int texture_colour_xform_is_identity(const texture_colour_xform *x) { return !x->cpu; }

extern "C" const char *texture_colour_xform_describe(const texture_colour_xform *x) {
  return x->description.c_str();
}

extern "C" nbrdf_status texture_colour_xform_apply_rgb(const texture_colour_xform *x, float *rgb,
                                                       size_t n, nbrdf_error *err) {
  if (!x->cpu || n == 0) return NBRDF_OK;
  try {
    texture_ocio::apply_rgb(*x->cpu, rgb, n);
    return NBRDF_OK;
  } catch (const std::exception &e) {
    return core_fail(err, NBRDF_ERR_INTERNAL, "colour conversion %s: %s", x->description.c_str(),
                     e.what());
  }
}

extern "C" nbrdf_status texture_colour_xform_apply_grey(const texture_colour_xform *x, float *v,
                                                        size_t n, nbrdf_error *err) {
  if (!x->cpu || n == 0) return NBRDF_OK;
  constexpr size_t CHUNK = 4096;
  float rgb[3 * CHUNK];
  for (size_t i = 0; i < n; i += CHUNK) {
    size_t m = n - i < CHUNK ? n - i : CHUNK;
    for (size_t j = 0; j < m; j++)
      rgb[3 * j] = rgb[3 * j + 1] = rgb[3 * j + 2] = v[i + j];
    nbrdf_status st = texture_colour_xform_apply_rgb(x, rgb, m, err);
    if (st != NBRDF_OK) return st;
    for (size_t j = 0; j < m; j++)
      v[i + j] = (rgb[3 * j] + rgb[3 * j + 1] + rgb[3 * j + 2]) / 3.0f;
  }
  return NBRDF_OK;
}

extern "C" void texture_colour_xform_free(texture_colour_xform *x) { delete x; }
