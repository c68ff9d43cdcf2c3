#include "serve/console_http.hpp"

#include "web/web_message.hpp"
#include "web/web_router.hpp"

namespace lmcfg::serve {

namespace {

// (httplib's set_header adds a header: each is set once, two CSPs would both apply)
void headers(web::Response& res, std::string_view csp = Console::content_security_policy(),
             const char* cache = "no-store") {
  res.set_header("Content-Security-Policy", std::string(csp));
  res.set_header("X-Content-Type-Options", "nosniff");
  res.set_header("Referrer-Policy", "no-referrer");
  res.set_header("Cache-Control", cache);
}

// A report page as `lmcfg report` writes it: its own CSP (inline style only).
void report(web::Response& res, const std::string& html) {
  headers(res, Console::report_security_policy());
  res.set_content(html, "text/html; charset=utf-8");
}

void page(web::Response& res, const Page& p) {
  headers(res);
  res.status = p.status;
  res.set_content(p.html, "text/html; charset=utf-8");
}

void see_other(web::Response& res, const std::string& location) {
  headers(res);
  res.status = 303;
  res.set_header("Location", location);
  res.set_content("", "text/plain");
}

// Only a path of this console: never another host ("//evil", "https://...",
// "/\\evil"), and nothing a browser would strip or rewrite before it reads
// the URL (tabs and line breaks: "/\t/evil" is "//evil" to a browser; the
// URL standard drops them) — the characters of a path and query, nothing else.
std::string local_path(const std::string& next) {
  if (next.empty() || next[0] != '/' || (next.size() > 1 && (next[1] == '/' || next[1] == '\\')))
    return "/";
  const std::string_view allowed =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789-._~/?=&%+:@!$'()*,;";
  if (next.find_first_not_of(allowed) != std::string::npos) return "/";
  return next;
}

std::string path_and_query(const web::Request& req) {
  std::string s = req.path;
  bool first = true;
  for (const auto& [k, v] : req.params) {
    s += (first ? "?" : "&") + url_encode(k) + "=" + url_encode(v);
    first = false;
  }
  return s;
}

// The form's fields; nullopt with the 400 page written when the body is not
// a form (application/x-www-form-urlencoded) of valid UTF-8.
std::optional<web::Params> form(Console* c, const web::Request& req, web::Response& res) {
  const std::string type = req.get_header_value("Content-Type");
  if (type.substr(0, type.find(';')) != "application/x-www-form-urlencoded") {
    page(res, c->error_page(nullptr, 415, "Refused",
                            "a form must be sent as application/x-www-form-urlencoded"));
    return std::nullopt;
  }
  web::Params p;
  std::string bad;
  if (!web::parse_query(req.body, p, bad, true)) {
    page(res, c->error_page(nullptr, 400, "Refused",
                            "the form's field '" + bad +
                                "' is malformed, not valid UTF-8 or has a control character"));
    return std::nullopt;
  }
  return p;
}

// The session cookie's attributes: Secure over HTTPS, so that the browser
// never sends it over plain HTTP.
std::string cookie_attributes(const web::Request& req, const std::string& path, long max_age) {
  return "; HttpOnly; SameSite=Strict; Path=" + path + "; Max-Age=" + std::to_string(max_age) +
         (req.tls ? "; Secure" : "");
}

std::string field(const web::Params& p, const char* key) {
  auto it = p.find(key);
  return it == p.end() ? "" : it->second;
}

// The signed-in user, or the answer that sends the browser to sign in.
std::optional<ConsoleUser> signed_in(Console* c, const web::Request& req, web::Response& res) {
  auto u = c->user(req.cookie(kSessionCookie));
  // After signing in, back to the page asked for (a form's POST: the overview).
  if (!u)
    see_other(res, "/signin?next=" + url_encode(req.method == "GET" ? path_and_query(req) : "/"));
  return u;
}

// A POST's user: signed in, with the form's CSRF token; an operator for
// anything that changes something.
std::optional<ConsoleUser> operator_post(Console* c, const web::Request& req, web::Response& res,
                                         const web::Params& f) {
  auto u = signed_in(c, req, res);
  if (!u) return u;
  if (!Console::csrf_ok(*u, field(f, "csrf"))) {
    page(res, c->error_page(&*u, 403, "Refused",
                            "the form's CSRF token is missing or not this session's: reload "
                            "the page and try again"));
    return std::nullopt;
  }
  if (u->role != Role::operator_) {
    page(res, c->error_page(&*u, 403, "Refused",
                            "'" + u->who + "' has role viewer: this needs role operator"));
    return std::nullopt;
  }
  return u;
}

// The stylesheet, the script and the (absent) icon.
void register_assets(web::Router& router) {
  router.Get("/console.css", [](const web::Request&, web::Response& res) {
    headers(res, Console::content_security_policy(), "max-age=300");
    res.set_content(std::string(Console::stylesheet()), "text/css; charset=utf-8");
  });
  router.Get("/console.js", [](const web::Request&, web::Response& res) {
    headers(res, Console::content_security_policy(), "max-age=300");
    res.set_content(std::string(Console::script()), "text/javascript; charset=utf-8");
  });
  // Browsers ask for it on every site; the console has none (and says so
  // without a 404 in the browser's console).
  router.Get("/favicon.ico", [](const web::Request&, web::Response& res) {
    headers(res);
    res.status = 204;
  });
}

// Sign-in: the form's CSRF value is a fresh one per visitor, also sent as a
// cookie of the sign-in path only; the POST must bring both, equal, and the
// console must have issued it (Console::signin_nonce). A page of another
// site can neither read the value nor set the cookie.
void register_signin(web::Router& router, Console* c) {
  router.Get("/signin", [c](const web::Request& req, web::Response& res) {
    if (!c->sign_in_needed()) return see_other(res, "/");
    auto nonce = c->signin_nonce(req.cookie(kSigninCookie), req.remote_addr);
    if (!nonce.ok())
      return page(res, c->error_page(nullptr, 503, "Sign-in unavailable", nonce.error().message));
    res.set_header("Set-Cookie", std::string(kSigninCookie) + "=" + *nonce +
                                     cookie_attributes(req, "/signin", 600));
    page(res, c->signin_page("", local_path(req.get_param_value("next")), *nonce));
  });
  router.Post("/signin", [c](const web::Request& req, web::Response& res) {
    const auto f = form(c, req, res);
    if (!f) return;
    const std::string next = local_path(field(*f, "next"));
    if (!c->sign_in_needed()) return see_other(res, next);
    auto fresh = [&](const std::string& message, int status) {
      auto nonce = c->signin_nonce({}, req.remote_addr);
      if (!nonce.ok())
        return page(res, c->error_page(nullptr, 503, "Sign-in unavailable", nonce.error().message));
      res.set_header("Set-Cookie", std::string(kSigninCookie) + "=" + *nonce +
                                       cookie_attributes(req, "/signin", 600));
      page(res, c->signin_page(message, next, *nonce, status));
    };
    if (!c->signin_nonce_ok(req.cookie(kSigninCookie), field(*f, "csrf")))
      return fresh("the form is out of date: sign in again", 403);
    auto s = c->sign_in(field(*f, "token"));
    if (!s.ok()) return fresh(s.error().message, 401);
    res.set_header("Set-Cookie", std::string(kSessionCookie) + "=" + s->id +
                                     cookie_attributes(req, "/", s->max_age));
    see_other(res, next);
  });
  router.Post("/signout", [c](const web::Request& req, web::Response& res) {
    const auto f = form(c, req, res);
    if (!f) return;
    auto u = signed_in(c, req, res);
    if (!u) return;
    if (!Console::csrf_ok(*u, field(*f, "csrf")))
      return page(res, c->error_page(&*u, 403, "Refused",
                                     "the form's CSRF token is missing or not this session's"));
    c->sign_out(req.cookie(kSessionCookie));
    res.set_header("Set-Cookie",
                   std::string(kSessionCookie) + "=" + cookie_attributes(req, "/", 0));
    see_other(res, "/signin");
  });
}

// The pages that only show something.
void register_pages(web::Router& router, Console* c) {
  router.Get("/", [c](const web::Request& req, web::Response& res) {
    if (auto u = signed_in(c, req, res))
      page(res, c->overview(*u, req.get_param_value("line"), req.get_param_value("status"),
                            req.get_param_value("page")));
  });
  router.Get("/position", [c](const web::Request& req, web::Response& res) {
    if (auto u = signed_in(c, req, res)) page(res, c->position(*u, req.get_param_value("name")));
  });
  router.Get("/job", [c](const web::Request& req, web::Response& res) {
    if (auto u = signed_in(c, req, res))
      page(res, c->job_page(*u, req.get_param_value("id"), req.get_param_value("name")));
  });
  router.Get("/replace", [c](const web::Request& req, web::Response& res) {
    if (auto u = signed_in(c, req, res))
      page(res, c->replace_page(*u, req.get_param_value("name"), req.get_param_value("rev")));
  });
  router.Get("/plan", [c](const web::Request& req, web::Response& res) {
    if (auto u = signed_in(c, req, res)) page(res, c->plan_page(*u, req.get_param_value("id")));
  });
}

// The forms that start something: the page each leads to (303), or the failure as a page.
void register_actions(web::Router& router, Console* c) {
  // A failure is a page in plain words with a button that sends the same
  // form again (`retry_fields`: the fields it repeats; none: no button).
  auto action = [c](const char* title, auto start, std::vector<const char*> retry_fields = {"name"},
                    const char* retry_action = nullptr, const char* retry_label = nullptr) {
    return [c, title, start, retry_fields, retry_action, retry_label](const web::Request& req,
                                                                      web::Response& res) {
      const auto f = form(c, req, res);
      if (!f) return;
      auto u = operator_post(c, req, res, *f);
      if (!u) return;
      Result<std::string> location = start(*u, *f);
      if (location.ok()) return see_other(res, *location);
      RetryForm retry;
      if (!retry_fields.empty()) retry.action = retry_action ? retry_action : req.path;
      if (retry_label) retry.label = retry_label;
      for (const char* k : retry_fields) retry.fields.emplace_back(k, field(*f, k));
      page(res, c->failure_page(*u, title, location.error(), retry, field(*f, "name")));
    };
  };
  router.Post("/backup",
              action("Cannot back up",
                     [c](const ConsoleUser& u, const web::Params& f) -> Result<std::string> {
                       const std::string name = field(f, "name");
                       LMCFG_ASSIGN_OR_RETURN(auto id, c->start_backup(u, name));
                       return "/job?id=" + url_encode(id) + "&name=" + url_encode(name);
                     }));
  // Planning reads the drive: a POST (it makes a plan on the server), then
  // the plan's own page.
  router.Post("/plan",
              action("No plan",
                     [c](const ConsoleUser& u, const web::Params& f) -> Result<std::string> {
                       LMCFG_ASSIGN_OR_RETURN(auto id,
                                              c->make_plan(u, field(f, "name"), field(f, "rev")));
                       return "/plan?id=" + url_encode(id);
                     },
                     {"name", "rev"}));
  // The automatic retry of a failed restore, waiting: then the position's page.
  router.Post("/cancel-retry",
              action("Retry not cancelled",
                     [c](const ConsoleUser& u, const web::Params& f) -> Result<std::string> {
                       const std::string name = field(f, "name");
                       LMCFG_TRY(c->cancel_retry(u, name));
                       return "/position?name=" + url_encode(name);
                     },
                     {}));
  // Approving a revision: then the position's page (its state after the drift check).
  router.Post("/approve",
              action("Not approved",
                     [c](const ConsoleUser& u, const web::Params& f) -> Result<std::string> {
                       const std::string name = field(f, "name");
                       LMCFG_TRY(c->approve(u, name, field(f, "rev"), field(f, "reason"),
                                            field(f, "ticket")));
                       return "/position?name=" + url_encode(name);
                     },
                     {}));
  router.Post("/execute",
              action(
                  "Not restored",
                  [c](const ConsoleUser& u, const web::Params& f) -> Result<std::string> {
                    LMCFG_ASSIGN_OR_RETURN(
                        auto id,
                        c->start_restore(u, field(f, "plan"), field(f, "reason"),
                                         field(f, "ticket"), field(f, "skip_incompatible") == "1"));
                    return "/job?id=" + url_encode(id) + "&name=" + url_encode(field(f, "name"));
                  },
                  {"name"}, "/plan", "Plan again"));
}

// The report's pages: a revision's, and the diff of two (or of one and the drive).
void register_reports(web::Router& router, Console* c) {
  auto report_route = [c](const char* title, auto render) {
    return [c, title, render](const web::Request& req, web::Response& res) {
      auto u = signed_in(c, req, res);
      if (!u) return;
      auto html = render(req);
      html.ok() ? report(res, *html) : page(res, c->failure_page(*u, title, html.error()));
    };
  };
  router.Get("/report", report_route("No report", [c](const web::Request& req) {
               return c->report(req.get_param_value("name"), req.get_param_value("rev"));
             }));
  router.Get("/diff", report_route("No diff", [c](const web::Request& req) {
               return c->diff(req.get_param_value("name"), req.get_param_value("from"),
                              req.get_param_value("to"));
             }));
}

}  // namespace

void register_console_routes(web::Router& router, Console& console) {
  register_assets(router);
  register_signin(router, &console);
  register_pages(router, &console);
  register_actions(router, &console);
  register_reports(router, &console);
}

}  // namespace lmcfg::serve
