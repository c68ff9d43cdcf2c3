#include "serve/http.hpp"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <mutex>
#include <thread>

#include "common/bytes.hpp"
#include "common/text.hpp"
#include "serve/console_http.hpp"
#include "serve/request_checks.hpp"
#include "web/web_router.hpp"
#include "web/web_server.hpp"
#include "web/web_tls.hpp"

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
  return web::is_loopback_address(host);
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

Result<void> check_tls_files(const HttpOptions& opt) {
  if (opt.tls_cert.empty()) return {};
  LMCFG_ASSIGN_OR_RETURN(auto ctx, web::TlsContext::load(opt.tls_cert, opt.tls_key));
  (void)ctx;
  return {};
}

namespace {

using web::Request;
using web::Response;

// nlohmann::json throws on a string that is not UTF-8; every text that
// reaches an answer is UTF-8 by the parser's checks, and whatever a lower
// layer adds (an archive's commit message) is replaced, never thrown.
std::string dump(const Json& j, int indent) {
  return j.dump(indent, ' ', false, Json::error_handler_t::replace);
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

}  // namespace

struct HttpServer::Impl {
  Service& service;
  HttpOptions opt;
  web::Router router;
  std::unique_ptr<web::Server> server;
  std::shared_ptr<web::TlsContext> tls;
  std::unique_ptr<Console> console;  // its routes are registered by bind()
  int port = 0;                      // bound
  std::vector<std::string> hosts;    // the Host values served without tokens
  std::mutex mu;                     // server, stop_asked (stop() from another thread)
  bool stop_asked = false;
  Impl(Service& s, HttpOptions o) : service(s), opt(std::move(o)) {}

  void log(const std::string& s) const {
    if (opt.log) opt.log(log_text(s));  // client text escaped (common/text.hpp)
  }

  static int status_of(const Error& e) {
    if (line_busy(e)) return 503;  // a live read waits for its line: ask again
    if (e.code == Errc::not_found) return 404;
    if (e.code == Errc::interrupted) return 503;  // the service is stopping
    if (e.code == Errc::invalid_argument) return 400;
    if (e.code == Errc::plan_refused) return 409;  // the plan cannot be executed as it stands
    return 500;
  }
  // {"error": message, "exit_code": N}: N is the CLI's exit code for the same error.
  static void error(Response& res, int status, const std::string& message, int exit_code) {
    res.status = status;
    res.set_content(dump(Json{{"error", message}, {"exit_code", exit_code}}, -1) + "\n",
                    "application/json");
  }
  void error(Response& res, const Error& e) const {
    const int code = opt.exit_code ? opt.exit_code(e) : 70;
    const auto busy = line_busy(e);
    if (!busy) return error(res, status_of(e), e.message, code);
    // RFC 9110 §10.2.3: when to ask again; the job that has the answer then.
    res.status = 503;
    res.set_header("Retry-After", std::to_string(busy->retry_after_s));
    Json j{{"error", e.message}, {"exit_code", code}};
    if (!busy->job.empty()) {
      j["job"] = busy->job;
      j["job_url"] = "/api/v1/jobs/" + busy->job;
    }
    res.set_content(dump(j, -1) + "\n", "application/json");
  }
  static void json(Response& res, const Json& j, int status = 200) {
    res.status = status;
    res.set_content(dump(j, 2) + "\n", "application/json");
  }

  // "Bearer TOKEN": RFC 7235 §2.1, "It uses a case-insensitive token as a
  // means to identify the authentication scheme" (curl and browsers send
  // "Bearer", other clients may not).
  static constexpr std::string_view kBearer = "Bearer ";
  static bool bearer(std::string_view header) {
    return iequals(header.substr(0, kBearer.size()), kBearer);
  }

  // true: allowed; false: the 401 or 403 answer is written.
  bool authorized(const Request& req, Response& res) const {
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
    if (!safe_method(req.method) && who->role != Role::operator_) {
      error(res, 403,
            "token '" + who->name + "' has role viewer: " + req.method + " needs role operator", 2);
      return false;
    }
    return true;
  }

