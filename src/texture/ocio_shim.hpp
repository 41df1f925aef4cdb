// The OpenColorIO pieces the colour shims share: texture's input conversion (ocio_shim.cpp,
// where they are defined) and the renderer's display transform (render/render_view.cpp).
// Only included by those C++ shims; each keeps its own processor and its own error messages.
#ifndef NBRDF_TEXTURE_OCIO_SHIM_HPP
#define NBRDF_TEXTURE_OCIO_SHIM_HPP

#include <OpenColorIO/OpenColorIO.h>

#include <cstddef>

namespace texture_ocio {

namespace OCIO = OCIO_NAMESPACE;

// The config to use: `given`, else $OCIO; nullptr when neither names one (an empty name
// counts as none).
const char *config_path(const char *given);

// The sRGB curve of IEC 61966-2-1 (v <= 0.04045 ? v / 12.92 : ((v + 0.055) / 1.055)^2.4) as
// OCIO's ExponentWithLinearTransform, gamma 2.4, offset 0.055 (OCIO 2.1 has no built-in
// configs): TRANSFORM_DIR_FORWARD decodes to linear, TRANSFORM_DIR_INVERSE encodes for a
// display.
OCIO::ConstProcessorRcPtr srgb_curve(OCIO::TransformDirection direction);

// Applies `cpu` to n RGB triples in place, in rows narrow enough for OCIO's long width,
// whatever n is. Throws what OCIO throws; safe from several threads at once.
void apply_rgb(const OCIO::CPUProcessor &cpu, float *rgb, std::size_t n);

} // namespace texture_ocio

#endif
