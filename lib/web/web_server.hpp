#pragma once
// The web layer's HTTP/1.1 server, lmcfg serve's (docs/serve.md "Security
// model"). The layer (lib/web: messages, routes, sockets, TLS) uses common
// only: the service, its routes and the console (lib/serve) use it, never
// the other way round, and the build refuses an include of serve here
// (tests/layering-test.py). One event
// loop thread holds every connection (a held connection costs a buffer, not a
// thread), a few worker threads run the handlers. Every resource a client can
// make it spend is bounded:
//   - request head, header count and body size (web::Limits), every
//     transfer coding;
//   - time: a request's head must be complete within head_timeout of its
//     first byte (of the connection's start for the first request), its body
//     within body_timeout of the head; a slow client gets 408 and is closed;
//     an idle keep-alive connection is closed after idle_timeout; an answer
//     that the client does not take within write_timeout is dropped;
//   - connections: max_connections in all, max_per_address per client
//     address. A new connection over a limit evicts a connection that has no
//     request with a worker (idle, or still sending its head or its body):
//     the oldest from the same address (per-address limit), or the oldest
//     from the address holding the most connections (total limit), so held
//     connections never lock a legitimate client out and no address pushes
//     out another's; when none can go, the new one is answered 503 and closed;
//   - handlers: queued_max requests waiting for a worker, then 503.
// A handler's exception answers 500 and is logged; it never ends the process.
#include <atomic>
#include <chrono>
#include <functional>
#include <memory>
#include <string>

#include "common/result.hpp"
#include "web/web_message.hpp"
#include "web/web_tls.hpp"

namespace lmcfg::web {

struct ServerOptions {
  Limits limits;
  std::size_t max_connections = 512;
  std::size_t max_per_address = 128;
  std::chrono::milliseconds head_timeout{10'000};
  std::chrono::milliseconds body_timeout{10'000};
  std::chrono::milliseconds idle_timeout{5'000};
  std::chrono::milliseconds write_timeout{30'000};
  std::size_t max_requests_per_connection = 1000;
  int workers = 4;
  std::size_t queued_max = 256;
  std::shared_ptr<TlsContext> tls;  // null: plain HTTP
  // The application: fills the response (the server adds Content-Length and
  // Connection). Called on a worker thread; may throw (500).
  std::function<void(Request&, Response&)> handle;
  // The answer to a request the parser refused (400, 408, 413, 431 ...),
  // given the status and the message; default: a text/plain body.
  std::function<void(int, const std::string&, Response&)> error_page;
  std::function<void(const std::string&)> log;  // one line per event
};

struct ServerStats {
  std::size_t open = 0;  // connections open now
  std::size_t accepted = 0, evicted = 0, refused = 0, timed_out = 0, handler_errors = 0;
};

class Server {
 public:
  explicit Server(ServerOptions opt);
  ~Server();
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;
  // Binds HOST:PORT (port 0: any free one) without SO_REUSEPORT (a second
  // server on the same port fails); the port bound. Errc::io_error naming the
  // address when it cannot be bound.
  Result<int> bind(const std::string& host, int port);
  // Serves until stop() (from any thread; a stop() before serve() makes
  // serve() return at once). Open connections are closed; handlers running
  // finish first.
  void serve();
  void stop();
  ServerStats stats() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace lmcfg::web
