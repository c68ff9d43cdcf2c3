#include "web/web_server.hpp"

#include <algorithm>
#include <cctype>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <map>
#include <mutex>
#include <string_view>
#include <thread>
#include <vector>

#include "common/text.hpp"
#include "web/web_socket.hpp"

namespace lmcfg::web {

namespace {

using SteadyClock = std::chrono::steady_clock;
using SteadyTime = SteadyClock::time_point;

enum class Phase { handshake, reading, handling, writing };

struct Connection {
  int fd = -1;
  std::uint64_t id = 0;
  std::string addr;
  std::unique_ptr<TlsStream> tls;
  RequestParser parser;
  Phase phase = Phase::reading;
  SteadyTime since;            // start of the current wait (connection, request, head, write)
  bool request_begun = false;  // bytes of a request have arrived
  std::string out;             // bytes to write
  std::size_t out_pos = 0;
  bool close_after = false;  // close once `out` is written
  std::size_t served = 0;
  bool want_write = false;  // TLS: the last step wants the socket writable
  explicit Connection(const Limits& l) : parser(l) {}
};

struct Done {
  std::uint64_t id;
  std::string bytes;
  bool close;
};

}  // namespace

struct Server::Impl {
  ServerOptions opt;
  int listen_fd = -1;
  Waker waker;
  std::atomic<bool> stop_asked{false}, entered{false};
  std::map<std::uint64_t, std::unique_ptr<Connection>> conns;
  std::uint64_t next_id = 1;

  // Workers: requests in, answers out.
  std::mutex mu;
  std::condition_variable cv;
  std::deque<std::pair<std::uint64_t, Request>> queue;
  std::deque<Done> done;
  bool workers_stop = false;
  std::vector<std::thread> workers;

  mutable std::mutex stats_mu;
  ServerStats st;
  SteadyTime last_refusal_log{};

  explicit Impl(ServerOptions o) : opt(std::move(o)) {}

  void log(const std::string& s) const {
    if (opt.log) opt.log(log_text(s));  // whatever a client sent, escaped (common/text.hpp)
  }
  void poke() const { waker.poke(); }
  template <typename F>
  void count(F f) {
    std::lock_guard<std::mutex> lock(stats_mu);
    f(st);
  }

  Response error_response(int status, const std::string& message) const {
    Response res;
    res.status = status;
    if (opt.error_page) {
      opt.error_page(status, message, res);
    } else {
      res.set_content(message + "\n", "text/plain; charset=utf-8");
    }
    res.close = true;
    return res;
  }

  // ---- workers

  void worker() {
    while (true) {
      std::pair<std::uint64_t, Request> job;
      {
        std::unique_lock<std::mutex> lock(mu);
        cv.wait(lock, [&] { return workers_stop || !queue.empty(); });
        if (queue.empty()) return;
        job = std::move(queue.front());
        queue.pop_front();
      }
      Request& req = job.second;
      Response res;
      try {
        opt.handle(req, res);
      } catch (const std::exception& e) {
        count([](ServerStats& s) { ++s.handler_errors; });
        log("http " + req.remote_addr + " " + req.method + " " + printable(req.target) +
            ": internal error: " + printable(e.what()));
        res = error_response(500,
                             "internal error while answering this request; the service "
                             "goes on (its log has the details)");
        res.close = false;
      } catch (...) {
        count([](ServerStats& s) { ++s.handler_errors; });
        res = error_response(500, "internal error while answering this request");
        res.close = false;
      }
      const bool keep = wants_keep_alive(req) && !res.close;
      res.close = !keep;
      Done d{job.first, serialize(res, req.method == "HEAD"), !keep};
      {
        std::lock_guard<std::mutex> lock(mu);
        done.push_back(std::move(d));
      }
      poke();
    }
  }

