// The notify command on POSIX: fork and execv, the event on a pipe to its
// stdin (notify_command_win32.cpp: CreateProcess).
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "serve/notify.hpp"

namespace lmcfg::serve {

Result<void> run_with_stdin(const std::string& program, const std::string& input) {
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0)
    return Error(Errc::io_error, "notify command " + program + ": pipe: " + std::strerror(errno));
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    return Error(Errc::io_error, "notify command " + program + ": fork: " + std::strerror(errno));
  }
  if (pid == 0) {
    ::dup2(fds[0], STDIN_FILENO);
    char* argv[] = {const_cast<char*>(program.c_str()), nullptr};
    ::execv(program.c_str(), argv);
    ::_exit(127);
  }
  ::close(fds[0]);
  // A command that exits without reading must not end the service (SIGPIPE).
  ::signal(SIGPIPE, SIG_IGN);
  std::size_t off = 0;
  while (off < input.size()) {
    const auto n = ::write(fds[1], input.data() + off, input.size() - off);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    off += static_cast<std::size_t>(n);
  }
  ::close(fds[1]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return {};
  if (WIFEXITED(status) && WEXITSTATUS(status) == 127)
    return Error(Errc::io_error, "notify command " + program + " could not be run (exit 127)");
  return Error(Errc::io_error,
               "notify command " + program + " failed (" +
                   (WIFEXITED(status) ? "exit " + std::to_string(WEXITSTATUS(status))
                                      : "signal " + std::to_string(WTERMSIG(status))) +
                   ")");
}

}  // namespace lmcfg::serve
