#pragma once
// A real RTP peer for the tests: gst-launch-1.0 run as a child process with a given pipeline,
// and a free pair of loopback UDP ports (RTP, RTCP) for it to send to.

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

namespace hd::drivers::testing {

/// An even port P on 127.0.0.1 with P and P + 1 free now (bound and released).
inline uint16_t free_rtp_port() {
  // From below the kernel's ephemeral range (32768-60999 here): a port the kernel handed out
  // for port 0 and this probe let go could be handed to any other socket bound to port 0 (a
  // sender's, an RTCP socket) before the camera binds it; under ctest -j2 that failed a test
  // with "cannot listen" (2026-12-05). A random even port of 20000-32698, checked with its
  // RTCP neighbour, collides only with another test that drew the same one.
  static std::mt19937 pick(static_cast<uint32_t>(::getpid()) * 2654435761u ^
                           static_cast<uint32_t>(std::random_device{}()));
  for (int attempt = 0; attempt < 256; ++attempt) {
    const uint16_t p = static_cast<uint16_t>(20000 + 2 * (pick() % 6350));
    bool ok = true;
    for (uint16_t q : {p, static_cast<uint16_t>(p + 1)}) {
      int s = ::socket(AF_INET, SOCK_DGRAM, 0);
      sockaddr_in b{};
      b.sin_family = AF_INET;
      b.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
      b.sin_port = htons(q);
      ok = ok && ::bind(s, reinterpret_cast<sockaddr*>(&b), sizeof b) == 0;
      ::close(s);
    }
    if (ok) return p;
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
  explicit ChildProcess(std::vector<std::string> words) {
    pid_ = ::fork();
    if (pid_ == 0) {
      std::vector<char*> argv;
      for (std::string& w : words) argv.push_back(w.data());
      argv.push_back(nullptr);
      ::execvp(argv[0], argv.data());
      ::_exit(127);
    }
  }
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