  static bool wants_keep_alive(const Request& req) {
    const std::string c = req.get_header_value("Connection");
    const auto has = [&](const char* word) {
      std::string lc;
      for (char ch : c)
        lc.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(ch))));
      return lc.find(word) != std::string::npos;
    };
    if (req.version_minor == 0) return has("keep-alive");
    return !has("close");
  }

  // ---- connections

  void close_conn(std::uint64_t id) {
    auto it = conns.find(id);
    if (it == conns.end()) return;
    it->second->tls.reset();
    close_socket(it->second->fd);
    conns.erase(it);
  }

  // Whether `c` holds a slot without a request in progress: waiting for its
  // first byte, idle between requests, in its TLS handshake, sending its head,
  // or sending the body its head announced. A client that announces a body
  // and never sends it holds a slot as surely as one that never ends its head.
  static bool evictable(const Connection& c) {
    return c.phase == Phase::handshake || c.phase == Phase::reading;
  }

  // The connection that makes room for a new one: with `addr`, the oldest
  // evictable one from that address; with "", one from the address that
  // holds the most connections (the oldest among equals), so that no address
  // pushes out the few of another. nullptr when none can go.
  Connection* victim(const std::string& addr) {
    std::map<std::string_view, std::size_t> per_addr;
    if (addr.empty())
      for (auto& kv : conns) ++per_addr[kv.second->addr];
    Connection* best = nullptr;
    std::size_t best_n = 0;
    for (auto& kv : conns) {
      Connection* c = kv.second.get();
      if (!evictable(*c) || (!addr.empty() && c->addr != addr)) continue;
      const std::size_t n = addr.empty() ? per_addr[c->addr] : 0;
      if (!best || n > best_n || (n == best_n && c->since < best->since)) {
        best = c;
        best_n = n;
      }
    }
    return best;
  }

  void refuse(int fd, const std::string& addr, const std::string& why) {
    count([](ServerStats& s) { ++s.refused; });
    if (!opt.tls) {
      Response r = error_response(503, "too many connections: " + why + "; try again later");
      r.set_header("Retry-After", "1");
      send_now(fd, serialize(r, false));
    }
    close_socket(fd);
    const auto now = SteadyClock::now();
    if (now - last_refusal_log > std::chrono::seconds(1)) {
      last_refusal_log = now;
      log("http " + addr + ": connection refused (" + why + ")");
    }
  }

  void accept_all() {
    while (true) {
      std::string addr;
      const int fd = accept_one(listen_fd, addr);
      if (fd == -1) return;  // none waiting, or a resource limit: the next wait tries again
      const auto from_addr = static_cast<std::size_t>(std::count_if(
          conns.begin(), conns.end(), [&](auto& kv) { return kv.second->addr == addr; }));
      if (from_addr >= opt.max_per_address || conns.size() >= opt.max_connections) {
        const bool per_addr = from_addr >= opt.max_per_address;
        Connection* v = victim(per_addr ? addr : "");
        if (!v) {
          refuse(fd, addr,
                 per_addr ? std::to_string(from_addr) + " open from " + addr
                          : std::to_string(conns.size()) + " open in all");
          continue;
        }
        count([](ServerStats& s) { ++s.evicted; });
        close_conn(v->id);
      }
      auto c = std::make_unique<Connection>(opt.limits);
      c->fd = fd;
      c->id = next_id++;
      c->addr = addr;
      c->since = SteadyClock::now();
      if (opt.tls) {
        c->tls = std::make_unique<TlsStream>(*opt.tls, fd);
        if (!c->tls->valid()) {
          close_socket(fd);
          continue;
        }
        c->phase = Phase::handshake;
      }
      count([](ServerStats& s) { ++s.accepted; });
      conns.emplace(c->id, std::move(c));
    }
  }

  IoStep read_some(Connection& c, char* buf, std::size_t size) {
    if (c.tls) return c.tls->read(buf, size);
    return recv_some(c.fd, buf, size);
  }

  IoStep write_some(Connection& c, const char* buf, std::size_t size) {
    if (c.tls) return c.tls->write(buf, size);
    return send_some(c.fd, buf, size);
  }

  // Queues a response written by the loop itself (parser errors, 503s).
  void answer_now(Connection& c, const Response& res) {
    c.out = serialize(res, false);
    c.out_pos = 0;
    c.close_after = true;
    c.phase = Phase::writing;
    c.since = SteadyClock::now();
  }

  // The parser's outcome on `c`: a request to the workers, an error answer,
  // a 100 Continue, or nothing yet. false: `c` was closed.
  bool after_parse(Connection& c, RequestParser::State s) {
    if (s == RequestParser::State::error) {
      answer_now(c, error_response(c.parser.error_status(), c.parser.error_message()));
      log("http " + c.addr + " refused: " + std::to_string(c.parser.error_status()) + " " +
          c.parser.error_message());
      return true;
    }
    if (s == RequestParser::State::need_more) {
      if (c.parser.started() && !c.request_begun) {
        // A connection's first request has head_timeout from the connection's
        // start; a later one from its first byte.
        c.request_begun = true;
        if (c.served > 0) c.since = SteadyClock::now();
      }
      if (c.parser.wants_continue()) {
        c.parser.continued();
        c.out = "HTTP/1.1 100 Continue\r\n\r\n";
        c.out_pos = 0;
        c.close_after = false;
        flush(c);  // small; whatever does not go now goes with the answer
      }
      return true;
    }
    // complete
    Request req = std::move(c.parser.request());
    req.remote_addr = c.addr;
    req.tls = static_cast<bool>(c.tls);
    c.phase = Phase::handling;
    ++c.served;
    std::unique_lock<std::mutex> lock(mu);
    if (queue.size() >= opt.queued_max) {
      lock.unlock();
      answer_now(c, error_response(503, "the service is busy (" + std::to_string(opt.queued_max) +
                                            " requests waiting): try again in a moment"));
      return true;
    }
    if (c.served >= opt.max_requests_per_connection) req.headers.emplace("Connection", "close");
    queue.emplace_back(c.id, std::move(req));
    lock.unlock();
    cv.notify_one();
    return true;
  }

  // Writes what it can of c.out; false: closed.
  bool flush(Connection& c) {
    while (c.out_pos < c.out.size()) {
      const IoStep r = write_some(c, c.out.data() + c.out_pos, c.out.size() - c.out_pos);
      if (r.closed) {
        close_conn(c.id);
        return false;
      }
      if (r.want_write || r.want_read) {
        c.want_write = r.want_write;
        return true;
      }
      c.out_pos += r.n;
    }
    c.out.clear();
    c.out_pos = 0;
    return true;
  }

  void on_readable(Connection& c) {
    if (c.phase == Phase::handshake) {
      const IoStep r = c.tls->handshake();
      if (r.closed) return close_conn(c.id);
      c.want_write = r.want_write;
      if (r.n == 1) {
        c.phase = Phase::reading;
        c.since = SteadyClock::now();
      } else {
        return;
      }
    }
    if (c.phase != Phase::reading) return;
    char buf[8192];
    for (int round = 0; round < 8; ++round) {
      const IoStep r = read_some(c, buf, sizeof buf);
      if (r.closed) return close_conn(c.id);
      if (r.want_read || r.want_write) {
        c.want_write = r.want_write;
        return;
      }
      const auto s = c.parser.feed(std::string_view(buf, r.n));
      const std::uint64_t id = c.id;
      if (!after_parse(c, s) || !conns.count(id)) return;
      if (c.phase != Phase::reading) return;
    }
  }

  void on_writable(Connection& c) {
    if (c.phase == Phase::handshake) return on_readable(c);
    if (c.out.empty()) {
      c.want_write = false;
      if (c.phase == Phase::reading) on_readable(c);  // TLS read that wanted a write
      return;
    }
    const std::uint64_t id = c.id;
    if (!flush(c) || !conns.count(id)) return;
    if (!c.out.empty() || c.phase != Phase::writing) return;
    if (c.close_after) return close_conn(id);
    // The answer is out: the next request (perhaps already buffered).
    c.parser.next();
    c.phase = Phase::reading;
    c.request_begun = c.parser.buffered() > 0;
    c.since = SteadyClock::now();
    if (c.parser.buffered() > 0) after_parse(c, c.parser.parse());
  }

  void collect_done() {
    std::deque<Done> ready;
    {
      std::lock_guard<std::mutex> lock(mu);
      ready.swap(done);
    }
    for (auto& d : ready) {
      auto it = conns.find(d.id);
      if (it == conns.end()) continue;
      Connection& c = *it->second;
      c.out = std::move(d.bytes);
      c.out_pos = 0;
      c.close_after = d.close;
      c.phase = Phase::writing;
      c.since = SteadyClock::now();
      on_writable(c);
    }
  }

  void expire() {
    const auto now = SteadyClock::now();
    std::vector<std::uint64_t> idle;
    for (auto& [id, cp] : conns) {
      Connection& c = *cp;
      if (c.phase == Phase::handling) continue;
      if (c.phase == Phase::writing) {
        if (now - c.since > opt.write_timeout) idle.push_back(id);
        continue;
      }
      if (c.phase == Phase::handshake) {
        if (now - c.since > opt.head_timeout) idle.push_back(id);
        continue;
      }
      const bool first = c.served == 0;
      if (!c.request_begun) {
        // Nothing sent yet: an idle keep-alive connection, or a new one that
        // says nothing (the first request's head has head_timeout).
        if (now - c.since > (first ? opt.head_timeout : opt.idle_timeout)) idle.push_back(id);
        continue;
      }
      const auto limit = c.parser.head_complete() ? opt.body_timeout : opt.head_timeout;
      if (now - c.since > limit) {
        count([](ServerStats& s) { ++s.timed_out; });
        const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(limit).count();
        const std::string span =
            ms % 1000 ? std::to_string(ms) + " ms" : std::to_string(ms / 1000) + " s";
        const char* part = c.parser.head_complete() ? "body" : "head";
        log("http " + c.addr + ": the request's " + part + " did not arrive within " + span +
            ", closed (408)");
        answer_now(c, error_response(408, std::string("the request's ") + part +
                                              " did not arrive within " + span));
        c.since = now;
        if (flush(c) && conns.count(id) && c.out.empty()) idle.push_back(id);
      }
    }
    for (auto id : idle) close_conn(id);
  }

  void loop() {
    std::vector<Watch> fds;
    std::vector<std::uint64_t> ids;
    while (!stop_asked) {
      fds.clear();
      ids.clear();
      fds.push_back({waker.socket(), true, false});
      fds.push_back({listen_fd, true, false});
      bool pending_tls = false;
      for (auto& [id, c] : conns) {
        Watch w;
        w.socket = c->fd;
        w.read = c->phase == Phase::handshake || c->phase == Phase::reading;
        w.write = c->want_write || (c->phase == Phase::writing && !c->out.empty());
        // A connection whose request is with a worker is not watched: a
        // client that hangs up then would make the wait report a hang-up at
        // once, round after round, until the answer is ready.
        if (c->phase == Phase::handling) continue;
        if (c->tls && c->phase == Phase::reading && c->tls->has_buffered()) pending_tls = true;
        fds.push_back(w);
        ids.push_back(id);
      }
      if (!wait_sockets(fds, pending_tls ? 0 : 250)) break;
      if (fds[0].readable) waker.drain();
      collect_done();
      for (std::size_t i = 2; i < fds.size(); ++i) {
        auto it = conns.find(ids[i - 2]);
        if (it == conns.end()) continue;
        Connection& c = *it->second;
        const Watch& w = fds[i];
        const bool tls_pending = c.tls && c.phase == Phase::reading && c.tls->has_buffered();
        if (w.failed) {
          close_conn(c.id);
          continue;
        }
        if (w.writable) {
          const std::uint64_t id = c.id;
          on_writable(c);
          if (!conns.count(id)) continue;
        }
        if (w.readable || w.hangup || tls_pending) on_readable(c);
      }
      if (fds[1].readable) accept_all();
      expire();
      count([&](ServerStats& s) { s.open = conns.size(); });
    }
  }
};

