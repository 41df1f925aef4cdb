// OpenImageIO writes an image's bytes through this proxy into a core_output_file, for the
// image writers (oiio_shim.cpp, lobe/png_write_shim.cpp). Only included by those C++ shims.
//
// Why not let OpenImageIO open "/proc/self/fd/N" by name: its PNG writer does not report a
// failed write (on a full disk it "succeeded" leaving a PNG cut at a buffer boundary), and its
// messages name the /proc path. Through the proxy every byte goes through
// core_output_file_pwrite, so the first failure is kept with the user's path and strerror,
// whatever the format plugin then reports.
#ifndef NBRDF_TEXTURE_OIIO_OUTPUT_PROXY_HPP
#define NBRDF_TEXTURE_OIIO_OUTPUT_PROXY_HPP

#include <OpenImageIO/filesystem.h>

#include <cstdint>
#include <mutex>

extern "C" {
#include "core/output_file.h"
}

namespace nbrdf_oiio {

class OutputFileProxy final : public OIIO::Filesystem::IOProxy {
public:
  explicit OutputFileProxy(core_output_file *f) : IOProxy(f->path, Write), f_(f) {}
  const char *proxytype() const override { return "nbrdf_output_file"; }
  void close() override { m_mode = Closed; }
  size_t write(const void *buf, size_t n) override {
    size_t w = pwrite(buf, n, m_pos);
    m_pos += (int64_t)w;
    return w;
  }
  size_t pwrite(const void *buf, size_t n, int64_t offset) override {
    std::lock_guard<std::mutex> lock(mutex_);
    if (status_ != NBRDF_OK) return 0; // the first failure stands; nothing after it lands
    if (n == 0) return 0;
    status_ = core_output_file_pwrite(f_, buf, n, offset, &err_);
    if (status_ != NBRDF_OK) return 0;
    if ((uint64_t)offset + n > end_) end_ = (uint64_t)offset + n;
    return n;
  }
  size_t size() const override { return (size_t)end_; }
  // NBRDF_OK, or the first write's failure (its message in *error()).
  nbrdf_status status() const { return status_; }
  const nbrdf_error *failure() const { return &err_; }

private:
  core_output_file *f_;
  std::mutex mutex_;
  nbrdf_status status_ = NBRDF_OK;
  nbrdf_error err_ = {};
  uint64_t end_ = 0;
};

} // namespace nbrdf_oiio

#endif
