#pragma once
// Bearer tokens of lmcfg serve (docs/serve.md "Security"): a tokens file holds
// one line per token, "NAME ROLE SHA256", never the token itself. `viewer`
// may GET, `operator` may also POST.
#include <string>
#include <string_view>
#include <vector>

#include "common/result.hpp"

namespace lmcfg::serve {

enum class Role { viewer, operator_ };
const char* role_name(Role r);                   // "viewer", "operator"
Result<Role> parse_role(std::string_view text);  // Errc::invalid_argument naming both

struct TokenEntry {
  std::string name;
  Role role = Role::viewer;
  std::string hash;  // sha256_hex of the token
};

// Errc::file_error when unreadable or writable by its group or others (the
// message names the fix, chmod 600 FILE), Errc::parse_error naming FILE:LINE
// for a bad line.
Result<std::vector<TokenEntry>> load_tokens(const std::string& path);
// A new random token (32 bytes from /dev/urandom as hex) for `name`, its hash
// appended to `path` (created with mode 0600). Returns the token, shown once.
// Errc::invalid_argument for a name in use or with blanks.
Result<std::string> add_token(const std::string& path, const std::string& name, Role role);
// `bytes` random bytes from /dev/urandom as hex digits (upper case) (tokens, console
// session ids and CSRF tokens). Errc::io_error when it cannot be read.
Result<std::string> random_hex(std::size_t bytes);
// The entry whose hash matches `token`; nullptr when none does.
const TokenEntry* find_token(const std::vector<TokenEntry>& tokens, std::string_view token);

}  // namespace lmcfg::serve
