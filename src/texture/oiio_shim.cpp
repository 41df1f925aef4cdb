// The OpenImageIO side of oiio_shim.h. Every entry point catches exceptions
// and turns OIIO's error strings into nbrdf_error messages naming the file.
#include "texture/oiio_shim.h"

#include <OpenImageIO/imageio.h>

#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include <unistd.h>

extern "C" {
#include "core/error.h"
#include "core/input_file.h"
#include "texture/image_check.h"
}
#include "texture/oiio_output_proxy.hpp"

using OIIO::ImageInput;
using OIIO::ImageOutput;
using OIIO::ImageSpec;
using OIIO::TypeDesc;

struct texture_image_in {
  std::string path;
  std::unique_ptr<ImageInput> in;
  ImageSpec spec;
};

namespace {

// The largest tile read (floats): real maps use tiles of 64x64 to 512x512.
constexpr size_t kTileBytesMax = size_t(64) << 20;

std::string first_line(std::string s) {
  size_t nl = s.find('\n');
  if (nl != std::string::npos) s.resize(nl);
  return s.empty() ? std::string("unknown error") : s;
}

texture_pixel_format classify(TypeDesc t) {
  switch (t.basetype) {
  case TypeDesc::UINT8:
    return NBRDF_PIXEL_U8;
  case TypeDesc::UINT16:
    return NBRDF_PIXEL_U16;
  case TypeDesc::HALF:
    return NBRDF_PIXEL_HALF;
  case TypeDesc::FLOAT:
    return NBRDF_PIXEL_FLOAT;
  default:
    return NBRDF_PIXEL_OTHER;
  }
}

TypeDesc to_type(texture_pixel_format f) {
  switch (f) {
  case NBRDF_PIXEL_U8:
    return TypeDesc::UINT8;
  case NBRDF_PIXEL_U16:
    return TypeDesc::UINT16;
  case NBRDF_PIXEL_HALF:
    return TypeDesc::HALF;
  default:
    return TypeDesc::FLOAT;
  }
}

void copy_string(char *dst, size_t n, const std::string &src) {
  std::snprintf(dst, n, "%s", src.c_str());
}

} // namespace

extern "C" const char *texture_pixel_format_name(texture_pixel_format format) {
  switch (format) {
  case NBRDF_PIXEL_U8:
    return "uint8";
  case NBRDF_PIXEL_U16:
    return "uint16";
  case NBRDF_PIXEL_HALF:
    return "half";
  case NBRDF_PIXEL_FLOAT:
    return "float";
  case NBRDF_PIXEL_OTHER:
    break;
  }
  return "other";
}

