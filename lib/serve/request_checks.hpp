#pragma once
// The checks every request to a loopback server of lmcfg passes before its
// route (docs/serve.md "Security model"): `lmcfg serve` and `lmcfg ui` both
// ask these, so a browser meets the same rules on both.
#include <optional>
#include <string>
#include <vector>

#include "web/web_message.hpp"

namespace lmcfg::serve {

// Why a request is refused: the HTTP status and the message.
struct Refusal {
  int status = 0;
  std::string message;
};

// Through DNS rebinding (evil.example resolving to 127.0.0.1) a web page's
// requests reach a loopback port with the page's own name as Host: only the
// server's own names (`hosts`, lower case "127.0.0.1:8470") are served (421).
std::optional<Refusal> check_host(const web::Request& req, const std::vector<std::string>& hosts);

// A state-changing request from a browser must come from a page of this
// server; curl and scripts send neither header and pass. Sec-Fetch-Site,
// which a page cannot set, decides where a browser sends it; otherwise Origin
// must be this server's (403).
std::optional<Refusal> check_origin(const web::Request& req);

// GET, HEAD and OPTIONS change nothing.
bool safe_method(const std::string& method);

}  // namespace lmcfg::serve
