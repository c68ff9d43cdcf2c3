#include "ops/platform.hpp"

#include <pwd.h>
#include <unistd.h>

#include <cstdlib>
#include <vector>

#include "ops/audit.hpp"

namespace lmcfg::ops {

namespace fs = std::filesystem;

Result<fs::path> state_dir() {
  const char* xdg = std::getenv("XDG_STATE_HOME");
  if (xdg && *xdg == '/') return fs::path(xdg) / "lmcfg";
  const char* home = std::getenv("HOME");
  if (home && *home) return fs::path(home) / ".local" / "state" / "lmcfg";
  return Error(Errc::file_error,
               "no place for the recovery record: neither $XDG_STATE_HOME (absolute) nor $HOME "
               "is set");
}

std::string current_user() {
  const uid_t uid = ::geteuid();
  long size = ::sysconf(_SC_GETPW_R_SIZE_MAX);
  std::vector<char> buf(size > 0 ? static_cast<std::size_t>(size) : 16384);
  passwd pw{};
  passwd* found = nullptr;
  if (::getpwuid_r(uid, &pw, buf.data(), buf.size(), &found) == 0 && found && found->pw_name &&
      *found->pw_name)
    return found->pw_name;
  if (const char* user = std::getenv("USER"); user && *user) return user;
  return std::to_string(uid);
}

}  // namespace lmcfg::ops
