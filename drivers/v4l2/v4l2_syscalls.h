#pragma once
// The seam between the V4L2 driver and the kernel: every system call the driver makes goes
// through this interface, so tests can put a fake device (a V4L2 state machine) behind it.

#include <poll.h>
#include <sys/types.h>

#include <cstddef>

namespace hd::drivers {

/// The six calls a V4L2 capture needs, with libc's contract: failures return -1 (MAP_FAILED for
/// mmap) and set errno. Implementations must be callable from the capture thread.
class V4l2Syscalls {
 public:
  virtual ~V4l2Syscalls() = default;
  virtual int open(const char* path, int flags) = 0;
  virtual int close(int fd) = 0;
  virtual int ioctl(int fd, unsigned long request, void* arg) = 0;
  virtual int poll(pollfd* fds, nfds_t count, int timeout_ms) = 0;
  virtual void* mmap(void* addr, std::size_t length, int prot, int flags, int fd, off_t offset) = 0;
  virtual int munmap(void* addr, std::size_t length) = 0;
};

/// The real kernel. ioctl is retried on EINTR, as every V4L2 program does.
V4l2Syscalls& libc_v4l2_syscalls();

}  // namespace hd::drivers
