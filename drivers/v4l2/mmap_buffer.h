#pragma once
// One driver buffer mapped into our address space, unmapped through the seam it was mapped with.

#include <sys/mman.h>

#include <cstddef>
#include <cstdint>
#include <utility>

#include "drivers/v4l2/v4l2_syscalls.h"

namespace hd::drivers {

class MmapBuffer {
 public:
  MmapBuffer() = default;
  /// Maps `length` bytes of `fd` at `offset` (read-only, shared). Check valid(); errno on failure.
  MmapBuffer(V4l2Syscalls& sys, int fd, std::size_t length, off_t offset) : sys_(&sys) {
    void* p = sys.mmap(nullptr, length, PROT_READ, MAP_SHARED, fd, offset);
    if (p != MAP_FAILED && p != nullptr) {
      data_ = static_cast<const uint8_t*>(p);
      size_ = length;
    }
  }
  ~MmapBuffer() { reset(); }
  MmapBuffer(MmapBuffer&& o) noexcept
      : sys_(o.sys_), data_(std::exchange(o.data_, nullptr)), size_(std::exchange(o.size_, 0)) {}
  MmapBuffer& operator=(MmapBuffer&& o) noexcept {
    if (this != &o) {
      reset();
      sys_ = o.sys_;
      data_ = std::exchange(o.data_, nullptr);
      size_ = std::exchange(o.size_, 0);
    }
    return *this;
  }
  MmapBuffer(const MmapBuffer&) = delete;
  MmapBuffer& operator=(const MmapBuffer&) = delete;

  bool valid() const { return data_ != nullptr; }
  const uint8_t* data() const { return data_; }
  std::size_t size() const { return size_; }
  void reset() {
    if (data_ != nullptr && sys_ != nullptr) sys_->munmap(const_cast<uint8_t*>(data_), size_);
    data_ = nullptr;
    size_ = 0;
  }

 private:
  V4l2Syscalls* sys_ = nullptr;
  const uint8_t* data_ = nullptr;
  std::size_t size_ = 0;
};

}  // namespace hd::drivers
