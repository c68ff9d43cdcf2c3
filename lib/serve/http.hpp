#pragma once
// The HTTP side of lmcfg serve (docs/serve.md "API", "Security model"): the
// routes of the REST API and the console on lmcfg's own server
// (web/web_server.hpp), a thin adapter from routes to Service calls, and the
// checks every request passes first: without tokens only this service's own
// Host names are served (421 otherwise); a state-changing request that a
// browser marks as coming from another origin (Origin, Sec-Fetch-Site) is
// refused (403); API bodies are application/json (415). Authorization: with tokens, a
// bearer token is required (viewer: GET, operator: also POST); without, every
// client is an operator, which only a loopback address makes acceptable (the
// tool refuses anything else).
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/result.hpp"
#include "serve/console.hpp"
#include "serve/service.hpp"
#include "serve/tokens.hpp"
#include "web/web_server.hpp"

namespace lmcfg::serve {

struct ListenAddress {
  std::string host;
  int port = 8470;
};
// "127.0.0.1:8470", "[::1]:8470", "localhost:0" (0: any free port).
// Errc::invalid_argument saying what is expected.
Result<ListenAddress> parse_listen(const std::string& text);
// An address in 127.0.0.0/8 (dotted quad), ::1 (in any IPv6 spelling) or
// "localhost"; a host name is not (whatever it resolves to).
bool is_loopback(const std::string& host);

struct HttpOptions {
  ListenAddress listen;
  std::optional<std::vector<TokenEntry>> tokens;  // nullopt: no authorization
  std::size_t max_body = 4096;                    // request bodies above are refused (413)
  std::function<void(const std::string&)> log;
  std::function<int(const Error&)> exit_code;  // the CLI's exit code of an error (for "exit_code")
  // Without tokens, Host values served besides the listen address's own
  // ("plant-pc:8470", "localhost:9000" for an ssh tunnel); lower case.
  std::vector<std::string> allowed_hosts;
  // The connection limits and timeouts (max_body above wins over server.limits).
  web::ServerOptions server;
  // HTTPS (OpenSSL, web/web_tls.hpp) with this PEM certificate (chain)
  // and private key; both empty: plain HTTP.
  std::string tls_cert, tls_key;
  ConsoleOptions console;  // the web console's sessions (docs/console.md)
};

// Whether `opt` may be served: a non-loopback address needs tokens and TLS,
// TLS needs both files. Errc::invalid_argument saying what is missing.
Result<void> check_exposure(const HttpOptions& opt, const std::string& listen_text);
// Whether the TLS certificate and key load (nothing to check without TLS).
// Errc::file_error naming both files.
Result<void> check_tls_files(const HttpOptions& opt);

class HttpServer {
 public:
  HttpServer(Service& service, HttpOptions opt);
  ~HttpServer();
  // Binds the address; the port bound (the free one chosen for port 0).
  // Errc::io_error naming the address when it cannot be bound (or when the
  // console finds no random bytes for its CSRF token);
  // Errc::file_error naming the files when the certificate or key cannot be loaded.
  Result<int> bind();
  // Serves until stop() (from another thread; a stop() before serve() has
  // begun makes serve() return at once).
  void serve();
  void stop();
  web::ServerStats stats() const;
  // The answers to one connection's bytes as the server would send them,
  // without a socket: each complete request through the same checks, routes
  // and handlers, then the refusal of bytes the parser refuses (nothing for
  // an unfinished request). After bind() (the console, the port). For the
  // fuzz target (fuzz/fuzz_http.cpp) and tests.
  std::string answer(std::string_view bytes, const std::string& remote_addr, bool tls);

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace lmcfg::serve
