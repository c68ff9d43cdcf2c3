#include "serve/http.hpp"

#include <arpa/inet.h>
#include <httplib.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "common/bytes.hpp"
#include "serve/console_http.hpp"

namespace lmcfg::serve {

Result<ListenAddress> parse_listen(const std::string& text) {
  const std::string expected =
      "--listen '" + text + "' is not HOST:PORT (e.g. 127.0.0.1:8470, [::1]:8470; PORT 0..65535)";
  ListenAddress a;
  const auto colon = text.rfind(':');
  if (colon == std::string::npos || colon == 0) return Error(Errc::invalid_argument, expected);
  a.host = text.substr(0, colon);
  if (a.host.size() >= 2 && a.host.front() == '[' && a.host.back() == ']')
    a.host = a.host.substr(1, a.host.size() - 2);
  if (a.host.empty()) return Error(Errc::invalid_argument, expected);  // "[]:8470"
  const std::string digits = text.substr(colon + 1);
  if (digits.empty() || digits.size() > 5 ||
      digits.find_first_not_of("0123456789") != std::string::npos || std::stoi(digits) > 65535)
    return Error(Errc::invalid_argument, expected);
  a.port = std::stoi(digits);
  return a;
}

bool is_loopback(const std::string& host) {
  if (host == "localhost") return true;
  // Addresses, not names that look like them: "127.example.com" resolves to
  // whatever its DNS says, and would otherwise pass as loopback without
  // tokens or TLS.
  in_addr v4{};
  if (::inet_pton(AF_INET, host.c_str(), &v4) == 1) return (ntohl(v4.s_addr) >> 24) == 127;
  in6_addr v6{};
  return ::inet_pton(AF_INET6, host.c_str(), &v6) == 1 && IN6_IS_ADDR_LOOPBACK(&v6);
}

Result<void> check_exposure(const HttpOptions& opt, const std::string& listen_text) {
  if (opt.tls_cert.empty() != opt.tls_key.empty())
    return Error(Errc::invalid_argument,
                 "--tls-cert and --tls-key go together (the certificate and its private key)");
  if (is_loopback(opt.listen.host)) return {};
  // Other hosts see the bearer tokens and the plant's data on the wire: both
  // are required, not one.
  std::string missing;
  if (!opt.tokens) missing = "--tokens";
  if (opt.tls_cert.empty())
    missing += std::string(missing.empty() ? "" : " and ") + "--tls-cert/--tls-key";
  if (missing.empty()) return {};
  return Error(Errc::invalid_argument,
               "--listen " + listen_text +
                   " is not a loopback address: serving other hosts needs --tokens and "
                   "--tls-cert/--tls-key (missing: " +
                   missing + "; docs/serve.md \"Security model\")");
}

namespace {
Error tls_files_error(const HttpOptions& opt) {
  return Error(Errc::file_error, "--tls-cert " + opt.tls_cert + " / --tls-key " + opt.tls_key +
                                     ": cannot load them as a PEM certificate and its private "
                                     "key (readable files, the key matching the certificate)");
}
}  // namespace

Result<void> check_tls_files(const HttpOptions& opt) {
  if (opt.tls_cert.empty()) return {};
  // SSLServer loads both files in its constructor; is_valid() is false when
  // either cannot be read or the key does not belong to the certificate.
  if (!httplib::SSLServer(opt.tls_cert.c_str(), opt.tls_key.c_str()).is_valid())
    return tls_files_error(opt);
  return {};
}

struct HttpServer::Impl {
  Service& service;
  HttpOptions opt;
  std::unique_ptr<httplib::Server> owned;
  httplib::Server& server;
  std::unique_ptr<Console> console;  // its routes are registered by bind()
  // serve() and stop() from two threads (HttpServer::stop).
  std::atomic<bool> entered{false}, stop_asked{false}, returned{false};
  Impl(Service& s, HttpOptions o)
      : service(s),
        opt(std::move(o)),
        owned(opt.tls_cert.empty() ? std::make_unique<httplib::Server>()
                                   : std::make_unique<httplib::SSLServer>(opt.tls_cert.c_str(),
                                                                          opt.tls_key.c_str())),
        server(*owned) {}

