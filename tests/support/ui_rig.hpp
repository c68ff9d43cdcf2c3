#pragma once
// lmcfg ui in-process for the tests (tests/ui/): a desk over a scratch
// folder, its server bound to a free loopback port, and requests answered
// through UiServer::answer (the same checks and routes as over a socket).
// XDG_STATE_HOME points into the scratch folder, so the undo and recovery
// records and the journal are this test's own.
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <thread>

#include "db/database.hpp"
#include "files.hpp"
#include "ui/desk.hpp"
#include "ui/server.hpp"

namespace lmcfg::test {

struct UiAnswer {
  int status = 0;
  std::multimap<std::string, std::string> headers;  // names in lower case
  std::string body;
  std::string header(const std::string& name) const {
    auto it = headers.find(name);
    return it == headers.end() ? "" : it->second;
  }
};

inline UiAnswer parse_answer(const std::string& raw) {
  UiAnswer a;
  const auto head_end = raw.find("\r\n\r\n");
  const std::string head = raw.substr(0, head_end);
  a.body = head_end == std::string::npos ? "" : raw.substr(head_end + 4);
  std::size_t pos = head.find("\r\n");
  a.status = std::stoi(head.substr(9, 3));
  while (pos != std::string::npos && pos < head.size()) {
    const std::size_t next = head.find("\r\n", pos + 2);
    const std::string line =
        head.substr(pos + 2, next == std::string::npos ? std::string::npos : next - pos - 2);
    const auto colon = line.find(':');
    if (colon != std::string::npos) {
      std::string name = line.substr(0, colon);
      for (char& c : name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      a.headers.emplace(name, line.substr(colon + 2));
    }
    pos = next;
  }
  return a;
}

// "%XX" for a form's value.
inline std::string form_encode(const std::string& s) {
  static const char* hexdigits = "0123456789ABCDEF";
  std::string o;
  for (unsigned char c : s) {
    if (std::isalnum(c) || c == '-' || c == '_' || c == '.' || c == '~') {
      o += static_cast<char>(c);
    } else {
      o += '%';
      o += hexdigits[c >> 4];
      o += hexdigits[c & 15];
    }
  }
  return o;
}

class UiRig {
 public:
  // `practice`: the practice drive's simulator state ("" = none).
  explicit UiRig(const std::string& name, const db::Database& db = db::Database::empty(),
                 const std::string& practice = "")
      : dir_(name) {
    ::setenv("XDG_STATE_HOME", (dir_.path / "state").string().c_str(), 1);
    ui::DeskOptions o;
    o.folder = dir_.path / "backups";
    o.db = db;
    o.exit_code = [](const Error& e) { return e.code == Errc::plan_refused ? 3 : 4; };
    o.exit_category = [](int c) { return c == 0 ? std::string("ok") : "error"; };
    o.who = "tester";
    o.practice_state = practice;
    auto d = ui::Desk::create(std::move(o));
    if (!d.ok()) throw std::runtime_error(d.error().message);
    desk_ = std::move(d).value();
    ui::UiOptions uo;
    uo.token = "T0KEN";
    server_ = std::make_unique<ui::UiServer>(*desk_, uo);
    auto port = server_->bind();
    if (!port.ok()) throw std::runtime_error(port.error().message);
    port_ = *port;
    host_ = "127.0.0.1:" + std::to_string(port_);
    // The session cookie, as a browser gets it by opening the printed address.
    const auto first = get("/?token=T0KEN", false);
    const std::string set = first.header("set-cookie");
    cookie_ = set.substr(0, set.find(';'));
    csrf_ = csrf_of(get("/").body);
  }
  ~UiRig() {
    if (serving_.joinable()) {
      server_->stop();
      serving_.join();
    }
    desk_->wait_idle();
    ::unsetenv("XDG_STATE_HOME");
  }

  const std::filesystem::path& dir() const { return dir_.path; }
  // Serves on the socket too (a browser's walk); stopped by the destructor.
  void serve_in_background() {
    serving_ = std::thread([this] { server_->serve(); });
  }
  // "http://127.0.0.1:PORT"; the address lmcfg ui prints is base() + "/?token=T0KEN".
  std::string base() const { return "http://" + host_; }
  ui::Desk& desk() { return *desk_; }
  const std::string& host() const { return host_; }
  const std::string& csrf() const { return csrf_; }
  const std::string& cookie() const { return cookie_; }

  UiAnswer raw(const std::string& request) { return parse_answer(server_->answer(request)); }

  UiAnswer get(const std::string& path, bool with_cookie = true) {
    return raw("GET " + path + " HTTP/1.1\r\nHost: " + host_ + "\r\n" +
               (with_cookie ? "Cookie: " + cookie_ + "\r\n" : "") + "\r\n");
  }
  // A form POST as the page sends it (the CSRF value added unless given).
  UiAnswer post(const std::string& path, std::map<std::string, std::string> fields,
                const std::string& extra_headers = "") {
    if (!fields.count("csrf")) fields["csrf"] = csrf_;
    std::string body;
    for (const auto& [k, v] : fields) body += (body.empty() ? "" : "&") + k + "=" + form_encode(v);
    return raw("POST " + path + " HTTP/1.1\r\nHost: " + host_ + "\r\nCookie: " + cookie_ +
               "\r\nContent-Type: application/x-www-form-urlencoded\r\n" + extra_headers +
               "Content-Length: " + std::to_string(body.size()) + "\r\n\r\n" + body);
  }
  // The drive page's file form as a browser sends it (multipart/form-data):
  // `fields` (the CSRF value added unless given) and one file part.
  UiAnswer upload(std::map<std::string, std::string> fields, const std::string& file_name,
                  const std::string& content, const std::string& extra_headers = "") {
    if (!fields.count("csrf")) fields["csrf"] = csrf_;
    const std::string boundary = "----lmcfgTestBoundary7MA4YWxkTrZu0gW";
    std::string body;
    for (const auto& [k, v] : fields)
      body += "--" + boundary + "\r\nContent-Disposition: form-data; name=\"" + k + "\"\r\n\r\n" +
              v + "\r\n";
    body += "--" + boundary + "\r\nContent-Disposition: form-data; name=\"file\"; filename=\"" +
            file_name + "\"\r\nContent-Type: application/json\r\n\r\n" + content + "\r\n--" +
            boundary + "--\r\n";
    return raw("POST /upload HTTP/1.1\r\nHost: " + host_ + "\r\nCookie: " + cookie_ +
               "\r\nContent-Type: multipart/form-data; boundary=" + boundary + "\r\n" +
               extra_headers + "Content-Length: " + std::to_string(body.size()) + "\r\n\r\n" +
               body);
  }
  // The job a form started (its 303 to /job?id=N), waited for; its JSON.
  ui::Json finish(const UiAnswer& started) {
    if (started.status != 303) throw std::runtime_error("no job started: " + started.body);
    const std::string loc = started.header("location");
    const std::string id = loc.substr(loc.find('=') + 1);
    for (int i = 0; i < 6000; ++i) {
      auto j = desk_->job(id);
      if (j.ok() && (*j)["state"] != "running") return *j;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    throw std::runtime_error("job " + id + " did not end");
  }

 private:
  static std::string csrf_of(const std::string& html) {
    const std::string mark = "name=\"csrf\" value=\"";
    const auto p = html.find(mark);
    if (p == std::string::npos) return "";
    return html.substr(p + mark.size(), html.find('"', p + mark.size()) - p - mark.size());
  }
  ScratchDir dir_;
  std::unique_ptr<ui::Desk> desk_;
  std::unique_ptr<ui::UiServer> server_;
  int port_ = 0;
  std::string host_, cookie_, csrf_;
  std::thread serving_;
};

}  // namespace lmcfg::test
