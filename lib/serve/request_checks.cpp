#include "serve/request_checks.hpp"

#include <algorithm>
#include <cctype>

namespace lmcfg::serve {

namespace {

std::string lowered(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

}  // namespace

bool safe_method(const std::string& m) { return m == "GET" || m == "HEAD" || m == "OPTIONS"; }

std::optional<Refusal> check_host(const web::Request& req, const std::vector<std::string>& hosts) {
  const std::string host = lowered(req.get_header_value("Host"));
  if (std::find(hosts.begin(), hosts.end(), host) != hosts.end()) return std::nullopt;
  return Refusal{421, "the Host header '" + host + "' is not this service's address (" +
                          (hosts.empty() ? std::string("none") : hosts.front()) +
                          "): without --tokens only requests to the listen address are served, "
                          "so that a web page cannot reach the drives through another name"};
}

// (Pages with Referrer-Policy: no-referrer make a browser's form POST carry
// "Origin: null": Sec-Fetch-Site says same-origin for it.)
std::optional<Refusal> check_origin(const web::Request& req) {
  if (safe_method(req.method)) return std::nullopt;
  if (req.has_header("Sec-Fetch-Site")) {
    const std::string site = lowered(req.get_header_value("Sec-Fetch-Site"));
    if (site == "same-origin" || site == "none") return std::nullopt;
    return Refusal{403, "cross-site request refused: Sec-Fetch-Site is '" + site +
                            "', a state-changing request must come from this service's own pages"};
  }
  const std::string own =
      std::string(req.tls ? "https://" : "http://") + lowered(req.get_header_value("Host"));
  if (req.has_header("Origin") && lowered(req.get_header_value("Origin")) != own)
    return Refusal{403, "cross-origin request refused: Origin '" + req.get_header_value("Origin") +
                            "' is not this service's origin '" + own + "'"};
  return std::nullopt;
}

}  // namespace lmcfg::serve
