#include "serve/tokens.hpp"

#include <fstream>
#include <sstream>

#include "common/bytes.hpp"
#include "common/text.hpp"
#include "serve/sha256.hpp"
#include "serve/token_file.hpp"

namespace lmcfg::serve {

const char* role_name(Role r) { return r == Role::operator_ ? "operator" : "viewer"; }

Result<Role> parse_role(std::string_view text) {
  if (text == "viewer") return Role::viewer;
  if (text == "operator") return Role::operator_;
  return Error(Errc::invalid_argument,
               "role '" + std::string(text) + "' is not one of viewer, operator");
}

Result<std::vector<TokenEntry>> load_tokens(const std::string& path) {
  LMCFG_TRY(check_owner_only(path));
  std::ifstream in(path);
  if (!in) return Error(Errc::file_error, path + ": cannot open the tokens file");
  std::vector<TokenEntry> out;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream words(line);
    TokenEntry e;
    std::string role, extra;
    words >> e.name >> role >> e.hash;
    auto r = parse_role(role);
    if (e.hash.size() != 64 || (words >> extra) || !r.ok()) {
      return Error(Errc::parse_error, path + ":" + std::to_string(n) +
                                          ": expected NAME ROLE SHA256 (written by lmcfg serve "
                                          "token add)");
    }
    // The name is who asked in commits, job records and pages (common/text.hpp).
    if (auto ok = check_line("token name", e.name, kMaxWhoBytes); !ok.ok())
      return Error(Errc::parse_error, path + ":" + std::to_string(n) + ": " + ok.error().message);
    e.role = *r;
    out.push_back(std::move(e));
  }
  return out;
}

Result<std::string> add_token(const std::string& path, const std::string& name, Role role) {
  LMCFG_TRY(check_line("token name", name, kMaxWhoBytes));
  if (name.empty() || name.find_first_of(" \t\r\n#") != std::string::npos)
    return Error(Errc::invalid_argument,
                 "token name '" + name + "' must be one word without blanks or '#'");
  if (file_exists(path)) {
    LMCFG_ASSIGN_OR_RETURN(auto existing, load_tokens(path));
    for (const auto& e : existing)
      if (e.name == name)
        return Error(Errc::invalid_argument,
                     path + ": a token named '" + name + "' exists already");
  }
  LMCFG_ASSIGN_OR_RETURN(std::string token, random_hex(32));
  LMCFG_TRY(append_owner_only(path, name + " " + role_name(role) + " " + sha256_hex(token) + "\n"));
  return token;
}

Result<std::string> random_hex(std::size_t bytes) {
  LMCFG_ASSIGN_OR_RETURN(auto raw, random_bytes(bytes));
  return to_hex(ByteView(raw.data(), raw.size()), '\0');
}

const TokenEntry* find_token(const std::vector<TokenEntry>& tokens, std::string_view token) {
  const std::string hash = sha256_hex(token);
  const TokenEntry* found = nullptr;
  for (const auto& e : tokens) {
    // Every entry compared in full: the time taken says nothing about which matched.
    unsigned diff = e.hash.size() == hash.size() ? 0u : 1u;
    for (std::size_t i = 0; i < hash.size() && i < e.hash.size(); ++i)
      diff |= static_cast<unsigned>(e.hash[i] ^ hash[i]);
    if (diff == 0) found = &e;
  }
  return found;
}

}  // namespace lmcfg::serve
