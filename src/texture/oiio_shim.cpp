// The OpenImageIO side of oiio_shim.h. Every entry point catches exceptions
// and turns OIIO's error strings into nbrdf_error messages naming the file.
#include "texture/oiio_shim.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <limits>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include <sys/mman.h>
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
  // Declared before `in`, so the reader is destroyed before the proxy it reads.
  std::unique_ptr<OIIO::Filesystem::IOProxy> proxy;
  std::unique_ptr<ImageInput> in;
  ImageSpec spec;
};

namespace {

// The largest tile read (floats): real maps use tiles of 64x64 to 512x512.
constexpr size_t kTileBytesMax = size_t(64) << 20;
// 16 x NBRDF_BAKE_SIZE_MAX (a larger map resamples to the largest texture); beyond it a
// row alone would cost OpenImageIO's readers gigabytes.
constexpr int kMapSideMax = 1 << 20;
constexpr double kTexelsPerByteMax = 16384.0;

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

std::atomic<int> g_capture_stderr{0};

// Sends fd 2 to an in-memory file for its lifetime (texture_image_capture_stderr);
// text() restores fd 2 and returns what was written meanwhile. Inactive (and a
// no-op) when capturing is off or a descriptor cannot be had.
class StderrCapture {
public:
  StderrCapture() {
    if (!g_capture_stderr.load()) return;
    std::fflush(stderr);
    mem_ = memfd_create("nbrdf-stderr", MFD_CLOEXEC);
    if (mem_ >= 0) saved_ = dup(2);
    if (saved_ < 0 || dup2(mem_, 2) < 0) release();
  }
  ~StderrCapture() { pass_on(); }
  StderrCapture(const StderrCapture &) = delete;
  StderrCapture &operator=(const StderrCapture &) = delete;

  std::string text() {
    std::string s;
    if (mem_ < 0) return s;
    std::fflush(stderr);
    dup2(saved_, 2);
    char buf[4096];
    ssize_t n = pread(mem_, buf, sizeof buf, 0);
    if (n > 0) s.assign(buf, (size_t)n);
    release();
    return s;
  }
  // A success: what the libraries said (warnings) reaches stderr as it would have.
  void pass_on() {
    std::string s = text();
    if (!s.empty() && write(2, s.data(), s.size()) < 0) {
    }
  }

private:
  void release() {
    if (saved_ >= 0) {
      dup2(saved_, 2);
      close(saved_);
    }
    if (mem_ >= 0) close(mem_);
    saved_ = mem_ = -1;
  }
  int mem_ = -1, saved_ = -1;
};

// OpenImageIO's reason, with what the libraries printed that it does not already say
// ("libpng error: X" adds X unless the reason holds it).
std::string with_captured(std::string why, const std::string &captured) {
  size_t at = 0;
  while (at < captured.size()) {
    size_t nl = captured.find('\n', at);
    std::string line = captured.substr(at, nl == std::string::npos ? std::string::npos : nl - at);
    at = nl == std::string::npos ? captured.size() : nl + 1;
    for (const char *lib : {"libpng error: ", "libpng warning: "})
      if (line.compare(0, std::strlen(lib), lib) == 0) line.erase(0, std::strlen(lib));
    if (!line.empty() && why.find(line) == std::string::npos) why += "; " + line;
  }
  return why;
}

} // namespace

extern "C" void texture_image_capture_stderr(int on) { g_capture_stderr.store(on != 0); }

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