extern "C" nbrdf_status texture_image_open(const char *path, int flags, texture_image_in **out,
                                           texture_image_info *info, nbrdf_error *err) {
  *out = nullptr;
  if (!path) return core_fail(err, NBRDF_ERR_ARGUMENT, "image path is NULL");
  // OpenImageIO opens by name: a FIFO or a device would block it or never end.
  uint64_t size = 0;
  nbrdf_status st = core_input_check(path, NBRDF_INPUT_ANY_SIZE, &size, err);
  if (st == NBRDF_OK) st = texture_image_check_structure(path, size, err);
  if (st != NBRDF_OK) return st;
  try {
    std::unique_ptr<texture_image_in> img(new texture_image_in);
    img->path = path;
    ImageSpec config;
    if (flags & NBRDF_IMAGE_UNASSOCIATED_ALPHA) config.attribute("oiio:UnassociatedAlpha", 1);
    img->in = ImageInput::open(path, &config);
    if (!img->in)
      return core_fail(err, NBRDF_ERR_IO, "%s: cannot read image: %s", path,
                       first_line(OIIO::geterror()).c_str());
    img->spec = img->in->spec();
    const ImageSpec &s = img->spec;
    if (s.width < 1 || s.height < 1 || s.nchannels < 1 || s.depth > 1)
      return core_fail(err, NBRDF_ERR_UNSUPPORTED, "%s: not a 2D image (%dx%dx%d, %d channels)",
                       path, s.width, s.height, s.depth, s.nchannels);
    // OpenImageIO reads a whole tile (as floats) to deliver any row of it: a
    // forged tile size would make it allocate gigabytes for a small image.
    if (s.tile_width > 0 && s.tile_height > 0 &&
        (double)s.tile_width * s.tile_height * s.nchannels * 4.0 > kTileBytesMax)
      return core_fail(err, NBRDF_ERR_UNSUPPORTED,
                       "%s: tiles of %dx%d texels and %d channels (at most %d MiB a tile)", path,
                       s.tile_width, s.tile_height, s.nchannels, (int)(kTileBytesMax >> 20));
    // OpenImageIO's Targa reader decodes the whole image when the first row is
    // asked for: a 21-byte file claiming 13000x13000 texels allocated 676 MB
    // (fuzz_param_map). Run-length packets hold at most 128 texels for one
    // header byte and one texel, which bounds what a file of `size` can hold.
    if (!std::strcmp(img->in->format_name(), "targa")) {
      double texel_bytes = (double)s.nchannels * (double)s.format.size();
      double most = 128.0 * (double)size / (1.0 + texel_bytes);
      if ((double)s.width * (double)s.height > most)
        return core_fail(err, NBRDF_ERR_FORMAT,
                         "%s: a Targa image of %dx%d texels cannot fit in %llu bytes", path,
                         s.width, s.height, (unsigned long long)size);
    }
    std::memset(info, 0, sizeof *info);
    info->width = s.width;
    info->height = s.height;
    info->channels = s.nchannels;
    info->alpha_channel = s.alpha_channel;
    info->format = classify(s.format);
    info->bits_per_sample = s.get_int_attribute("oiio:BitsPerSample", (int)s.format.size() * 8);
    copy_string(info->format_name, sizeof info->format_name, s.format.c_str());
    copy_string(info->file_format, sizeof info->file_format, img->in->format_name());
    copy_string(info->colour_space, sizeof info->colour_space,
                s.get_string_attribute("oiio:ColorSpace"));
    int levels = 1;
    while (levels < 32 && img->in->spec_dimensions(0, levels).width > 0)
      levels++;
    info->mip_levels = levels;
    *out = img.release();
    return NBRDF_OK;
  } catch (const std::exception &e) {
    return core_fail(err, NBRDF_ERR_IO, "%s: cannot read image: %s", path, e.what());
  } catch (...) {
    return core_fail(err, NBRDF_ERR_INTERNAL, "%s: unknown exception in OpenImageIO", path);
  }
}

extern "C" const char *texture_image_channel_name(const texture_image_in *img, int c) {
  if (c < 0 || c >= (int)img->spec.channelnames.size()) return "";
  return img->spec.channelnames[(size_t)c].c_str();
}

extern "C" nbrdf_status texture_image_level_size(texture_image_in *img, int level, int *width,
                                                 int *height, nbrdf_error *err) {
  try {
    ImageSpec s = level == 0 ? img->spec : img->in->spec_dimensions(0, level);
    if (level < 0 || s.width < 1)
      return core_fail(err, NBRDF_ERR_ARGUMENT, "%s: no mip level %d", img->path.c_str(), level);
    *width = s.width;
    *height = s.height;
    return NBRDF_OK;
  } catch (const std::exception &e) {
    return core_fail(err, NBRDF_ERR_IO, "%s: %s", img->path.c_str(), e.what());
  }
}

extern "C" nbrdf_status texture_image_read_rows(texture_image_in *img, int level, int y0, int y1,
                                                int c0, int c1, float *out, nbrdf_error *err) {
  const char *path = img->path.c_str();
  try {
    ImageSpec s = level == 0 ? img->spec : img->in->spec_dimensions(0, level);
    if (level < 0 || s.width < 1)
      return core_fail(err, NBRDF_ERR_ARGUMENT, "%s: no mip level %d", path, level);
    if (y0 < 0 || y1 > s.height || y0 >= y1 || c0 < 0 || c1 > s.nchannels || c0 >= c1)
      return core_fail(err, NBRDF_ERR_ARGUMENT, "%s: rows [%d, %d) channels [%d, %d) of %dx%d",
                       path, y0, y1, c0, c1, s.width, s.height);
    bool ok;
    if (s.tile_width > 0 && s.tile_height > 0) {
      // OIIO 2.4.7's read_scanlines dies of SIGFPE on tiled files: read the
      // tile rows that cover [y0, y1) instead and copy the rows asked for.
      int th = s.tile_height, ty0 = y0 / th * th, ty1 = (y1 + th - 1) / th * th;
      if (ty1 > s.height) ty1 = s.height;
      size_t row = (size_t)s.width * (size_t)(c1 - c0);
      std::vector<float> band((size_t)(ty1 - ty0) * row);
      ok = img->in->read_tiles(0, level, s.x, s.x + s.width, s.y + ty0, s.y + ty1, s.z,
                               s.z + (s.depth > 0 ? s.depth : 1), c0, c1, TypeDesc::FLOAT,
                               band.data());
      if (ok)
        std::memcpy(out, band.data() + (size_t)(y0 - ty0) * row,
                    (size_t)(y1 - y0) * row * sizeof(float));
    } else {
      ok = img->in->read_scanlines(0, level, s.y + y0, s.y + y1, s.z, c0, c1, TypeDesc::FLOAT, out);
    }
    if (!ok)
      return core_fail(err, NBRDF_ERR_IO, "%s: cannot read rows %d..%d: %s", path, y0, y1 - 1,
                       first_line(img->in->geterror()).c_str());
    return NBRDF_OK;
  } catch (const std::exception &e) {
    return core_fail(err, NBRDF_ERR_IO, "%s: %s", path, e.what());
  } catch (...) {
    return core_fail(err, NBRDF_ERR_INTERNAL, "%s: unknown exception in OpenImageIO", path);
  }
}

