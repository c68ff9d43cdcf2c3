#include "ops/audit.hpp"

#include <pwd.h>
#include <unistd.h>

#include <cstdlib>
#include <vector>

#include "common/text.hpp"

namespace lmcfg::ops {

std::string trailers(const Audit& a) {
  std::string out;
  if (!a.who.empty()) out += "Operator: " + one_line(a.who) + "\n";
  if (!a.reason.empty()) out += "Reason: " + one_line(a.reason) + "\n";
  if (!a.ticket.empty()) out += "Ticket: " + one_line(a.ticket) + "\n";
  return out;
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
