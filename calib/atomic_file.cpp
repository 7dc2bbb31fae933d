#include "calib/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace hd::calib {

namespace fs = std::filesystem;

namespace {

// Owns the temp file until it is renamed into place.
class TempFile {
 public:
  explicit TempFile(const fs::path& target) {
    std::string tmpl = target.string() + ".tmp.XXXXXX";
    fd_ = ::mkstemp(tmpl.data());
    if (fd_ < 0)
      throw std::runtime_error(target.string() +
                               ": cannot create a temp file beside it: " + std::strerror(errno));
    path_ = tmpl;
  }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
  ~TempFile() {
    if (fd_ >= 0) ::close(fd_);
    if (!committed_) ::unlink(path_.c_str());
  }
  void write_all(const std::string& s, const fs::path& target) {
    std::size_t off = 0;
    while (off < s.size()) {
      const ssize_t n = ::write(fd_, s.data() + off, s.size() - off);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0)
        throw std::runtime_error(target.string() + ": write failed: " + std::strerror(errno));
      off += static_cast<std::size_t>(n);
    }
    if (::fchmod(fd_, 0644) != 0 || ::fsync(fd_) != 0 || ::close(fd_) != 0) {
      fd_ = -1;
      throw std::runtime_error(target.string() + ": flush failed: " + std::strerror(errno));
    }
    fd_ = -1;
  }
  void rename_to(const fs::path& target) {
    if (::rename(path_.c_str(), target.c_str()) != 0)
      throw std::runtime_error(target.string() + ": rename failed: " + std::strerror(errno));
    committed_ = true;
  }

 private:
  int fd_ = -1;
  std::string path_;
  bool committed_ = false;
};

}  // namespace

void check_output_free(const fs::path& path, bool force) {
  std::error_code ec;
  if (!force && fs::exists(path, ec))
    throw OutputExists(path.string() +
                       ": already exists; pass --force to replace it (the old file is kept as " +
                       path.string() + ".bak)");
}

void write_file_atomically(const fs::path& path, const std::string& content, bool force) {
  check_output_free(path, force);
  TempFile tmp(path);
  tmp.write_all(content, path);
  std::error_code ec;
  if (fs::exists(path, ec)) {
    fs::copy_file(path, path.string() + ".bak", fs::copy_options::overwrite_existing, ec);
    if (ec)
      throw std::runtime_error(path.string() +
                               ": cannot keep the old file as .bak: " + ec.message());
  }
  tmp.rename_to(path);
}

}  // namespace hd::calib