extern "C" void texture_image_close(texture_image_in *img) {
  if (!img) return;
  try {
    if (img->in) img->in->close();
  } catch (...) {
  }
  delete img;
}

static nbrdf_status check_image(const char *path, int width, int height, int channels,
                                const float *pixels, nbrdf_error *err) {
  if (!path || width < 1 || height < 1 || channels < 1 || channels > 16 || !pixels)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "%s: cannot write a %dx%d image of %d channels",
                     path ? path : "(null)", width, height, channels);
  return NBRDF_OK;
}

extern "C" nbrdf_status texture_image_write_to(core_output_file *f, int width, int height,
                                               int channels, const float *pixels,
                                               texture_pixel_format format, nbrdf_error *err) {
  const char *path = f ? f->path : nullptr;
  nbrdf_status st = check_image(path, width, height, channels, pixels, err);
  if (st != NBRDF_OK) return st;
  /* Declared before `out`: an ImageOutput closes (and may write) when destroyed. */
  nbrdf_oiio::OutputFileProxy proxy(f);
  try {
    std::unique_ptr<ImageOutput> out = ImageOutput::create(path);
    if (!out)
      return core_fail(err, NBRDF_ERR_UNSUPPORTED, "%s: no image format for this name: %s", path,
                       first_line(OIIO::geterror()).c_str());
    ImageSpec spec(width, height, channels, to_type(format));
    if (channels == 4) spec.alpha_channel = 3;
    /* The bytes go through the proxy where the format takes one (PNG and OpenEXR do): a
     * failed write is then reported with `path` and its errno, which some plugins drop.
     * Others open "/proc/self/fd/N" (the unnamed temporary file) by name. */
    bool ok = out->supports("ioproxy") ? out->set_ioproxy(&proxy) && out->open(path, spec)
                                       : out->open(core_output_file_name(f), spec);
    ok = ok && out->write_image(TypeDesc::FLOAT, pixels);
    std::string why = ok ? std::string() : first_line(out->geterror());
    ok = out->close() && ok;
    if (proxy.status() != NBRDF_OK) {
      if (err) *err = *proxy.failure();
      return proxy.status();
    }
    if (!ok) return core_fail(err, NBRDF_ERR_IO, "%s: cannot write image: %s", path, why.c_str());
  } catch (const std::exception &e) {
    return core_fail(err, NBRDF_ERR_IO, "%s: cannot write image: %s", path, e.what());
  } catch (...) {
    return core_fail(err, NBRDF_ERR_INTERNAL, "%s: unknown exception in OpenImageIO", path);
  }
  return NBRDF_OK;
}

extern "C" nbrdf_status texture_image_write(const char *path, int width, int height, int channels,
                                            const float *pixels, texture_pixel_format format,
                                            nbrdf_error *err) {
  nbrdf_status st = check_image(path, width, height, channels, pixels, err);
  if (st != NBRDF_OK) return st;
  core_output_file f;
  st = core_output_file_open(&f, path, nullptr, 0, err);
  if (st != NBRDF_OK) return st;
  st = texture_image_write_to(&f, width, height, channels, pixels, format, err);
  if (st != NBRDF_OK) {
    core_output_file_abort(&f);
    return st;
  }
  return core_output_file_commit(&f, err);
}
