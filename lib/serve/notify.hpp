#pragma once
// Delivery of the service's events (docs/serve.md "States and events"): the inventory's
// [notify] command gets each event's JSON on stdin, its webhook a POST of it.
// Delivery runs on its own thread, so a slow receiver never holds up a line;
// a webhook that fails is retried with back-off and logged when given up.
#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

#include "common/result.hpp"
#include "common/text.hpp"

namespace lmcfg::serve {

struct NotifyOptions {
  std::string webhook;    // http:// or https:// URL; "" = none
  std::string command;    // absolute path of a program; "" = none
  int attempts = 5;       // webhook tries before giving up
  int backoff_ms = 1000;  // wait before the second try, doubled before each next
  std::function<void(const std::string&)> log;
};

// Runs `program` (no shell) with `input` on its stdin; Errc::io_error when it
// cannot be started or exits other than 0.
Result<void> run_with_stdin(const std::string& program, const std::string& input);
// Whether this build can deliver to `url`: Errc::invalid_argument for an
// https:// webhook where cpp-httplib has no TLS (the Windows build), so the
// service refuses it at start instead of dropping every event.
Result<void> check_webhook(const std::string& url);
// POSTs `json` to `url` once (cpp-httplib client); Errc::io_error naming the
// HTTP status or the connection failure.
Result<void> post_json(const std::string& url, const std::string& json);

class Notifier {
 public:
  explicit Notifier(NotifyOptions opt);
  ~Notifier();  // delivers what is queued (without further retries' waits), then stops
  Notifier(const Notifier&) = delete;
  Notifier& operator=(const Notifier&) = delete;
  void send(std::string json);
  // Until every event sent so far has been delivered or given up (tests).
  void flush();

 private:
  void run();
  // One event to the command and the webhook (with the webhook's retries).
  void deliver(const std::string& json);
  void log(const std::string& s) const {
    if (opt_.log) opt_.log(log_text(s));  // events quote peers' and drives' text
  }
  NotifyOptions opt_;
  std::mutex mu_;
  std::condition_variable cv_;
  std::deque<std::string> queue_;
  bool busy_ = false, stopping_ = false;
  std::thread thread_;
};

}  // namespace lmcfg::serve
