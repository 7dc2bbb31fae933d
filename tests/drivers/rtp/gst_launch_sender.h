#pragma once
// A real RTP peer for the tests: gst-launch-1.0 run as a child process with a given pipeline,
// and a free run of loopback UDP ports (RTP and RTCP per camera) for it to send to.

#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdint>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "test_spawn.h"

namespace hd::drivers::testing {

/// A base port P on 127.0.0.1 for `cameras` RTP streams (camera i: P + 2 i, its RTCP P + 2 i + 1),
/// all free now (bound and released).
inline uint16_t free_rtp_port(int cameras = 3) {
  // From below the kernel's ephemeral range (32768-60999 here): a port the kernel handed out
  // for port 0 and this probe let go could be handed to any other socket bound to port 0 (a
  // sender's, an RTCP socket) before the camera binds it; under ctest -j2 that failed a test
  // with "cannot listen" (2026-12-05). Bases are multiples of 8 and a default-scene sender uses
  // 6 ports, so two tests' runs never overlap in part: a sender's camera 1 or 2, with no one
  // listening yet, cannot be another test's camera 0. The default of 3 is the default scene's.
  static std::mt19937 pick(static_cast<uint32_t>(::getpid()) * 2654435761u ^
                           static_cast<uint32_t>(std::random_device{}()));
  if (cameras < 1 || cameras > 4) return 0;
  for (int attempt = 0; attempt < 256; ++attempt) {
    const int base = 20000 + 8 * static_cast<int>(pick() % 1595);
    bool ok = true;
    for (int q = base; q < base + 2 * cameras && ok; ++q) {
      const int s = ::socket(AF_INET, SOCK_DGRAM, 0);
      sockaddr_in b{};
      b.sin_family = AF_INET;
      b.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
      b.sin_port = htons(static_cast<uint16_t>(q));
      ok = ::bind(s, reinterpret_cast<sockaddr*>(&b), sizeof b) == 0;
      ::close(s);
    }
    if (ok) return static_cast<uint16_t>(base);
  }
  return 0;
}

/// The plain standard sender, to 127.0.0.1:port.
inline std::string plain_sender_pipeline(uint16_t port) {
  return "videotestsrc is-live=true ! x264enc tune=zerolatency ! rtph264pay ! udpsink "
         "host=127.0.0.1 port=" +
         std::to_string(port);
}

/// A child process (argv[0] looked up in PATH) killed and reaped when destroyed.
class ChildProcess {
 public:
  explicit ChildProcess(const std::vector<std::string>& words) : pid_(hd::test::spawn(words)) {}
  ~ChildProcess() { stop(); }
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;
  void stop() {
    if (pid_ <= 0) return;
    ::kill(pid_, SIGKILL);
    int status = 0;
    ::waitpid(pid_, &status, 0);
    pid_ = -1;
  }
  bool running() const { return pid_ > 0; }

 private:
  pid_t pid_ = -1;
};

/// Runs `gst-launch-1.0 -q PIPELINE` until destroyed.
class GstLaunch : public ChildProcess {
 public:
  explicit GstLaunch(const std::string& pipeline) : ChildProcess(words(pipeline)) {}

 private:
  static std::vector<std::string> words(const std::string& pipeline) {
    std::vector<std::string> w{"gst-launch-1.0", "-q"};
    std::istringstream in(pipeline);
    for (std::string x; in >> x;) w.push_back(x);
    return w;
  }
};

}  // namespace hd::drivers::testing
