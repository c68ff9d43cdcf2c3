// lmcfg ui's routes on lmcfg's own HTTP server (ui/server.hpp).
#include "ui/server.hpp"

#include <algorithm>
#include <fstream>
#include <iterator>
#include <mutex>

#include "serve/console.hpp"
#include "serve/http.hpp"
#include "serve/request_checks.hpp"
#include "serve/tokens.hpp"
#include "ui/pages.hpp"
#include "ui/upload.hpp"
#include "web/web_router.hpp"

namespace lmcfg::ui {

using web::Request;
using web::Response;

namespace {

std::string lower_text(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// Equal without telling by its time where they differ.
bool same_secret(std::string_view a, std::string_view b) {
  if (a.size() != b.size() || a.empty()) return false;
  unsigned char d = 0;
  for (std::size_t i = 0; i < a.size(); ++i) d |= static_cast<unsigned char>(a[i] ^ b[i]);
  return d == 0;
}

void security_headers(Response& res, std::string_view csp) {
  res.set_header("Content-Security-Policy", std::string(csp));
  res.set_header("X-Content-Type-Options", "nosniff");
  res.set_header("Referrer-Policy", "no-referrer");
  res.set_header("Cache-Control", "no-store");
}

void html(Response& res, const std::string& body, int status = 200) {
  security_headers(res, serve::Console::content_security_policy());
  res.status = status;
  res.set_content(body, "text/html; charset=utf-8");
}

void redirect(Response& res, const std::string& to) {
  security_headers(res, serve::Console::content_security_policy());
  res.status = 303;
  res.set_header("Location", to);
  res.set_content("", "text/plain");
}

void json_answer(Response& res, const Json& j, int status = 200) {
  security_headers(res, serve::Console::content_security_policy());
  res.status = status;
  res.set_content(j.dump(2, ' ', false, Json::error_handler_t::replace) + "\n", "application/json");
}

// The address asked for without its token (the path's characters kept,
// the other parameters encoded again), so the token leaves the address bar.
std::string without_token(const Request& req) {
  std::string to;
  for (unsigned char c : req.path)
    to += (c > 0x20 && c < 0x7F && c != '"' && c != '\\' && c != '?' && c != '#')
              ? std::string(1, static_cast<char>(c))
              : serve::url_encode(std::string(1, static_cast<char>(c)));
  if (to.empty() || to[0] != '/' || (to.size() > 1 && to[1] == '/')) to = "/";
  bool first = true;
  for (const auto& [k, v] : req.params) {
    if (k == "token") continue;
    to += (first ? "?" : "&") + serve::url_encode(k) + "=" + serve::url_encode(v);
    first = false;
  }
  return to;
}

int status_for(const Error& e) {
  if (e.code == Errc::not_found) return 404;
  if (e.code == Errc::invalid_argument) return 400;
  if (e.code == Errc::plan_refused) return 409;
  if (e.code == Errc::interrupted) return 503;
  return 500;
}

std::string field_of(const web::Params& p, const char* key) {
  auto it = p.find(key);
  return it == p.end() ? "" : it->second;
}

}  // namespace

struct UiServer::Impl {
  Desk& desk;
  UiOptions opt;
  web::Router router;
  std::unique_ptr<web::Server> server;
  std::string session, csrf;  // the cookie's value, the forms' value
  std::vector<std::string> hosts;
  int port = 0;
  std::mutex mu;
  bool stop_asked = false;

  Impl(Desk& d, UiOptions o) : desk(d), opt(std::move(o)) {}

  void log(const std::string& s) const {
    if (opt.log) opt.log(s);
  }
  int code_of(const Error& e) const { return opt.exit_code ? opt.exit_code(e) : 70; }

  void fail_page(Response& res, const std::string& title, const Error& e,
                 const std::string& back = "/") {
    html(res, pages::failure(title, e, code_of(e), back, csrf), status_for(e));
  }

