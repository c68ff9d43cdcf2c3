#pragma once
// Routes of lmcfg serve's HTTP server: a method and a path pattern to a
// handler. Patterns are literal text with placeholders, matched against the
// whole decoded path without regular expressions (std::regex recurses per
// character and a long path could exhaust the stack):
//   {any}  one or more bytes, '/' included (a drive name "press3/z-axis")
//   {hex}  one or more of 0-9 a-f
//   {num}  one or more of 0-9
// The placeholders' texts are the request's matches[1...] (matches[0] is the path).
#include <functional>
#include <string>
#include <vector>

#include "web/web_message.hpp"

namespace lmcfg::web {

using Handler = std::function<void(const Request&, Response&)>;

// The placeholders' texts when `path` matches `pattern` as a whole, else false.
bool match_pattern(std::string_view pattern, std::string_view path,
                   std::vector<std::string>& groups);

class Router {
 public:
  void Get(std::string pattern, Handler h) { add("GET", std::move(pattern), std::move(h)); }
  void Post(std::string pattern, Handler h) { add("POST", std::move(pattern), std::move(h)); }
  void add(std::string method, std::string pattern, Handler h);

  enum class Outcome { handled, not_found, method_not_allowed };
  // Runs the first route whose method and pattern match (HEAD runs GET's;
  // the server drops the body). not_found: no pattern matches the path;
  // method_not_allowed: one does, for other methods (`allow` lists them).
  // The handler's exceptions propagate to the caller.
  Outcome dispatch(Request& req, Response& res, std::string* allow = nullptr) const;

 private:
  struct Route {
    std::string method, pattern;
    Handler handler;
  };
  std::vector<Route> routes_;
};

}  // namespace lmcfg::web