  void log(const std::string& s) const {
    if (opt.log) opt.log(s);
  }

  static int status_of(const Error& e) {
    if (e.code == Errc::not_found) return 404;
    if (e.code == Errc::interrupted) return 503;  // the service is stopping
    if (e.code == Errc::invalid_argument) return 400;
    if (e.code == Errc::plan_refused) return 409;  // the plan cannot be executed as it stands
    return 500;
  }
  // {"error": message, "exit_code": N}: N is the CLI's exit code for the same error.
  static void error(httplib::Response& res, int status, const std::string& message, int exit_code) {
    res.status = status;
    res.set_content(Json{{"error", message}, {"exit_code", exit_code}}.dump() + "\n",
                    "application/json");
  }
  void error(httplib::Response& res, const Error& e) const {
    error(res, status_of(e), e.message, opt.exit_code ? opt.exit_code(e) : 70);
  }
  static void json(httplib::Response& res, const Json& j, int status = 200) {
    res.status = status;
    res.set_content(j.dump(2) + "\n", "application/json");
  }

  // "Bearer TOKEN": RFC 7235 §2.1, "It uses a case-insensitive token as a
  // means to identify the authentication scheme" (curl and browsers send
  // "Bearer", other clients may not).
  static constexpr std::string_view kBearer = "Bearer ";
  static bool bearer(std::string_view header) {
    return iequals(header.substr(0, kBearer.size()), kBearer);
  }

  // true: allowed; false: the 401 or 403 answer is written.
  bool authorized(const httplib::Request& req, httplib::Response& res) const {
    if (!opt.tokens) return true;
    const auto header = req.get_header_value("Authorization");
    if (!bearer(header)) {
      res.set_header("WWW-Authenticate", "Bearer");
      error(res, 401, "a bearer token is needed (Authorization: Bearer TOKEN)", 2);
      return false;
    }
    const TokenEntry* who =
        find_token(*opt.tokens, std::string_view(header).substr(kBearer.size()));
    if (!who) {
      res.set_header("WWW-Authenticate", "Bearer error=\"invalid_token\"");
      error(res, 401, "the bearer token is not in the tokens file", 2);
      return false;
    }
    if (req.method != "GET" && req.method != "HEAD" && who->role != Role::operator_) {
      error(res, 403,
            "token '" + who->name + "' has role viewer: " + req.method + " needs role operator", 2);
      return false;
    }
    return true;
  }

  // Who is asking: the token's name; without tokens "local".
  std::string who(const httplib::Request& req) const {
    if (!opt.tokens) return "local";
    const auto header = req.get_header_value("Authorization");
    const TokenEntry* t = find_token(*opt.tokens, std::string_view(header).substr(kBearer.size()));
    return t ? t->name : "local";
  }
  // The request's JSON object body ("" = {}); false: the 400 answer is written.
  static bool body(const httplib::Request& req, httplib::Response& res, Json& out) {
    if (req.body.empty()) {
      out = Json::object();
      return true;
    }
    out = Json::parse(req.body, nullptr, false);
    if (!out.is_object()) {
      error(res, 400, "the request body is not a JSON object", 2);
      return false;
    }
    return true;
  }
  static std::string text(const Json& j, const char* key, httplib::Response& res, bool& ok) {
    if (!j.contains(key) || j[key].is_null()) return "";
    if (j[key].is_string()) return j[key].get<std::string>();
    error(res, 400, std::string("\"") + key + "\" must be a string", 2);
    ok = false;
    return "";
  }

