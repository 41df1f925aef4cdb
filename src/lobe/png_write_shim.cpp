// The only C++ in lobe/: OpenImageIO's PNG writer behind png_write.h.
#include "lobe/png_write.h"

#include <OpenImageIO/imageio.h>

#include <exception>
#include <string>

extern "C" {
#include "core/error.h"
#include "core/output_file.h"
}
#include "texture/oiio_output_proxy.hpp"

namespace {

// Writes the image into `f`'s temporary file; the caller commits or aborts `f`.
nbrdf_status write_png(core_output_file *f, int width, int height, const unsigned char *rgb,
                       nbrdf_error *err) {
  const char *path = f->path;
  // Declared before `out`: an ImageOutput closes (and may write) when destroyed.
  nbrdf_oiio::OutputFileProxy proxy(f);
  auto out = OIIO::ImageOutput::create("png");
  if (!out)
    return core_fail(err, NBRDF_ERR_UNSUPPORTED, "%s: OpenImageIO has no PNG writer: %s", path,
                     OIIO::geterror().c_str());
  OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
  // The bytes go through the proxy: OpenImageIO's PNG writer ignores failed writes.
  bool ok = out->set_ioproxy(&proxy) && out->open(path, spec) &&
            out->write_image(OIIO::TypeDesc::UINT8, rgb);
  std::string why = ok ? "" : out->geterror();
  ok = out->close() && ok;
  if (proxy.status() != NBRDF_OK) { // the write's own failure names the file and errno
    if (err) *err = *proxy.failure();
    return proxy.status();
  }
  if (!ok)
    return core_fail(err, NBRDF_ERR_IO, "%s: writing failed: %s", path,
                     why.empty() ? out->geterror().c_str() : why.c_str());
  return NBRDF_OK;
}

nbrdf_status check_size(const char *path, int width, int height, const unsigned char *rgb,
                        nbrdf_error *err) {
  if (!path || !rgb || width < 1 || height < 1 || width > 65535 || height > 65535)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "PNG %s: invalid size %d x %d", path ? path : "",
                     width, height);
  return NBRDF_OK;
}

} // namespace

extern "C" nbrdf_status lobe_png_write_rgb8_to(core_output_file *f, int width, int height,
                                               const unsigned char *rgb, nbrdf_error *err) {
  nbrdf_status st = check_size(f ? f->path : nullptr, width, height, rgb, err);
  if (st != NBRDF_OK) return st;
  try {
    return write_png(f, width, height, rgb, err);
  } catch (const std::exception &e) { // nothing may unwind through the C API
    return core_fail(err, NBRDF_ERR_INTERNAL, "%s: OpenImageIO threw: %s", f->path, e.what());
  } catch (...) {
    return core_fail(err, NBRDF_ERR_INTERNAL, "%s: OpenImageIO threw", f->path);
  }
}

extern "C" nbrdf_status lobe_png_write_rgb8(const char *path, int width, int height,
                                            const unsigned char *rgb, nbrdf_error *err) {
  nbrdf_status st = check_size(path, width, height, rgb, err);
  if (st != NBRDF_OK) return st;
  core_output_file f;
  st = core_output_file_open(&f, path, nullptr, 0, err);
  if (st != NBRDF_OK) return st;
  st = lobe_png_write_rgb8_to(&f, width, height, rgb, err);
  if (st != NBRDF_OK) {
    core_output_file_abort(&f);
    return st;
  }
  return core_output_file_commit(&f, err);
}
