#pragma once
// An owned file descriptor, closed through the syscall seam it was opened with.

#include <utility>

#include "drivers/v4l2/v4l2_syscalls.h"

namespace hd::drivers {

class UniqueFd {
 public:
  UniqueFd() = default;
  UniqueFd(V4l2Syscalls& sys, int fd) : sys_(&sys), fd_(fd) {}
  ~UniqueFd() { reset(); }
  UniqueFd(UniqueFd&& o) noexcept : sys_(o.sys_), fd_(std::exchange(o.fd_, -1)) {}
  UniqueFd& operator=(UniqueFd&& o) noexcept {
    if (this != &o) {
      reset();
      sys_ = o.sys_;
      fd_ = std::exchange(o.fd_, -1);
    }
    return *this;
  }
  UniqueFd(const UniqueFd&) = delete;
  UniqueFd& operator=(const UniqueFd&) = delete;

  int get() const { return fd_; }
  bool valid() const { return fd_ >= 0; }
  void reset() {
    if (fd_ >= 0 && sys_ != nullptr) sys_->close(fd_);
    fd_ = -1;
  }

 private:
  V4l2Syscalls* sys_ = nullptr;
  int fd_ = -1;
};

}  // namespace hd::drivers
