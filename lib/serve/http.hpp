#pragma once
// The HTTP side of lmcfg serve (docs/serve.md "API"): cpp-httplib's server,
// a thin adapter from routes to Service calls. Authorization: with tokens, a
// bearer token is required (viewer: GET, operator: also POST); without, every
// client is an operator, which only a loopback address makes acceptable (the
// tool refuses anything else).
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/result.hpp"
#include "serve/console.hpp"
#include "serve/service.hpp"
#include "serve/tokens.hpp"

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
  // HTTPS (cpp-httplib's SSLServer, OpenSSL) with this PEM certificate (chain)
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

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace lmcfg::serve