namespace {

// Everything after OpenImageIO has opened the image, for a file or a buffer:
// the checks that keep a forged header from costing gigabytes, and the info.
nbrdf_status finish_open(std::unique_ptr<texture_image_in> img, uint64_t size,
                         texture_image_in **out, texture_image_info *info, nbrdf_error *err) {
  const char *path = img->path.c_str();
  img->spec = img->in->spec();
  const ImageSpec &s = img->spec;
  if (s.width < 1 || s.height < 1 || s.nchannels < 1 || s.depth > 1)
    return core_fail(err, NBRDF_ERR_UNSUPPORTED, "%s: not a 2D image (%dx%dx%d, %d channels)",
                     path, s.width, s.height, s.depth, s.nchannels);
  // OpenEXR's data window may be smaller (or larger, or shifted) than its display window;
  // the texels read are the data window's, so such a map would bake at another size, and
  // an environment map would be misplaced, without a word. Which of the two the author
  // meant cannot be told: refuse, and say how to make them one.
  if (s.full_width > 0 && s.full_height > 0 &&
      (s.x != s.full_x || s.y != s.full_y || s.width != s.full_width ||
       s.height != s.full_height))
    return core_fail(err, NBRDF_ERR_UNSUPPORTED,
                     "%s: data window %dx%d at (%d, %d), display window %dx%d at (%d, %d); "
                     "expected texels filling the display window (`oiiotool IN --croptofull "
                     "-o OUT` pads it with zeros, `--fullpixels` makes the data window the "
                     "image)",
                     path, s.width, s.height, s.x, s.y, s.full_width, s.full_height, s.full_x,
                     s.full_y);
  // No map is much larger than the largest latent texture; and no format compresses more than
  // about 11,000 texels into a byte (LZW on 1-bit texels; deflate: 8 x 1,032), so a
  // header claiming more lies: OpenImageIO's readers allocate for the claim before finding
  // the data short (fuzz_param_map: an 18-byte PGM claiming 2222224x3 texels, 569 MB).
  // OpenEXR is exempt: every chunk was decoded by OpenEXRCore first (image_check.c).
  if (s.width > kMapSideMax || s.height > kMapSideMax)
    return core_fail(err, NBRDF_ERR_UNSUPPORTED, "%s: %dx%d texels; a map is at most %d a side",
                     path, s.width, s.height, kMapSideMax);
  if (std::strcmp(img->in->format_name(), "openexr") &&
      (double)s.width * (double)s.height > kTexelsPerByteMax * (double)size)
    return core_fail(err, NBRDF_ERR_FORMAT, "%s: a %s image of %dx%d texels cannot come from %llu bytes",
                     path, img->in->format_name(), s.width, s.height, (unsigned long long)size);
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
  // OpenImageIO's BMP reader does the same (a 54-byte file claiming 1048579x3 texels
  // allocated 805 MB); its run-length packets hold at most 255 texels for two bytes.
  const bool targa = !std::strcmp(img->in->format_name(), "targa");
  const bool bmp = !std::strcmp(img->in->format_name(), "bmp");
  if (targa || bmp) {
    double texel_bytes = (double)s.nchannels * (double)s.format.size();
    double most = bmp ? 128.0 * (double)size : 128.0 * (double)size / (1.0 + texel_bytes);
    if ((double)s.width * (double)s.height > most)
      return core_fail(err, NBRDF_ERR_FORMAT,
                       "%s: a %s image of %dx%d texels cannot fit in %llu bytes", path,
                       targa ? "Targa" : "BMP", s.width, s.height, (unsigned long long)size);
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
}

ImageSpec open_config(int flags) {
  ImageSpec config;
  if (flags & NBRDF_IMAGE_UNASSOCIATED_ALPHA) config.attribute("oiio:UnassociatedAlpha", 1);
  return config;
}

} // namespace

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
    ImageSpec config = open_config(flags);
    StderrCapture capture;
    img->in = ImageInput::open(path, &config);
    if (!img->in) {
      std::string why = first_line(OIIO::geterror());
      return core_fail(err, NBRDF_ERR_IO, "%s: cannot read image: %s", path,
                       with_captured(why, capture.text()).c_str());
    }
    capture.pass_on();
    return finish_open(std::move(img), size, out, info, err);
  } catch (const std::exception &e) {
    return core_fail(err, NBRDF_ERR_IO, "%s: cannot read image: %s", path, e.what());
  } catch (...) {
    return core_fail(err, NBRDF_ERR_INTERNAL, "%s: unknown exception in OpenImageIO", path);
  }
}

