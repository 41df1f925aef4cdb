// The OpenColorIO side of render_view.h.
#include "render/render_view.h"

#include <memory>
#include <string>

#include "texture/ocio_shim.hpp"

extern "C" {
#include "core/error.h"
}

namespace OCIO = OCIO_NAMESPACE;

struct render_view {
  std::string description;
  OCIO::ConstCPUProcessorRcPtr cpu;
};

extern "C" nbrdf_status render_view_create(const char *config_path, const char *display,
                                           const char *view, render_view **out, nbrdf_error *err) {
  *out = nullptr;
  const char *config = texture_ocio::config_path(config_path);
  try {
    std::unique_ptr<render_view> v(new render_view);
    if (config) {
      OCIO::ConstConfigRcPtr cfg = OCIO::Config::CreateFromFile(config);
      const char *d = display ? display : cfg->getDefaultDisplay();
      const char *w = view ? view : cfg->getDefaultView(d);
      OCIO::DisplayViewTransformRcPtr t = OCIO::DisplayViewTransform::Create();
      t->setSrc(OCIO::ROLE_SCENE_LINEAR);
      t->setDisplay(d);
      t->setView(w);
      v->cpu = cfg->getProcessor(t)->getDefaultCPUProcessor();
      v->description = std::string(d) + " / " + w + " (" + config + ")";
    } else {
      if (display || view)
        return core_fail(err, NBRDF_ERR_ARGUMENT,
                         "a display or view needs an OCIO config (--ocio or $OCIO); the built-in "
                         "transform is sRGB only");
      // The forward curve decodes sRGB to linear; a display needs the encoding.
      v->cpu = texture_ocio::srgb_curve(OCIO::TRANSFORM_DIR_INVERSE)->getDefaultCPUProcessor();
      v->description = "sRGB (built in)";
    }
    *out = v.release();
    return NBRDF_OK;
  } catch (const std::exception &e) {
    return core_fail(err, NBRDF_ERR_ARGUMENT, "OCIO view transform%s%s: %s",
                     config ? " in config " : "", config ? config : "", e.what());
  }
}

extern "C" const char *render_view_describe(const render_view *v) { return v->description.c_str(); }

extern "C" nbrdf_status render_view_apply(const render_view *v, float *rgb, size_t n,
                                          nbrdf_error *err) {
  try {
    texture_ocio::apply_rgb(*v->cpu, rgb, n);
    return NBRDF_OK;
  } catch (const std::exception &e) {
    return core_fail(err, NBRDF_ERR_INTERNAL, "view transform %s: %s", v->description.c_str(),
                     e.what());
  }
}

extern "C" void render_view_free(render_view *v) { delete v; }
