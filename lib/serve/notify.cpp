#include "serve/notify.hpp"

#include <httplib.h>

#include <chrono>

namespace lmcfg::serve {

Result<void> check_webhook(const std::string& url) {
#ifndef CPPHTTPLIB_OPENSSL_SUPPORT
  if (url.rfind("https://", 0) == 0)
    return Error(Errc::invalid_argument,
                 "[notify] webhook " + url +
                     ": this build of lmcfg serve posts to http:// webhooks only (its HTTP "
                     "client has no TLS; docs/windows.md); use an http:// receiver on this host "
                     "or a [notify] command");
#else
  (void)url;
#endif
  return {};
}

Result<void> post_json(const std::string& url, const std::string& json) {
  // scheme://host[:port]/path: httplib's Client takes the first part, Post the path.
  const auto scheme_end = url.find("://");
  const auto path_at = url.find('/', scheme_end == std::string::npos ? 0 : scheme_end + 3);
  const std::string base = url.substr(0, path_at);
  const std::string path = path_at == std::string::npos ? "/" : url.substr(path_at);
  httplib::Client client(base);
  client.set_connection_timeout(5);
  client.set_read_timeout(10);
  client.set_write_timeout(10);
  auto res = client.Post(path.c_str(), json, "application/json");
  if (!res) return Error(Errc::io_error, "webhook " + url + ": " + httplib::to_string(res.error()));
  if (res->status < 200 || res->status > 299)
    return Error(Errc::io_error, "webhook " + url + ": HTTP " + std::to_string(res->status));
  return {};
}

Notifier::Notifier(NotifyOptions opt) : opt_(std::move(opt)), thread_([this] { run(); }) {}

Notifier::~Notifier() {
  {
    std::lock_guard<std::mutex> lock(mu_);
    stopping_ = true;
  }
  cv_.notify_all();
  thread_.join();
}

void Notifier::send(std::string json) {
  {
    std::lock_guard<std::mutex> lock(mu_);
    queue_.push_back(std::move(json));
  }
  cv_.notify_all();
}

void Notifier::flush() {
  std::unique_lock<std::mutex> lock(mu_);
  cv_.wait(lock, [this] { return queue_.empty() && !busy_; });
}

void Notifier::run() {
  std::unique_lock<std::mutex> lock(mu_);
  for (;;) {
    cv_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
    if (queue_.empty()) return;  // stopping and nothing left
    std::string json = std::move(queue_.front());
    queue_.pop_front();
    busy_ = true;
    lock.unlock();
    // A delivery that throws (a bug, a library throwing) drops that event,
    // said in the log; the thread goes on with the next (it must never end
    // the service).
    try {
      deliver(json);
    } catch (const std::exception& e) {
      log(std::string("notify: delivery failed (") + e.what() + "), event dropped: " + json);
    } catch (...) {
      log("notify: delivery failed (an exception of unknown type), event dropped: " + json);
    }
    lock.lock();
    busy_ = false;
    cv_.notify_all();
  }
}

void Notifier::deliver(const std::string& json) {
  if (!opt_.command.empty()) {
    if (auto ran = run_with_stdin(opt_.command, json + "\n"); !ran.ok()) log(ran.error().message);
  }
  if (opt_.webhook.empty()) return;
  int wait_ms = opt_.backoff_ms;
  for (int attempt = 1; attempt <= opt_.attempts; ++attempt) {
    auto posted = post_json(opt_.webhook, json);
    if (posted.ok()) return;
    if (attempt == opt_.attempts) {
      log(posted.error().message + "; gave up after " + std::to_string(attempt) +
          " attempt(s), event dropped: " + json);
      return;
    }
    log(posted.error().message + "; attempt " + std::to_string(attempt) + " of " +
        std::to_string(opt_.attempts) + ", next in " + std::to_string(wait_ms) + " ms");
    // Waits for the back-off, or less when the service stops.
    std::unique_lock<std::mutex> w(mu_);
    if (cv_.wait_for(w, std::chrono::milliseconds(wait_ms), [this] { return stopping_; })) {
      w.unlock();
      // Stopping: one last try without waiting, then give up.
      if (!post_json(opt_.webhook, json).ok())
        log("webhook " + opt_.webhook + ": stopping, event dropped: " + json);
      return;
    }
    wait_ms *= 2;
  }
}

}  // namespace lmcfg::serve
