#pragma once
// Aravis's fake GigE Vision camera as a child process on 127.0.0.1: a real GVCP/GVSP peer.

#include <arpa/inet.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>

#include "drivers/gige/gvcp_liveness_probe.h"

namespace hd::drivers::testing {

class FakeGigeCamera {
 public:
  /// `genicam`: a GenICam XML file the camera describes itself with instead of Aravis's built-in
  /// one (arv-fake-gv-camera-0.8 -g); its features must match the fake's registers.
  explicit FakeGigeCamera(const std::string& serial = "SERIAL", const std::string& genicam = "") {
    // Every fake camera listens on 127.0.0.1:3956, and a second one cannot start while another
    // process holds the port (a parallel test run elsewhere on this machine): wait for it.
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(180);
    while (std::chrono::steady_clock::now() < deadline) {
      if (!port_free()) {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        continue;
      }
      if (start(serial, genicam)) return;
    }
    throw std::runtime_error(
        "arv-fake-gv-camera-0.8 could not listen on 127.0.0.1:3956 within 180 s (another fake "
        "camera kept the port)");
  }
  ~FakeGigeCamera() { kill(); }
  FakeGigeCamera(const FakeGigeCamera&) = delete;
  FakeGigeCamera& operator=(const FakeGigeCamera&) = delete;

  /// SIGKILL: the camera vanishes without a word, as when its power or cable goes.
  void kill() {
    if (pid_ <= 0) return;
    ::kill(pid_, SIGKILL);
    int status = 0;
    ::waitpid(pid_, &status, 0);
    pid_ = -1;
  }

 private:
  // True when nobody holds UDP 127.0.0.1:3956 (our bind would fail with EADDRINUSE otherwise).
  static bool port_free() {
    const int fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    if (fd < 0) return true;  // cannot tell: let the start attempt decide
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(3956);
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    const bool free = ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
    ::close(fd);
    return free;
  }

  bool child_alive() {
    int status = 0;
    if (::waitpid(pid_, &status, WNOHANG) == 0) return true;
    pid_ = -1;
    return false;
  }

  // One attempt: false when the child exited (it lost the port to another process meanwhile).
  bool start(const std::string& serial, const std::string& genicam) {
    const pid_t parent = ::getpid();
    pid_ = ::fork();
    if (pid_ < 0) throw std::runtime_error("fork failed");
    if (pid_ == 0) {
      // The camera dies with the test: a test process that aborts (a sanitizer report) or is
      // killed at its ctest timeout runs no destructor, and an orphaned fake camera would hold
      // port 3956 and make every later GigE test wait for it.
      ::prctl(PR_SET_PDEATHSIG, SIGKILL);
      if (::getppid() != parent) ::_exit(127);  // the test died before prctl took effect
      if (genicam.empty()) {
        ::execl(HD_ARV_FAKE_GV_CAMERA, HD_ARV_FAKE_GV_CAMERA, "-i", "127.0.0.1", "-s",
                serial.c_str(), static_cast<char*>(nullptr));
      } else {
        ::execl(HD_ARV_FAKE_GV_CAMERA, HD_ARV_FAKE_GV_CAMERA, "-i", "127.0.0.1", "-s",
                serial.c_str(), "-g", genicam.c_str(), static_cast<char*>(nullptr));
      }
      ::_exit(127);
    }
    // Ready when it answers GVCP on its control port, and is still the one running there.
    GvcpLivenessProbe probe("127.0.0.1");
    for (int i = 0; i < 1000; ++i) {
      if (!child_alive()) return false;
      if (probe.ping(50'000'000) == GvcpLivenessProbe::Answer::kAlive && child_alive()) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    kill();
    throw std::runtime_error("arv-fake-gv-camera-0.8 did not answer GVCP on 127.0.0.1:3956");
  }

  pid_t pid_ = -1;
};

}  // namespace hd::drivers::testing