  // The form's fields, checked: a form of valid UTF-8 with this process's
  // CSRF value; nullopt with the refusal written.
  std::optional<web::Params> form(const Request& req, Response& res) {
    const std::string type = req.get_header_value("Content-Type");
    if (type.substr(0, type.find(';')) != "application/x-www-form-urlencoded") {
      fail_page(res, "Refused",
                Error(Errc::invalid_argument,
                      "a form must be sent as application/x-www-form-urlencoded"));
      res.status = 415;
      return std::nullopt;
    }
    web::Params p;
    std::string bad;
    if (!web::parse_query(req.body, p, bad, true)) {
      fail_page(res, "Refused",
                Error(Errc::invalid_argument, "the form's field '" + bad +
                                                  "' is malformed, not valid UTF-8 or has a "
                                                  "control character"));
      return std::nullopt;
    }
    if (!csrf_ok(field_of(p, "csrf"), res)) return std::nullopt;
    return p;
  }

  // Whether a form's CSRF value is this process's; the refusal (403) written when not.
  bool csrf_ok(const std::string& sent, Response& res) {
    if (same_secret(sent, csrf)) return true;
    fail_page(res, "Refused",
              Error(Errc::invalid_argument,
                    "the form's CSRF token is missing or not this page's: "
                    "reload the page and try again"));
    res.status = 403;
    return false;
  }

  // The drive page's file form (multipart/form-data, ui/upload.hpp) with
  // this process's CSRF value; nullopt with the refusal written.
  std::optional<UploadForm> upload_form(const Request& req, Response& res) {
    auto up = parse_upload(req.get_header_value("Content-Type"), req.body);
    if (!up.ok()) {
      const bool not_multipart = up.error().message.rfind("a file must be sent as", 0) == 0;
      fail_page(res, "Refused", up.error());
      if (not_multipart) res.status = 415;
      return std::nullopt;
    }
    const auto csrf_it = up->fields.find("csrf");
    if (!csrf_ok(csrf_it == up->fields.end() ? std::string() : csrf_it->second, res))
      return std::nullopt;
    return std::move(up).value();
  }

  // A job started: its page; refused: the failure page.
  void started(Response& res, const Result<std::string>& id, const std::string& title,
               const std::string& back) {
    if (id.ok()) return redirect(res, "/job?id=" + *id);
    fail_page(res, title, id.error(), back);
  }

  // The token in the address becomes the cookie; without either: 403.
  bool admitted(Request& req, Response& res) {
    if (req.path == "/console.css" || req.path == "/console.js" || req.path == "/favicon.ico")
      return true;
    if (req.has_param("token")) {
      if (!same_secret(req.get_param_value("token"), opt.token)) {
        html(res, pages::need_token(), 403);
        return false;
      }
      res.set_header("Set-Cookie", std::string(kUiCookie) + "=" + session +
                                       "; HttpOnly; SameSite=Strict; Path=/");
      redirect(res, without_token(req));
      return false;
    }
    if (same_secret(req.cookie(kUiCookie), session)) return true;
    html(res, pages::need_token(), 403);
    return false;
  }

  void handle(Request& req, Response& res) {
    auto refused = serve::check_host(req, hosts);
    if (!refused) refused = serve::check_origin(req);
    if (refused) {
      res.status = refused->status;
      res.set_content(refused->message + "\n", "text/plain; charset=utf-8");
    } else if (admitted(req, res)) {
      std::string allow;
      switch (router.dispatch(req, res, &allow)) {
        case web::Router::Outcome::handled:
          break;
        case web::Router::Outcome::not_found:
          fail_page(res, "Not found", Error(Errc::not_found, "no page " + req.path));
          break;
        case web::Router::Outcome::method_not_allowed:
          res.set_header("Allow", allow);
          fail_page(res, "Refused",
                    Error(Errc::invalid_argument, req.method + " is not allowed on " + req.path));
          res.status = 405;
          break;
      }
    }
    log("http " + req.remote_addr + " " + web::printable(req.method) + " " +
        web::printable(req.path) + " " + std::to_string(res.status));
  }