  // Who is asking: the token's name; without tokens "local".
  std::string who(const Request& req) const {
    if (!opt.tokens) return "local";
    const auto header = req.get_header_value("Authorization");
    const TokenEntry* t = find_token(*opt.tokens, std::string_view(header).substr(kBearer.size()));
    return t ? t->name : "local";
  }
  // The request's JSON object body ("" = {}); false: the 400 answer is written.
  static bool body(const Request& req, Response& res, Json& out) {
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
  static std::string text(const Json& j, const char* key, Response& res, bool& ok) {
    if (!j.contains(key) || j[key].is_null()) return "";
    if (j[key].is_string()) return j[key].get<std::string>();
    error(res, 400, std::string("\"") + key + "\" must be a string", 2);
    ok = false;
    return "";
  }

  void routes();
  void position_routes();
  template <class Handler>
  web::Handler guard(Handler handler);

  // ---- the checks every request passes before its route (docs/serve.md "Security model")

  // Without tokens every client is an operator, which only loopback makes
  // acceptable; but a web page in a browser on the same host is a client too.
  // Through DNS rebinding (evil.example resolving to 127.0.0.1) its requests
  // reach this port with its own name as Host: only this service's own names
  // are served.
  bool host_ok(const Request& req, Response& res) const {
    if (opt.tokens) return true;
    const auto refused = check_host(req, hosts);
    if (refused) error(res, refused->status, refused->message, 2);
    return !refused;
  }
  // A state-changing request from a browser must come from a page of this
  // service (serve/request_checks.hpp).
  bool origin_ok(const Request& req, Response& res) const {
    const auto refused = check_origin(req);
    if (refused) error(res, refused->status, refused->message, 2);
    return !refused;
  }

  void handle(Request& req, Response& res) {
    if (host_ok(req, res) && origin_ok(req, res)) {
      std::string allow;
      switch (router.dispatch(req, res, &allow)) {
        case web::Router::Outcome::handled:
          break;
        case web::Router::Outcome::not_found:
          error(res, 404, "no such resource: " + req.method + " " + req.path, 2);
          break;
        case web::Router::Outcome::method_not_allowed:
          res.set_header("Allow", allow);
          error(res, 405, req.method + " is not allowed on " + req.path + " (only " + allow + ")",
                2);
          break;
      }
    }
    // RFC 6797: browsers that came over HTTPS keep to it.
    if (req.tls) res.set_header("Strict-Transport-Security", "max-age=31536000");
    log("http " + req.remote_addr + " " + web::printable(req.method) + " " +
        web::printable(req.target) + " " + std::to_string(res.status));
  }
};

// API POSTs carry JSON: a form or text/plain body (what a cross-site HTML
// form can send without asking) is refused before any route runs.
template <class Handler>
web::Handler HttpServer::Impl::guard(Handler handler) {
  return [this, handler](const Request& req, Response& res) {
    if (!authorized(req, res)) return;
    if (!safe_method(req.method) && (req.has_header("Content-Type") || !req.body.empty())) {
      const std::string type = lower(req.get_header_value("Content-Type"));
      if (type.substr(0, type.find(';')) != "application/json")
        return error(res, 415,
                     "the request body must be application/json, not '" +
                         req.get_header_value("Content-Type") + "'",
                     2);
    }
    handler(req, res);
  };
}

void HttpServer::Impl::routes() {
  router.Get("/metrics", guard([this](const Request&, Response& res) {
               res.set_content(service.metrics(), "text/plain; version=0.0.4; charset=utf-8");
             }));
  router.Get("/api/v1/drives", guard([this](const Request&, Response& res) {
               std::string text = service.drives_text();
               text += '\n';  // as json() ends its answers
               res.set_content(std::move(text), "application/json");
             }));
  // Drive names contain '/', so {name} is the rest of the path; the
  // /history and /backup endpoints are the same path with a suffix.
  router.Get("/api/v1/drives/{any}/history", guard([this](const Request& req, Response& res) {
               auto h = service.history(req.matches[1]);
               h.ok() ? json(res, *h) : error(res, h.error());
             }));
  router.Get("/api/v1/drives/{any}/diff", guard([this](const Request& req, Response& res) {
               if (!req.has_param("from")) {
                 error(res, 400, "from=REV is needed (to=REV or to=live, default live)", 2);
                 return;
               }
               const std::string to = req.has_param("to") ? req.get_param_value("to") : "live";
               auto d = service.diff(req.matches[1], req.get_param_value("from"), to);
               d.ok() ? json(res, *d) : error(res, d.error());
             }));
  router.Get("/api/v1/drives/{any}/report", guard([this](const Request& req, Response& res) {
               auto r = service.report_html(req.matches[1], req.get_param_value("rev"));
               if (!r.ok()) return error(res, r.error());
               res.set_content(*r, "text/html; charset=utf-8");
             }));
  router.Get("/api/v1/drives/{any}", guard([this](const Request& req, Response& res) {
               auto d = service.drive(req.matches[1]);
               d.ok() ? json(res, *d) : error(res, d.error());
             }));
  router.Post("/api/v1/drives/{any}/backup", guard([this](const Request& req, Response& res) {
                auto id = service.backup_drive(req.matches[1], who(req));
                id.ok() ? json(res, Json{{"job", *id}}, 202) : error(res, id.error());
              }));
  router.Post("/api/v1/lines/{any}/backup", guard([this](const Request& req, Response& res) {
                auto id = service.backup_line(req.matches[1], who(req));
                id.ok() ? json(res, Json{{"job", *id}}, 202) : error(res, id.error());
              }));
  router.Post("/api/v1/drives/{any}/plan", guard([this](const Request& req, Response& res) {
                Json b;
                bool ok = body(req, res, b);
                const std::string rev = ok ? text(b, "rev", res, ok) : "";
                if (!ok) return;
                auto p = service.plan(req.matches[1], rev, who(req));
                p.ok() ? json(res, *p) : error(res, p.error());
              }));
  router.Post("/api/v1/plans/{hex}/execute", guard([this](const Request& req, Response& res) {
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
  position_routes();
}

// What an operator decides about a position: its approved configuration, the
// automatic retry of a failed restore; and the jobs.
void HttpServer::Impl::position_routes() {
  // The position's approved configuration (docs/serve.md "Approved configurations").
  router.Post("/api/v1/drives/{any}/approve", guard([this](const Request& req, Response& res) {
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
  // The automatic retry of a failed restore, waiting for the drive (docs/serve.md).
  router.Post("/api/v1/drives/{any}/retry/cancel", guard([this](const Request& req, Response& res) {
                auto c = service.cancel_retry(req.matches[1], who(req));
                c.ok() ? json(res, *c) : error(res, c.error());
              }));
  router.Get("/api/v1/jobs/{num}", guard([this](const Request& req, Response& res) {
               auto j = service.job(req.matches[1]);
               j.ok() ? json(res, *j) : error(res, j.error());
             }));
}

HttpServer::HttpServer(Service& service, HttpOptions opt)
    : impl_(std::make_unique<Impl>(service, std::move(opt))) {
  impl_->routes();
}
HttpServer::~HttpServer() = default;

Result<int> HttpServer::bind() {
  auto& im = *impl_;
  if (!im.console) {
    LMCFG_ASSIGN_OR_RETURN(im.console, Console::create(im.service, im.opt.tokens, im.opt.console));
    register_console_routes(im.router, *im.console);
  }
  if (!im.opt.tls_cert.empty() && !im.tls) {
    LMCFG_ASSIGN_OR_RETURN(im.tls, web::TlsContext::load(im.opt.tls_cert, im.opt.tls_key));
  }
  web::ServerOptions so = im.opt.server;
  so.limits.max_body = im.opt.max_body;
  so.tls = im.tls;
  so.handle = [&im](Request& req, Response& res) { im.handle(req, res); };
  so.error_page = [](int status, const std::string& message, Response& res) {
    Impl::error(res, status, message, 2);
  };
  so.log = im.opt.log;
  {
    std::lock_guard<std::mutex> lock(im.mu);
    im.server = std::make_unique<web::Server>(std::move(so));
  }
  const auto& a = im.opt.listen;
  LMCFG_ASSIGN_OR_RETURN(im.port, im.server->bind(a.host, a.port));
  // The names a browser may use for this service: the listen address, and
  // for a loopback address "localhost" and the loopback address of its family.
  const std::string p = ":" + std::to_string(im.port);
  auto add = [&](const std::string& h) {
    const bool v6 = h.find(':') != std::string::npos;
    im.hosts.push_back(lower(v6 ? "[" + h + "]" : h) + p);
  };
  add(a.host);
  for (const auto& h : im.opt.allowed_hosts) im.hosts.push_back(lower(h));
  if (is_loopback(a.host)) {
    add("localhost");
    if (a.host == "localhost") {
      add("127.0.0.1");
      add("::1");
    }
  }
  return im.port;
}

// stop() may come from another thread at any moment, before bind() too:
// the server object is made under the lock, and web::Server::serve returns
// at once after a stop() that came before it.
void HttpServer::serve() {
  web::Server* s = nullptr;
  {
    std::lock_guard<std::mutex> lock(impl_->mu);
    if (impl_->stop_asked || !impl_->server) return;
    s = impl_->server.get();
  }
  s->serve();
}

void HttpServer::stop() {
  std::lock_guard<std::mutex> lock(impl_->mu);
  impl_->stop_asked = true;
  if (impl_->server) impl_->server->stop();
}

std::string HttpServer::answer(std::string_view bytes, const std::string& remote_addr, bool tls) {
  web::Limits limits = impl_->opt.server.limits;
  limits.max_body = impl_->opt.max_body;
  web::RequestParser parser(limits);
  std::string out;
  auto state = parser.feed(bytes);
  while (state == web::RequestParser::State::complete) {
    Request req = std::move(parser.request());
    req.remote_addr = remote_addr;
    req.tls = tls;
    Response res;
    impl_->handle(req, res);
    out += web::serialize(res, req.method == "HEAD");
    parser.next();
    state = parser.parse();
  }
  if (state == web::RequestParser::State::error) {
    Response res;
    Impl::error(res, parser.error_status(), parser.error_message(), 2);
    res.close = true;
    out += web::serialize(res, false);
  }
  return out;
}

web::ServerStats HttpServer::stats() const {
  return impl_->server ? impl_->server->stats() : web::ServerStats{};
}

}  // namespace lmcfg::serve
