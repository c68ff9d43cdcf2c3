#include "serve/console_http.hpp"

#include <httplib.h>

namespace lmcfg::serve {

namespace {

std::string cookie(const httplib::Request& req, std::string_view name) {
  const std::string header = req.get_header_value("Cookie");
  std::size_t pos = 0;
  while (pos < header.size()) {
    auto end = header.find(';', pos);
    if (end == std::string::npos) end = header.size();
    std::string_view part(header.data() + pos, end - pos);
    while (!part.empty() && part.front() == ' ') part.remove_prefix(1);
    if (part.size() > name.size() && part.substr(0, name.size()) == name &&
        part[name.size()] == '=')
      return std::string(part.substr(name.size() + 1));
    pos = end + 1;
  }
  return "";
}

// (httplib's set_header adds a header: each is set once, two CSPs would both apply)
void headers(httplib::Response& res, std::string_view csp = Console::content_security_policy(),
             const char* cache = "no-store") {
  res.set_header("Content-Security-Policy", std::string(csp));
  res.set_header("X-Content-Type-Options", "nosniff");
  res.set_header("Referrer-Policy", "no-referrer");
  res.set_header("Cache-Control", cache);
}

// A report page as `lmcfg report` writes it: its own CSP (inline style only).
void report(httplib::Response& res, const std::string& html) {
  headers(res, Console::report_security_policy());
  res.set_content(html, "text/html; charset=utf-8");
}

void page(httplib::Response& res, const Page& p) {
  headers(res);
  res.status = p.status;
  res.set_content(p.html, "text/html; charset=utf-8");
}

void see_other(httplib::Response& res, const std::string& location) {
  headers(res);
  res.status = 303;
  res.set_header("Location", location);
  res.set_content("", "text/plain");
}

// Only a path of this console: never another host ("//evil", "https://...").
std::string local_path(const std::string& next) {
  if (next.empty() || next[0] != '/' || (next.size() > 1 && (next[1] == '/' || next[1] == '\\')))
    return "/";
  return next;
}

std::string path_and_query(const httplib::Request& req) {
  std::string s = req.path;
  bool first = true;
  for (const auto& [k, v] : req.params) {
    s += (first ? "?" : "&") + url_encode(k) + "=" + url_encode(v);
    first = false;
  }
  return s;
}

httplib::Params form(const httplib::Request& req) {
  httplib::Params p;
  httplib::detail::parse_query_text(req.body, p);
  return p;
}

std::string field(const httplib::Params& p, const char* key) {
  auto it = p.find(key);
  return it == p.end() ? "" : it->second;
}

// The signed-in user, or the answer that sends the browser to sign in.
std::optional<ConsoleUser> signed_in(Console* c, const httplib::Request& req,
                                     httplib::Response& res) {
  auto u = c->user(cookie(req, kSessionCookie));
  // After signing in, back to the page asked for (a form's POST: the overview).
  if (!u)
    see_other(res, "/signin?next=" + url_encode(req.method == "GET" ? path_and_query(req) : "/"));
  return u;
}

// A POST's user: signed in, with the form's CSRF token; an operator for
// anything that changes something.
std::optional<ConsoleUser> operator_post(Console* c, const httplib::Request& req,
                                         httplib::Response& res, const httplib::Params& f) {
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
void register_assets(httplib::Server& server) {
  server.Get("/console.css", [](const httplib::Request&, httplib::Response& res) {
    headers(res, Console::content_security_policy(), "max-age=300");
    res.set_content(std::string(Console::stylesheet()), "text/css; charset=utf-8");
  });
  server.Get("/console.js", [](const httplib::Request&, httplib::Response& res) {
    headers(res, Console::content_security_policy(), "max-age=300");
    res.set_content(std::string(Console::script()), "text/javascript; charset=utf-8");
  });
  // Browsers ask for it on every site; the console has none (and says so
  // without a 404 in the browser's console).
  server.Get("/favicon.ico", [](const httplib::Request&, httplib::Response& res) {
    headers(res);
    res.status = 204;
  });
}

void register_signin(httplib::Server& server, Console* c) {
  server.Get("/signin", [c](const httplib::Request& req, httplib::Response& res) {
    if (!c->sign_in_needed()) return see_other(res, "/");
    page(res, c->signin_page("", local_path(req.get_param_value("next"))));
  });
  server.Post("/signin", [c](const httplib::Request& req, httplib::Response& res) {
    const auto f = form(req);
    const std::string next = local_path(field(f, "next"));
    if (!c->sign_in_needed()) return see_other(res, next);
    if (field(f, "csrf") != c->anonymous_csrf())
      return page(res, c->signin_page("the form is out of date: sign in again", next, 403));
    auto s = c->sign_in(field(f, "token"));
    if (!s.ok()) return page(res, c->signin_page(s.error().message, next, 401));
    res.set_header("Set-Cookie", std::string(kSessionCookie) + "=" + s->id +
                                     "; HttpOnly; SameSite=Strict; Path=/; Max-Age=" +
                                     std::to_string(s->max_age));
    see_other(res, next);
  });
  server.Post("/signout", [c](const httplib::Request& req, httplib::Response& res) {
    const auto f = form(req);
    auto u = signed_in(c, req, res);
    if (!u) return;
    if (!Console::csrf_ok(*u, field(f, "csrf")))
      return page(res, c->error_page(&*u, 403, "Refused",
                                     "the form's CSRF token is missing or not this session's"));
    c->sign_out(cookie(req, kSessionCookie));
    res.set_header("Set-Cookie",
                   std::string(kSessionCookie) + "=; HttpOnly; SameSite=Strict; Path=/; Max-Age=0");
    see_other(res, "/signin");
  });
}

// The pages that only show something.
void register_pages(httplib::Server& server, Console* c) {
  server.Get("/", [c](const httplib::Request& req, httplib::Response& res) {
    if (auto u = signed_in(c, req, res))
      page(res, c->overview(*u, req.get_param_value("line"), req.get_param_value("status")));
  });
  server.Get("/position", [c](const httplib::Request& req, httplib::Response& res) {
    if (auto u = signed_in(c, req, res)) page(res, c->position(*u, req.get_param_value("name")));
  });
  server.Get("/job", [c](const httplib::Request& req, httplib::Response& res) {
    if (auto u = signed_in(c, req, res))
      page(res, c->job_page(*u, req.get_param_value("id"), req.get_param_value("name")));
  });
  server.Get("/replace", [c](const httplib::Request& req, httplib::Response& res) {
    if (auto u = signed_in(c, req, res))
      page(res, c->replace_page(*u, req.get_param_value("name"), req.get_param_value("rev")));
  });
  server.Get("/plan", [c](const httplib::Request& req, httplib::Response& res) {
    if (auto u = signed_in(c, req, res)) page(res, c->plan_page(*u, req.get_param_value("id")));
  });
}

// The forms that start something: the page each leads to (303), or the failure as a page.
void register_actions(httplib::Server& server, Console* c) {
  auto action = [c](const char* title, auto start) {
    return [c, title, start](const httplib::Request& req, httplib::Response& res) {
      const auto f = form(req);
      auto u = operator_post(c, req, res, f);
      if (!u) return;
      Result<std::string> location = start(*u, f);
      location.ok() ? see_other(res, *location)
                    : page(res, c->failure_page(*u, title, location.error()));
    };
  };
  server.Post("/backup",
              action("Cannot back up",
                     [c](const ConsoleUser& u, const httplib::Params& f) -> Result<std::string> {
                       const std::string name = field(f, "name");
                       LMCFG_ASSIGN_OR_RETURN(auto id, c->start_backup(u, name));
                       return "/job?id=" + url_encode(id) + "&name=" + url_encode(name);
                     }));
  // Planning reads the drive: a POST (it makes a plan on the server), then
  // the plan's own page.
  server.Post(
      "/plan",
      action("No plan", [c](const ConsoleUser& u, const httplib::Params& f) -> Result<std::string> {
        LMCFG_ASSIGN_OR_RETURN(auto id, c->make_plan(u, field(f, "name"), field(f, "rev")));
        return "/plan?id=" + url_encode(id);
      }));
  // Approving a revision: then the position's page (its state after the drift check).
  server.Post("/approve",
              action("Not approved",
                     [c](const ConsoleUser& u, const httplib::Params& f) -> Result<std::string> {
                       const std::string name = field(f, "name");
                       LMCFG_TRY(c->approve(u, name, field(f, "rev"), field(f, "reason"),
                                            field(f, "ticket")));
                       return "/position?name=" + url_encode(name);
                     }));
  server.Post("/execute",
              action("Not restored",
                     [c](const ConsoleUser& u, const httplib::Params& f) -> Result<std::string> {
                       LMCFG_ASSIGN_OR_RETURN(
                           auto id, c->start_restore(u, field(f, "plan"), field(f, "reason"),
                                                     field(f, "ticket"),
                                                     field(f, "skip_incompatible") == "1"));
                       return "/job?id=" + url_encode(id) + "&name=" + url_encode(field(f, "name"));
                     }));
}

// The report's pages: a revision's, and the diff of two (or of one and the drive).
void register_reports(httplib::Server& server, Console* c) {
  auto report_route = [c](const char* title, auto render) {
    return [c, title, render](const httplib::Request& req, httplib::Response& res) {
      auto u = signed_in(c, req, res);
      if (!u) return;
      auto html = render(req);
      html.ok() ? report(res, *html) : page(res, c->failure_page(*u, title, html.error()));
    };
  };
  server.Get("/report", report_route("No report", [c](const httplib::Request& req) {
               return c->report(req.get_param_value("name"), req.get_param_value("rev"));
             }));
  server.Get("/diff", report_route("No diff", [c](const httplib::Request& req) {
               return c->diff(req.get_param_value("name"), req.get_param_value("from"),
                              req.get_param_value("to"));
             }));
}

}  // namespace

void register_console_routes(httplib::Server& server, Console& console) {
  register_assets(server);
  register_signin(server, &console);
  register_pages(server, &console);
  register_actions(server, &console);
  register_reports(server, &console);
}

}  // namespace lmcfg::serve
