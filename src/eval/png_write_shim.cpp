// The only C++ in eval/: OpenImageIO's PNG writer behind png_write.h.
#include "eval/png_write.h"

#include <OpenImageIO/imageio.h>

#include <cstdio>
#include <exception>
#include <string>
#include <unistd.h>

extern "C" {
#include "core/error.h"
}

namespace {

nbrdf_status write_png(const char *path, int width, int height, const unsigned char *rgb,
                       nbrdf_error *err) {
  // The temporary name keeps the target's folder (rename must not cross file systems)
  // and the process id (two writers of the same path do not clobber each other).
  const std::string tmp = std::string(path) + "." + std::to_string(getpid()) + ".tmp";
  auto out = OIIO::ImageOutput::create("png");
  if (!out)
    return nbrdf_fail(err, NBRDF_ERR_UNSUPPORTED, "%s: OpenImageIO has no PNG writer: %s", path,
                      OIIO::geterror().c_str());
  OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
  if (!out->open(tmp, spec))
    return nbrdf_fail(err, NBRDF_ERR_IO, "%s: cannot create: %s", tmp.c_str(),
                      out->geterror().c_str());
  bool ok = out->write_image(OIIO::TypeDesc::UINT8, rgb);
  std::string why = ok ? "" : out->geterror();
  ok = out->close() && ok;
  if (ok && std::rename(tmp.c_str(), path) != 0) {
    why = "cannot rename " + tmp;
    ok = false;
  }
  if (!ok) {
    std::remove(tmp.c_str());
    return nbrdf_fail(err, NBRDF_ERR_IO, "%s: writing failed: %s", path,
                      why.empty() ? out->geterror().c_str() : why.c_str());
  }
  return NBRDF_OK;
}

} // namespace

extern "C" nbrdf_status nbrdf_png_write_rgb8(const char *path, int width, int height,
                                             const unsigned char *rgb, nbrdf_error *err) {
  if (!path || !rgb || width < 1 || height < 1 || width > 65535 || height > 65535)
    return nbrdf_fail(err, NBRDF_ERR_ARGUMENT, "PNG %s: invalid size %d x %d", path ? path : "",
                      width, height);
  try {
    return write_png(path, width, height, rgb, err);
  } catch (const std::exception &e) { // nothing may unwind through the C API
    return nbrdf_fail(err, NBRDF_ERR_INTERNAL, "%s: OpenImageIO threw: %s", path, e.what());
  }
}
