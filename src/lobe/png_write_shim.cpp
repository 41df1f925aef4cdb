// The only C++ in eval/: OpenImageIO's PNG writer behind png_write.h.
#include "lobe/png_write.h"

#include <OpenImageIO/imageio.h>

#include <exception>
#include <string>

extern "C" {
#include "core/error.h"
#include "core/output_file.h"
}

namespace {

nbrdf_status write_png(const char *path, int width, int height, const unsigned char *rgb,
                       nbrdf_error *err) {
  auto out = OIIO::ImageOutput::create("png");
  if (!out)
    return core_fail(err, NBRDF_ERR_UNSUPPORTED, "%s: OpenImageIO has no PNG writer: %s", path,
                     OIIO::geterror().c_str());
  core_output_file f;
  nbrdf_status st = core_output_file_open(&f, path, nullptr, 0, err);
  if (st != NBRDF_OK) return st;
  OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
  // OpenImageIO opens the file by name: "/proc/self/fd/N" reaches the unnamed temporary file.
  bool ok = false;
  std::string why;
  try {
    ok = out->open(core_output_file_name(&f), spec) &&
         out->write_image(OIIO::TypeDesc::UINT8, rgb);
    why = ok ? "" : out->geterror();
    ok = out->close() && ok;
  } catch (...) { // the temporary file must not outlive a throw
    core_output_file_abort(&f);
    throw;
  }
  if (!ok) {
    core_output_file_abort(&f);
    return core_fail(err, NBRDF_ERR_IO, "%s: writing failed: %s", path,
                     why.empty() ? out->geterror().c_str() : why.c_str());
  }
  return core_output_file_commit(&f, err);
}

} // namespace

extern "C" nbrdf_status lobe_png_write_rgb8(const char *path, int width, int height,
                                            const unsigned char *rgb, nbrdf_error *err) {
  if (!path || !rgb || width < 1 || height < 1 || width > 65535 || height > 65535)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "PNG %s: invalid size %d x %d", path ? path : "",
                     width, height);
  try {
    return write_png(path, width, height, rgb, err);
  } catch (const std::exception &e) { // nothing may unwind through the C API
    return core_fail(err, NBRDF_ERR_INTERNAL, "%s: OpenImageIO threw: %s", path, e.what());
  }
}
