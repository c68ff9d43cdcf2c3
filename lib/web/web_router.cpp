#include "web/web_router.hpp"

namespace lmcfg::web {

namespace {

bool in_class(std::string_view kind, char c) {
  if (kind == "{num}") return c >= '0' && c <= '9';
  if (kind == "{hex}") return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f');
  return true;  // {any}
}

// Backtracking over at most a few placeholders: each tries its longest
// extent first (a drive name may contain "/history"-like segments only
// before the route's own suffix).
bool match_from(std::string_view pattern, std::string_view path, std::vector<std::string>& groups) {
  const auto open = pattern.find('{');
  if (open == std::string_view::npos) return pattern == path;
  if (path.substr(0, open) != pattern.substr(0, open)) return false;
  const auto close = pattern.find('}', open);
  const std::string_view kind = pattern.substr(open, close - open + 1);
  const std::string_view rest_pattern = pattern.substr(close + 1);
  const std::string_view rest_path = path.substr(open);
  std::size_t longest = 0;
  while (longest < rest_path.size() && in_class(kind, rest_path[longest])) ++longest;
  for (std::size_t n = longest; n >= 1; --n) {
    groups.emplace_back(rest_path.substr(0, n));
    if (match_from(rest_pattern, rest_path.substr(n), groups)) return true;
    groups.pop_back();
  }
  return false;
}

}  // namespace

bool match_pattern(std::string_view pattern, std::string_view path,
                   std::vector<std::string>& groups) {
  groups.clear();
  groups.emplace_back(path);
  if (match_from(pattern, path, groups)) return true;
  groups.clear();
  return false;
}

void Router::add(std::string method, std::string pattern, Handler h) {
  routes_.push_back(Route{std::move(method), std::move(pattern), std::move(h)});
}

Router::Outcome Router::dispatch(Request& req, Response& res, std::string* allow) const {
  const std::string& method = req.method == "HEAD" ? std::string("GET") : req.method;
  bool path_known = false;
  std::string methods;
  std::vector<std::string> groups;
  for (const auto& r : routes_) {
    if (!match_pattern(r.pattern, req.path, groups)) continue;
    if (r.method == method) {
      req.matches = std::move(groups);
      r.handler(req, res);
      return Outcome::handled;
    }
    path_known = true;
    if (methods.find(r.method) == std::string::npos)
      methods += (methods.empty() ? "" : ", ") + r.method;
  }
  if (!path_known) return Outcome::not_found;
  if (allow) *allow = methods;
  return Outcome::method_not_allowed;
}

}  // namespace lmcfg::web
