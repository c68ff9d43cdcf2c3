#pragma once
// Helpers shared by the client's source files (client.cpp, lists.cpp, blocks.cpp).
#include <cstdio>
#include <map>
#include <string>

#include "client/client.hpp"
#include "common/result.hpp"

namespace lmcfg::client::detail {

inline std::string hexid(const char* fmt, unsigned v) {
  char buf[96];
  std::snprintf(buf, sizeof buf, fmt, v);
  return buf;
}

// Lost, garbled or mis-addressed answers (ErrorClass::bad_answer), as opposed
// to a drive's refusal or a link that is gone (closed, I/O error): a read that
// fails with one of these may be repeated.
inline bool is_link_error(const Error& e) { return e.code == ErrorClass::bad_answer; }

// Restarts of a block or list transfer while they make progress. Blocks
// measure progress as a growing number (votes gathered): a pass that raised it
// resets the count of passes without progress. Lists count failures per
// position (entries received before the failure). `limit` passes in a row
// without progress, `limit` failures at one position, or the deadline end it.
class RestartBudget {
 public:
  RestartBudget(int limit, transport::Millis deadline)
      : limit_(limit), end_(transport::Clock::now() + deadline) {}
  // After a pass that reached `progress` (votes, items): may it restart?
  bool another(std::size_t progress) {
    ++passes_;
    if (progress > best_) {
      best_ = progress;
      stuck_ = 0;
    } else {
      ++stuck_;
    }
    return stuck_ < limit_ && !out_of_time();
  }
  // After a pass that failed at `position`: may it restart?
  bool another_at(std::size_t position) {
    ++passes_;
    return ++fails_[position] < limit_ && !out_of_time();
  }
  bool out_of_time() const { return transport::Clock::now() >= end_; }
  int passes() const { return passes_; }

 private:
  int limit_;
  transport::Clock::time_point end_;
  std::size_t best_ = 0;
  int stuck_ = 0;
  int passes_ = 0;
  std::map<std::size_t, int> fails_;
};

// Same answer: equal values, or the same refusal state.
template <class T>
bool same_answer(const Result<T>& a, const Result<T>& b) {
  if (a.ok() != b.ok()) return false;
  if (a.ok()) return *a == *b;
  return a.error().code == b.error().code;
}

}  // namespace lmcfg::client::detail

namespace lmcfg::client {

// Reads until agreeing_reads() answers agree; a refusal (C1..C9) is an answer
// too, a link failure (after the transact's own retries) ends it. With one
// read required this is just `read()`.
template <class T, class F>
Result<T> LinrsClient::agreed(F&& read) {
  return agreed<T>(std::forward<F>(read), [this](const Result<T>&) { return agreeing_reads(); });
}

template <class T, class F, class N>
Result<T> LinrsClient::agreed(F&& read, N&& need_for) {
  std::vector<Result<T>> seen;
  int link_failures = 0;
  // The limit grows by one if the line shows corruption during this value.
  const auto max_reads = [&] { return agreeing_reads() + 2 + opt_.read_retries; };
  for (int i = 0; i < max_reads(); ++i) {
    if (i > 0) ++stats_.extra_reads;
    if (i >= 2) ++stats_.third_reads;
    Result<T> r = read();
    if (!r.ok() && r.error().code != ErrorClass::drive_refusal) {
      // A read that failed on the link (after the transact's own retries) gets
      // one more chance from the same budget; a second one ends it.
      if (!detail::is_link_error(r.error()) || link_failures++ > 0) return r;
      continue;
    }
    int count = 1;
    for (const auto& s : seen) {
      if (detail::same_answer(s, r))
        ++count;
      else
        noise_seen_ = true;  // reads of one value disagreed: the line flips bits
    }
    const int need = need_for(r);
    if (count >= need) {
      if (static_cast<int>(seen.size()) + 1 > need) ++stats_.disagreements;
      return r;
    }
    seen.push_back(std::move(r));
  }
  ++stats_.disagreements;
  return Error(Errc::unexpected_response,
               "no " + std::to_string(agreeing_reads()) + " of " + std::to_string(max_reads()) +
                   " reads agreed (no checksum on this link: a flipped bit cannot be detected)");
}

}  // namespace lmcfg::client
