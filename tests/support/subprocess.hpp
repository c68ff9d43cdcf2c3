#pragma once
// Runs the lmcfg binary as a child process for end-to-end tests.
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "files.hpp"

namespace lmcfg::test {

class Child {
 public:
  explicit Child(const std::vector<std::string>& argv) {
    int out[2];
    if (::pipe(out) != 0) return;
    pid_ = ::fork();
    if (pid_ == 0) {
      ::dup2(out[1], STDOUT_FILENO);
      ::close(out[0]);
      ::close(out[1]);
      std::vector<char*> args;
      for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
      args.push_back(nullptr);
      ::execv(args[0], args.data());
      ::_exit(127);
    }
    ::close(out[1]);
    out_ = out[0];
  }
  ~Child() {
    stop();
    if (out_ >= 0) ::close(out_);
  }
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;

  // One line of stdout, waiting at most timeout_ms; "" on timeout or EOF.
  std::string read_line(int timeout_ms = 10000) {
    std::string line;
    while (true) {
      pollfd p{out_, POLLIN, 0};
      if (::poll(&p, 1, timeout_ms) <= 0) return "";
      char c;
      if (::read(out_, &c, 1) != 1) return line;
      if (c == '\n') return line;
      line.push_back(c);
    }
  }
  pid_t pid() const { return pid_; }
  // SIGTERM and wait; returns the exit status (or -1).
  int stop() {
    if (pid_ <= 0) return -1;
    ::kill(pid_, SIGTERM);
    int status = 0;
    ::waitpid(pid_, &status, 0);
    pid_ = -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

 private:
  pid_t pid_ = -1;
  int out_ = -1;
};

struct ToolRun {
  int exit_code = -1;
  std::string out;  // stdout
  std::string err;  // stderr
};
// `lmcfg ARGS` run in `dir` (stdin /dev/null; stdout and stderr kept in
// dir/stdout.txt and dir/stderr.txt). XDG_STATE_HOME is `dir`: the recovery
// records of restore and default (ops/recovery.hpp) are named after port and
// MACID, which parallel tests share.
inline ToolRun run_tool_in(const std::filesystem::path& dir, const std::string& args) {
  const std::string cmd = "cd '" + dir.string() + "' && XDG_STATE_HOME='" + dir.string() + "' '" +
                          std::string(LMCFG_TOOL_PATH) + "' " + args +
                          " >stdout.txt 2>stderr.txt </dev/null";
  const int rc = std::system(cmd.c_str());
  ToolRun r;
  r.exit_code = WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
  r.out = slurp(dir / "stdout.txt");
  r.err = slurp(dir / "stderr.txt");
  return r;
}

// The output of a shell command, stdout only (`git log ...`, `id -un`).
inline std::string shell_output(const std::string& cmd) {
  std::string out;
  if (FILE* p = ::popen(cmd.c_str(), "r")) {
    char buf[4096];
    std::size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
    ::pclose(p);
  }
  return out;
}

// The OS user the tools record as "who", as id(1) names it.
inline std::string os_user() {
  std::string u = shell_output("id -un");
  while (!u.empty() && u.back() == '\n') u.pop_back();
  return u;
}

inline int run_tool(const std::string& args) {
  const int rc = std::system((std::string(LMCFG_TOOL_PATH) + " " + args).c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

}  // namespace lmcfg::test