  void routes();
  void action_routes();
};

void UiServer::Impl::routes() {
  router.Get("/console.css", [](const Request&, Response& res) {
    res.set_header("Cache-Control", "no-cache");
    res.set_content(std::string(serve::Console::stylesheet()), "text/css; charset=utf-8");
  });
  router.Get("/console.js", [](const Request&, Response& res) {
    res.set_header("Cache-Control", "no-cache");
    res.set_content(std::string(serve::Console::script()), "text/javascript; charset=utf-8");
  });
  // No icon: an empty answer rather than a 404 in the browser's console.
  router.Get("/favicon.ico", [](const Request&, Response& res) {
    res.status = 204;
    res.set_header("Cache-Control", "max-age=86400");
  });
  router.Get("/", [this](const Request&, Response& res) {
    html(res,
         pages::connect(desk.ports(), desk.drives(), desk.jobs(), desk.folder().string(), csrf));
  });
  router.Get("/drive", [this](const Request& req, Response& res) {
    auto d = desk.drive(req.get_param_value("key"));
    if (!d.ok()) return fail_page(res, "No such drive", d.error());
    html(res, pages::drive(*d, desk.folder().string(), csrf));
  });
  router.Get("/job", [this](const Request& req, Response& res) {
    auto j = desk.job(req.get_param_value("id"));
    if (!j.ok()) return fail_page(res, "No such operation", j.error());
    html(res, pages::job(*j, csrf));
  });
  router.Get("/plan", [this](const Request& req, Response& res) {
    auto p = desk.plan_json(req.get_param_value("id"));
    if (!p.ok()) return fail_page(res, "No such plan", p.error());
    html(res, pages::plan(*p, csrf));
  });
  router.Get("/compare", [this](const Request& req, Response& res) {
    auto page = desk.compare_html(req.get_param_value("job"));
    if (!page.ok()) return fail_page(res, "No such comparison", page.error());
    security_headers(res, serve::Console::report_security_policy());
    res.set_content(*page, "text/html; charset=utf-8");
  });
  router.Get("/report", [this](const Request& req, Response& res) {
    auto page = desk.report_html(req.get_param_value("file"));
    if (!page.ok()) return fail_page(res, "No report", page.error());
    security_headers(res, serve::Console::report_security_policy());
    res.set_content(*page, "text/html; charset=utf-8");
  });
  router.Get("/files/{any}", [this](const Request& req, Response& res) {
    auto path = desk.file(req.matches[1]);
    if (!path.ok()) return fail_page(res, "No such file", path.error());
    std::ifstream in(*path, std::ios::binary);
    std::string body((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    security_headers(res, serve::Console::content_security_policy());
    res.set_header("Content-Disposition", "attachment; filename=\"" + req.matches[1] + "\"");
    res.set_content(std::move(body), "application/json");
  });
  // JSON for scripts and tests: the same data the pages show.
  router.Get("/api/v1/job/{num}", [this](const Request& req, Response& res) {
    auto j = desk.job(req.matches[1]);
    j.ok() ? json_answer(res, *j)
           : json_answer(res, Json{{"error", j.error().message}}, status_for(j.error()));
  });
  router.Get("/api/v1/drives",
             [this](const Request&, Response& res) { json_answer(res, desk.drives()); });
  router.Get("/api/v1/ports",
             [this](const Request&, Response& res) { json_answer(res, desk.ports()); });
  router.Get("/api/v1/plan/{any}", [this](const Request& req, Response& res) {
    auto p = desk.plan_json(req.matches[1]);
    p.ok() ? json_answer(res, *p)
           : json_answer(res, Json{{"error", p.error().message}}, status_for(p.error()));
  });
  action_routes();
}

void UiServer::Impl::action_routes() {
  router.Post("/find", [this](const Request& req, Response& res) {
    auto f = form(req, res);
    if (!f) return;
    FindRequest fr;
    fr.port = field_of(*f, "port");
    const std::string baud = field_of(*f, "baud"), from = field_of(*f, "from"),
                      to = field_of(*f, "to");
    try {
      if (!baud.empty()) fr.bauds = {static_cast<unsigned>(std::stoul(baud))};
      if (!from.empty()) fr.first_id = static_cast<unsigned>(std::stoul(from, nullptr, 0));
      if (!to.empty()) fr.last_id = static_cast<unsigned>(std::stoul(to, nullptr, 0));
    } catch (const std::exception&) {
      return fail_page(
          res, "Cannot find drives",
          Error(Errc::invalid_argument, "the rate and the MACIDs must be numbers (MACIDs 0..255)"));
    }
    started(res, desk.find(fr), "Cannot find drives", "/");
  });
  router.Post("/backup", [this](const Request& req, Response& res) {
    auto f = form(req, res);
    if (!f) return;
    const std::string key = field_of(*f, "key");
    started(res, desk.backup(key), "Cannot back up", "/drive?key=" + serve::url_encode(key));
  });
  router.Post("/compare", [this](const Request& req, Response& res) {
    auto f = form(req, res);
    if (!f) return;
    const std::string key = field_of(*f, "key");
    started(res, desk.compare(key, field_of(*f, "against")), "Cannot compare",
            "/drive?key=" + serve::url_encode(key));
  });
  router.Post("/plan", [this](const Request& req, Response& res) {
    auto f = form(req, res);
    if (!f) return;
    const std::string key = field_of(*f, "key");
    started(res, desk.plan(key, field_of(*f, "file")), "Cannot plan the restore",
            "/drive?key=" + serve::url_encode(key));
  });
  router.Post("/undo", [this](const Request& req, Response& res) {
    auto f = form(req, res);
    if (!f) return;
    const std::string key = field_of(*f, "key");
    started(res, desk.plan_undo(key), "Cannot plan the undo",
            "/drive?key=" + serve::url_encode(key));
  });
  router.Post("/execute", [this](const Request& req, Response& res) {
    auto f = form(req, res);
    if (!f) return;
    ops::Audit a{"", field_of(*f, "reason"), field_of(*f, "ticket")};
    started(res, desk.execute(field_of(*f, "plan"), a, field_of(*f, "skip_incompatible") == "1"),
            "Cannot write the plan", "/plan?id=" + serve::url_encode(field_of(*f, "plan")));
  });
  // A file from this computer: kept in the folder, then the comparison or
  // the plan, as with a file that was there.
  router.Post("/upload", [this](const Request& req, Response& res) {
    auto up = upload_form(req, res);
    if (!up) return;
    const std::string key = up->fields["key"], then = up->fields["then"];
    const std::string back = "/drive?key=" + serve::url_encode(key);
    if (then != "compare" && then != "plan")
      return fail_page(res, "Cannot take the file",
                       Error(Errc::invalid_argument,
                             "the form asks for '" + then +
                                 "' after the upload, not 'compare' or 'plan': send the file "
                                 "from the drive's page"),
                       back);
    if (up->file_field != "file")
      return fail_page(res, "Cannot take the file",
                       Error(Errc::invalid_argument,
                             "no file chosen: choose a configuration "
                             "file (.json or .xml) on this computer"),
                       back);
    auto stored = desk.store_upload(up->file_name, up->file);
    if (!stored.ok()) return fail_page(res, "Cannot take the file", stored.error(), back);
    log("upload " + web::printable(*stored) + " (" + std::to_string(up->file.size()) + " bytes)");
    if (then == "plan")
      return started(res, desk.plan(key, *stored), "Cannot plan the restore", back);
    started(res, desk.compare(key, *stored), "Cannot compare", back);
  });
  router.Post("/quit", [this](const Request& req, Response& res) {
    auto f = form(req, res);
    if (!f) return;
    if (desk.busy())
      return fail_page(res, "Not quitting yet",
                       Error(Errc::plan_refused,
                             "an operation is running: lmcfg ui quits when it has ended (a write "
                             "is never stopped half way from this page)"));
    html(res, pages::stopped());
    res.close = true;
    if (opt.on_quit) opt.on_quit();
  });
}

UiServer::UiServer(Desk& desk, UiOptions opt)
    : impl_(std::make_unique<Impl>(desk, std::move(opt))) {
  impl_->routes();
}

UiServer::~UiServer() = default;

Result<int> UiServer::bind() {
  auto& im = *impl_;
  if (!serve::is_loopback(im.opt.host))
    return Error(Errc::invalid_argument,
                 "'" + im.opt.host +
                     "' is not a loopback address: lmcfg ui serves this computer "
                     "only (127.0.0.1, ::1 or localhost)");
  if (im.opt.token.empty()) {
    LMCFG_ASSIGN_OR_RETURN(im.opt.token, serve::random_hex(24));
  }
  LMCFG_ASSIGN_OR_RETURN(im.session, serve::random_hex(32));
  LMCFG_ASSIGN_OR_RETURN(im.csrf, serve::random_hex(32));
  web::ServerOptions so = im.opt.server;
  so.limits.max_body = std::max(so.limits.max_body, kMaxUpload + kUploadFraming);
  so.handle = [&im](Request& req, Response& res) { im.handle(req, res); };
  so.log = im.opt.log;
  {
    std::lock_guard<std::mutex> lock(im.mu);
    im.server = std::make_unique<web::Server>(std::move(so));
  }
  LMCFG_ASSIGN_OR_RETURN(im.port, im.server->bind(im.opt.host, im.opt.port));
  const std::string p = ":" + std::to_string(im.port);
  auto add = [&](const std::string& h) {
    im.hosts.push_back(lower_text(h.find(':') != std::string::npos ? "[" + h + "]" : h) + p);
  };
  add(im.opt.host);
  add("localhost");
  if (im.opt.host == "localhost") {
    add("127.0.0.1");
    add("::1");
  }
  return im.port;
}

std::string UiServer::url() const {
  const auto& h = impl_->opt.host;
  const std::string host = h.find(':') != std::string::npos ? "[" + h + "]" : h;
  return "http://" + host + ":" + std::to_string(impl_->port) + "/?token=" + impl_->opt.token;
}

const std::string& UiServer::token() const { return impl_->opt.token; }

void UiServer::serve() {
  web::Server* s = nullptr;
  {
    std::lock_guard<std::mutex> lock(impl_->mu);
    if (impl_->stop_asked || !impl_->server) return;
    s = impl_->server.get();
  }
  s->serve();
}

void UiServer::stop() {
  std::lock_guard<std::mutex> lock(impl_->mu);
  impl_->stop_asked = true;
  if (impl_->server) impl_->server->stop();
}

std::string UiServer::answer(std::string_view bytes, const std::string& remote_addr) {
  web::Limits limits = impl_->opt.server.limits;
  limits.max_body = std::max(limits.max_body, kMaxUpload + kUploadFraming);
  web::RequestParser parser(limits);
  std::string out;
  auto state = parser.feed(bytes);
  while (state == web::RequestParser::State::complete) {
    Request req = std::move(parser.request());
    req.remote_addr = remote_addr;
    Response res;
    impl_->handle(req, res);
    out += web::serialize(res, req.method == "HEAD");
    parser.next();
    state = parser.parse();
  }
  if (state == web::RequestParser::State::error) {
    Response res;
    res.status = parser.error_status();
    res.set_content(parser.error_message() + "\n", "text/plain");
    res.close = true;
    out += web::serialize(res, false);
  }
  return out;
}

}  // namespace lmcfg::ui