extern "C" nbrdf_status texture_image_open_memory(const char *label, const char *format,
                                                  const void *data, size_t size, int flags,
                                                  texture_image_in **out,
                                                  texture_image_info *info, nbrdf_error *err) {
  *out = nullptr;
  if (!label || !format || (!data && size))
    return core_fail(err, NBRDF_ERR_ARGUMENT, "image in memory: NULL %s",
                     !label ? "label" : !format ? "format" : "data");
  nbrdf_status st = texture_image_check_memory(label, data, size, err);
  if (st != NBRDF_OK) return st;
  try {
    std::unique_ptr<texture_image_in> img(new texture_image_in);
    img->path = label;
    img->proxy.reset(new OIIO::Filesystem::IOMemReader(data, size));
    // The format is named, so OpenImageIO probes no other reader.
    img->in = ImageInput::create(format, false, nullptr, img->proxy.get());
    if (!img->in)
      return core_fail(err, NBRDF_ERR_UNSUPPORTED, "%s: no %s reader: %s", label, format,
                       first_line(OIIO::geterror()).c_str());
    if (!img->in->supports("ioproxy"))
      return core_fail(err, NBRDF_ERR_UNSUPPORTED, "%s: the %s reader cannot read from memory",
                       label, format);
    ImageSpec config = open_config(flags), spec;
    OIIO::Filesystem::IOProxy *proxy = img->proxy.get();
    config.attribute("oiio:ioproxy", TypeDesc::PTR, &proxy);
    if (!img->in->open(label, spec, config))
      return core_fail(err, NBRDF_ERR_IO, "%s: cannot read image: %s", label,
                       first_line(img->in->geterror()).c_str());
    return finish_open(std::move(img), size, out, info, err);
  } catch (const std::exception &e) {
    return core_fail(err, NBRDF_ERR_IO, "%s: cannot read image: %s", label, e.what());
  } catch (...) {
    return core_fail(err, NBRDF_ERR_INTERNAL, "%s: unknown exception in OpenImageIO", label);
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
    StderrCapture capture;
    if (s.tile_width > 0 && s.tile_height > 0) {
      // OIIO 2.4.7's read_scanlines dies of SIGFPE on tiled files: read the
      // tile rows that cover [y0, y1) instead and copy the rows asked for.
      int th = s.tile_height, ty0 = y0 / th * th, ty1 = (y1 + th - 1) / th * th;
      if (ty1 > s.height) ty1 = s.height;
      size_t row = (size_t)s.width * (size_t)(c1 - c0);
      std::vector<float> band((size_t)(ty1 - ty0) * row, std::numeric_limits<float>::quiet_NaN());
      ok = img->in->read_tiles(0, level, s.x, s.x + s.width, s.y + ty0, s.y + ty1, s.z,
                               s.z + (s.depth > 0 ? s.depth : 1), c0, c1, TypeDesc::FLOAT,
                               band.data());
      if (ok)
        std::memcpy(out, band.data() + (size_t)(y0 - ty0) * row,
                    (size_t)(y1 - y0) * row * sizeof(float));
    } else {
      // A damaged file can decode to fewer bytes than the rows hold and leave the rest
      // unwritten: NaN there is refused by every caller, where stale memory would be baked.
      std::fill(out, out + (size_t)(y1 - y0) * (size_t)s.width * (size_t)(c1 - c0),
                std::numeric_limits<float>::quiet_NaN());
      ok = img->in->read_scanlines(0, level, s.y + y0, s.y + y1, s.z, c0, c1, TypeDesc::FLOAT, out);
    }
    if (!ok) {
      std::string why = first_line(img->in->geterror());
      return core_fail(err, NBRDF_ERR_IO, "%s: cannot read rows %d..%d: %s", path, y0, y1 - 1,
                       with_captured(why, capture.text()).c_str());
    }
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
