#pragma once
// Starts a program as a test's child process with posix_spawn: nothing but exec runs in the
// child. A test process has GStreamer and device threads, and after fork() a child may make only
// async-signal-safe calls; one that built its argv there could hang before exec when another
// thread held the allocator's lock (GCC 12's ASan takes no lock around fork). A remote sender
// that never ran failed the CI's ASan run once: its camera saw 0 packets in 60 s (2026-12-05).
#include <fcntl.h>
#include <spawn.h>
#include <unistd.h>

#include <string>
#include <vector>

namespace hd::test {

/// Where the child's stdout and stderr go; unset: the test's own.
struct ChildOutput {
  int stdout_fd = -1;             ///< dup'ed to the child's stdout (open it O_CLOEXEC)
  std::string stderr_path;        ///< created or truncated, mode 0644
  bool stderr_to_stdout = false;  ///< stderr joins stdout (when no stderr_path)
};

/// Runs words[0] (searched in PATH when it has no '/') with words as argv; its pid, or -1 when it
/// could not be started.
inline pid_t spawn(const std::vector<std::string>& words, const ChildOutput& out = {}) {
  if (words.empty()) return -1;
  std::vector<char*> argv;
  for (const std::string& w : words) argv.push_back(const_cast<char*>(w.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (out.stdout_fd >= 0) posix_spawn_file_actions_adddup2(&actions, out.stdout_fd, 1);
  if (!out.stderr_path.empty())
    posix_spawn_file_actions_addopen(&actions, 2, out.stderr_path.c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0644);
  else if (out.stderr_to_stdout)
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
  pid_t pid = -1;
  const int rc = ::posix_spawnp(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  return rc == 0 ? pid : -1;
}

}  // namespace hd::test
