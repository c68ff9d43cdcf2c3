#include "ui_platform.hpp"

#include <spawn.h>
#include <sys/wait.h>

#include <cstdlib>
#include <vector>

extern char** environ;

namespace lmcfg::cli {

bool open_browser(const std::string& url) {
  // xdg-open returns once the browser is asked (or started in the
  // background); its exit status says whether it found one.
  std::string prog = "xdg-open";
  std::vector<char*> argv{prog.data(), const_cast<char*>(url.c_str()), nullptr};
  pid_t pid = 0;
  if (posix_spawnp(&pid, "xdg-open", nullptr, nullptr, argv.data(), environ) != 0) return false;
  int status = 0;
  if (waitpid(pid, &status, 0) != pid) return false;
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

std::string default_ui_folder() {
  const char* home = std::getenv("HOME");
  return home && *home ? std::string(home) + "/lmcfg" : "lmcfg";
}

}  // namespace lmcfg::cli