Server::Server(ServerOptions opt) : impl_(std::make_unique<Impl>(std::move(opt))) {}

Server::~Server() { close_socket(impl_->listen_fd); }

Result<int> Server::bind(const std::string& host, int port) {
  LMCFG_ASSIGN_OR_RETURN(Listener l, listen_on(host, port));
  if (auto woke = impl_->waker.open(); !woke.ok()) {
    close_socket(l.socket);
    return woke.error();
  }
  impl_->listen_fd = l.socket;
  return l.port;
}

void Server::serve() {
  impl_->entered = true;
  if (impl_->stop_asked || impl_->listen_fd < 0) return;
  ignore_broken_pipe();
  for (int i = 0; i < std::max(1, impl_->opt.workers); ++i)
    impl_->workers.emplace_back([this] { impl_->worker(); });
  impl_->loop();
  {
    std::lock_guard<std::mutex> lock(impl_->mu);
    impl_->workers_stop = true;
    impl_->queue.clear();
  }
  impl_->cv.notify_all();
  for (auto& t : impl_->workers) t.join();
  impl_->workers.clear();
  std::vector<std::uint64_t> ids;
  for (auto& kv : impl_->conns) ids.push_back(kv.first);
  for (auto id : ids) impl_->close_conn(id);
}

void Server::stop() {
  impl_->stop_asked = true;
  if (impl_->listen_fd != -1) impl_->poke();
}

ServerStats Server::stats() const {
  std::lock_guard<std::mutex> lock(impl_->stats_mu);
  return impl_->st;
}

}  // namespace lmcfg::web
