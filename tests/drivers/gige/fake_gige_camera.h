#pragma once
// Aravis's fake GigE Vision camera as a child process on 127.0.0.1: a real GVCP/GVSP peer.

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>

#include "drivers/gige/gvcp_liveness_probe.h"

namespace hd::drivers::testing {

class FakeGigeCamera {
 public:
  explicit FakeGigeCamera(const std::string& serial = "SERIAL") {
    pid_ = ::fork();
    if (pid_ < 0) throw std::runtime_error("fork failed");
    if (pid_ == 0) {
      ::execl(HD_ARV_FAKE_GV_CAMERA, HD_ARV_FAKE_GV_CAMERA, "-i", "127.0.0.1", "-s", serial.c_str(),
              static_cast<char*>(nullptr));
      ::_exit(127);
    }
    // Ready when it answers GVCP on its control port.
    GvcpLivenessProbe probe("127.0.0.1");
    for (int i = 0; i < 100; ++i) {
      if (probe.ping(50'000'000) == GvcpLivenessProbe::Answer::kAlive) return;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    kill();
    throw std::runtime_error("arv-fake-gv-camera-0.8 did not answer GVCP on 127.0.0.1:3956");
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
  pid_t pid_ = -1;
};

}  // namespace hd::drivers::testing