  void routes() {
    auto guard = [this](auto handler) {
      return [this, handler](const httplib::Request& req, httplib::Response& res) {
        if (authorized(req, res)) handler(req, res);
      };
    };
    server.Get("/metrics", guard([this](const httplib::Request&, httplib::Response& res) {
                 res.set_content(service.metrics(), "text/plain; version=0.0.4; charset=utf-8");
               }));
    server.Get("/api/v1/drives", guard([this](const httplib::Request&, httplib::Response& res) {
                 json(res, service.drives());
               }));
    // Drive names contain '/', so {name} is the rest of the path; the
    // /history and /backup endpoints are the same path with a suffix.
    server.Get(R"(/api/v1/drives/(.+)/history)",
               guard([this](const httplib::Request& req, httplib::Response& res) {
                 auto h = service.history(req.matches[1]);
                 h.ok() ? json(res, *h) : error(res, h.error());
               }));
    server.Get(R"(/api/v1/drives/(.+)/diff)",
               guard([this](const httplib::Request& req, httplib::Response& res) {
                 if (!req.has_param("from")) {
                   error(res, 400, "from=REV is needed (to=REV or to=live, default live)", 2);
                   return;
                 }
                 const std::string to = req.has_param("to") ? req.get_param_value("to") : "live";
                 auto d = service.diff(req.matches[1], req.get_param_value("from"), to);
                 d.ok() ? json(res, *d) : error(res, d.error());
               }));
    server.Get(R"(/api/v1/drives/(.+)/report)",
               guard([this](const httplib::Request& req, httplib::Response& res) {
                 auto r = service.report_html(req.matches[1], req.get_param_value("rev"));
                 if (!r.ok()) return error(res, r.error());
                 res.set_content(*r, "text/html; charset=utf-8");
               }));
    server.Get(R"(/api/v1/drives/(.+))",
               guard([this](const httplib::Request& req, httplib::Response& res) {
                 auto d = service.drive(req.matches[1]);
                 d.ok() ? json(res, *d) : error(res, d.error());
               }));
    server.Post(R"(/api/v1/drives/(.+)/backup)",
                guard([this](const httplib::Request& req, httplib::Response& res) {
                  auto id = service.backup_drive(req.matches[1], who(req));
                  id.ok() ? json(res, Json{{"job", *id}}, 202) : error(res, id.error());
                }));
    server.Post(R"(/api/v1/lines/(.+)/backup)",
                guard([this](const httplib::Request& req, httplib::Response& res) {
                  auto id = service.backup_line(req.matches[1], who(req));
                  id.ok() ? json(res, Json{{"job", *id}}, 202) : error(res, id.error());
                }));
    server.Post(R"(/api/v1/drives/(.+)/plan)",
                guard([this](const httplib::Request& req, httplib::Response& res) {
                  Json b;
                  bool ok = body(req, res, b);
                  const std::string rev = ok ? text(b, "rev", res, ok) : "";
                  if (!ok) return;
                  auto p = service.plan(req.matches[1], rev, who(req));
                  p.ok() ? json(res, *p) : error(res, p.error());
                }));
    server.Post(R"(/api/v1/plans/([0-9a-f]+)/execute)",
                guard([this](const httplib::Request& req, httplib::Response& res) {
                  Json b;
                  bool ok = body(req, res, b);
                  Service::ExecuteRequest er;
                  er.plan_id = req.matches[1];
                  er.audit.who = who(req);
                  if (ok) er.audit.reason = text(b, "reason", res, ok);
                  if (ok) er.audit.ticket = text(b, "ticket", res, ok);
                  if (!ok) return;
                  if (b.contains("skip_incompatible")) {
                    if (!b["skip_incompatible"].is_boolean())
                      return error(res, 400, "\"skip_incompatible\" must be true or false", 2);
                    er.skip_incompatible = b["skip_incompatible"].get<bool>();
                  }
                  auto id = service.execute(er);
                  id.ok() ? json(res, Json{{"job", *id}}, 202) : error(res, id.error());
                }));
    approve_route(guard);
    server.Get(R"(/api/v1/jobs/([0-9]+))",
               guard([this](const httplib::Request& req, httplib::Response& res) {
                 auto j = service.job(req.matches[1]);
                 j.ok() ? json(res, *j) : error(res, j.error());
               }));
  }

