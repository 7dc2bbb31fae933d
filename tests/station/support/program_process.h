#pragma once
// A program the tests run as a child process (hybrid-station, hybrid-remote), its stdout read line
// by line while it runs so a test waits for the program's own event and progress lines, never for
// wall-clock time. The destructor stops a child still running (SIGTERM, as Ctrl-C would) and reaps
// it: no test leaves a process behind.

#include <fcntl.h>
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>
#include <csignal>

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "test_spawn.h"

namespace hd::station::testing {

class ProgramProcess {
 public:
  /// Starts `program` with `args`; stderr goes to the file `err`.
  ProgramProcess(const std::string& program, const std::vector<std::string>& args,
                 const std::filesystem::path& err) {
    int fds[2];
    EXPECT_EQ(::pipe2(fds, O_CLOEXEC), 0);
    std::vector<std::string> words{program};
    words.insert(words.end(), args.begin(), args.end());
    pid_ = hd::test::spawn(words, {fds[1], err.string()});
    EXPECT_GT(pid_, 0) << "could not start " << program;
    ::close(fds[1]);
    out_ = ::fdopen(fds[0], "r");
  }
  ~ProgramProcess() {
    interrupt();
    wait();
  }
  ProgramProcess(const ProgramProcess&) = delete;
  ProgramProcess& operator=(const ProgramProcess&) = delete;

  /// Reads stdout until a line contains `text` (true) or the program ends (false).
  bool read_until(const std::string& text) {
    return read_until_line([&](const std::string& l) { return l.find(text) != std::string::npos; });
  }
  /// Reads stdout until `done(line)` holds for a line (true) or the program ends (false).
  template <class Done>
  bool read_until_line(Done done) {
    char line[8192];
    while (out_ != nullptr && std::fgets(line, sizeof line, out_) != nullptr) {
      all_ += line;
      if (done(std::string(line))) return true;
    }
    return false;
  }
  /// Asks the program to stop as Ctrl-C would (it finishes and writes its outputs).
  void interrupt() {
    if (pid_ > 0) ::kill(pid_, SIGTERM);
  }
  /// Reads the rest of stdout and returns the exit code (-1: killed by a signal).
  int wait() {
    if (pid_ <= 0) return code_;
    read_until_line([](const std::string&) { return false; });
    if (out_ != nullptr) std::fclose(out_);
    out_ = nullptr;
    int status = 0;
    ::waitpid(pid_, &status, 0);
    pid_ = -1;
    code_ = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return code_;
  }
  const std::string& out() const { return all_; }

 private:
  pid_t pid_ = -1;
  FILE* out_ = nullptr;
  std::string all_;
  int code_ = -1;
};

}  // namespace hd::station::testing
