#pragma once
// The HTTP side of `lmcfg ui` (docs/ui.md "What is checked"): lmcfg's own
// HTTP server on a loopback address only, the desk's pages and forms, and the
// checks of `lmcfg serve` (serve/request_checks.hpp): only this server's own
// Host names (421), no state-changing request from another site (403).
// Besides, as `jupyter lab` does, a random token in the address it prints:
// the first load with ?token=T gets a session cookie (HttpOnly,
// SameSite=Strict) and is sent on to the same address without the token;
// every other request without that cookie is refused (403). Every form
// carries the CSRF value (one random value per process), checked on each
// POST. The answers carry the console's security headers.
#include <functional>
#include <memory>
#include <string>
#include <string_view>

#include "common/result.hpp"
#include "ui/desk.hpp"
#include "web/web_server.hpp"

namespace lmcfg::ui {

inline constexpr const char* kUiCookie = "lmcfg_ui";

struct UiOptions {
  std::string host = "127.0.0.1";  // a loopback address (is_loopback), else bind() refuses
  int port = 0;                    // 0: a free port
  std::string token;               // "" = a new random one
  std::function<void(const std::string&)> log;
  std::function<void()> on_quit;  // the page's Quit (the tool then stops the server)
  std::function<int(const Error&)> exit_code;
  web::ServerOptions server;  // limits and timeouts (handle, error_page are set here)
};

class UiServer {
 public:
  UiServer(Desk& desk, UiOptions opt);
  ~UiServer();
  // Binds the address; the port bound. Errc::invalid_argument for an address
  // that is not loopback; Errc::io_error when it cannot be bound or no random
  // bytes can be read.
  Result<int> bind();
  // "http://127.0.0.1:PORT/?token=T": the address to open (after bind()).
  std::string url() const;
  const std::string& token() const;
  void serve();
  void stop();
  // The answers to one connection's bytes, through the same checks and
  // routes, without a socket (after bind()): for tests.
  std::string answer(std::string_view bytes, const std::string& remote_addr = "127.0.0.1");
  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace lmcfg::ui