  // POST /api/v1/drives/{name}/approve {"rev", "reason", "ticket"}: the
  // position's approved configuration (docs/serve.md "Approved configurations").
  template <class Guard>
  void approve_route(Guard& guard) {
    server.Post(R"(/api/v1/drives/(.+)/approve)",
                guard([this](const httplib::Request& req, httplib::Response& res) {
                  Json b;
                  bool ok = body(req, res, b);
                  Service::ApproveRequest ar;
                  ar.who = who(req);
                  if (ok) ar.rev = text(b, "rev", res, ok);
                  if (ok) ar.reason = text(b, "reason", res, ok);
                  if (ok) ar.ticket = text(b, "ticket", res, ok);
                  if (!ok) return;
                  auto a = service.approve(req.matches[1], ar);
                  a.ok() ? json(res, *a) : error(res, a.error());
                }));
  }

  // Errors as JSON, the request log, the body limit and the socket options.
  void server_options() {
    server.set_error_handler([](const httplib::Request& req, httplib::Response& res) {
      if (!res.body.empty()) return;  // a handler's own answer
      if (res.status == 413) {
        error(res, 413, "request body too large", 2);
      } else if (res.status == 404) {
        error(res, 404, "no such resource: " + req.method + " " + req.path, 2);
      } else {
        error(res, res.status, "HTTP " + std::to_string(res.status), 2);
      }
    });
    server.set_logger([this](const httplib::Request& req, const httplib::Response& res) {
      log("http " + req.remote_addr + " " + req.method + " " + req.path + " " +
          std::to_string(res.status));
    });
    server.set_payload_max_length(opt.max_body);
    // cpp-httplib's default sets SO_REUSEPORT, with which a second lmcfg serve
    // on the same port binds as well and the kernel shares the connections
    // between the two: SO_REUSEADDR only (a restart still binds at once).
    server.set_socket_options([](socket_t sock) {
      int yes = 1;
      ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    });
  }
};

HttpServer::HttpServer(Service& service, HttpOptions opt)
    : impl_(std::make_unique<Impl>(service, std::move(opt))) {
  impl_->routes();
  impl_->server_options();
}
HttpServer::~HttpServer() = default;

Result<int> HttpServer::bind() {
  if (!impl_->console) {
    LMCFG_ASSIGN_OR_RETURN(impl_->console,
                           Console::create(impl_->service, impl_->opt.tokens, impl_->opt.console));
    register_console_routes(impl_->server, *impl_->console);
  }
  const auto& a = impl_->opt.listen;
  if (!impl_->server.is_valid()) return tls_files_error(impl_->opt);
  const int port = a.port == 0 ? impl_->server.bind_to_any_port(a.host.c_str())
                               : (impl_->server.bind_to_port(a.host.c_str(), a.port) ? a.port : -1);
  if (port < 0)
    return Error(Errc::io_error, "cannot listen on " + a.host + ":" + std::to_string(a.port) +
                                     " (address in use or not on this host)");
  return port;
}

// cpp-httplib's stop() acts only on a server whose loop runs: a stop() that
// comes before the loop starts would be lost and serve() would never return
// (a SIGTERM right after the start, a test's short-lived server). Each side
// announces itself before it looks at the other, so one of them sees the other.
void HttpServer::serve() {
  impl_->entered = true;
  if (!impl_->stop_asked) impl_->server.listen_after_bind();
  impl_->returned = true;
}

void HttpServer::stop() {
  impl_->stop_asked = true;
  if (!impl_->entered) return;  // serve() has not begun: it will see stop_asked
  while (!impl_->server.is_running() && !impl_->returned)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  impl_->server.stop();
}

}  // namespace lmcfg::serve
