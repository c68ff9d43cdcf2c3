#include "client/client.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "client/internal.hpp"
#include "common/layers.hpp"

namespace lmcfg::client {

using namespace codec;
using detail::hexid;
using detail::is_link_error;

LinrsClient::LinrsClient(transport::Transport& link, ClientOptions opt)
    : Client(opt), link_(link), decoder_(opt.checksum) {}

namespace {

// What a refused request was about, for the message: " for UPID 5555h" etc.
std::string refused_subject(const Telegram& r) {
  if (r.data.size() < 2) return {};
  const unsigned key = r.data[0] | r.data[1] << 8;
  char buf[32] = "";
  if (static_cast<Main>(r.main) == Main::parameter ||
      (static_cast<Main>(r.main) == Main::param_config && request_key(r)))
    std::snprintf(buf, sizeof buf, " for UPID %04Xh", key);
  else if (static_cast<Main>(r.main) == Main::curve && request_key(r))
    std::snprintf(buf, sizeof buf, " for curve %u", key);
  else if (static_cast<Main>(r.main) == Main::command_table && r.sub != 0x07 && request_key(r))
    std::snprintf(buf, sizeof buf, " for entry %u", key);
  return buf;
}

// Communication states a manual names: 00/04/C6 and the error states of
// common/result.cpp's table (LinRS §16.1, and D7h of LinRS 3V27 p32).
bool documented_state(std::uint8_t s) {
  return s == 0x00 || s == 0x04 || s == 0xC6 || comm_state_text(s) != nullptr;
}

}  // namespace

int LinrsClient::agreeing_reads() const {
  if (opt_.agreeing_reads > 0) return opt_.agreeing_reads;
  if (opt_.checksum.mode != codec::ChecksumMode::none || opt_.link_has_parity) return 1;
  return noise_seen_ ? std::max(2, opt_.noisy_agreeing_reads) : 2;
}

namespace {
// Longest data (after SUB MAIN) an answer to `req` can carry: the group's
// answers (at most 11 bytes: 73h error log entry), error texts (71h: state,
// code, 32 characters), or the default response form (the configured layout
// and a read value), which any request may draw (error states).
std::size_t max_answer_data(const Telegram& req, const DefaultResponseLayout& layout) {
  const std::uint8_t sub = expected_answer_sub(req);
  const std::size_t group = (sub & 0xF0) == 0x70 ? 35 : 11;
  return std::max(group, layout.size() + (layout.mc_response ? 0 : 4));
}
constexpr double kUnknownByteUs = 10.0 * 1e6 / 4800.0;  // TCP gateway: assume the slowest rate
}  // namespace

double LinrsClient::wire_us(std::size_t bytes) const {
  const double bt = link_.byte_time_us();
  return static_cast<double>(bytes) * (bt > 0.0 ? bt : kUnknownByteUs);
}

std::int64_t LinrsClient::deadline_floor_us(const Telegram& req) const {
  // 01 ID LEN 02 SUB MAIN .. [CS] 04: LEN counts 02, SUB, MAIN and the data.
  const std::size_t overhead = 7 + opt_.checksum.size();
  const std::size_t bytes = 2 * overhead + req.data.size() + max_answer_data(req, opt_.layout);
  const double us = wire_us(bytes) +
                    1000.0 * (opt_.turnaround_max_ms + link_.receive_latency_ms()) +
                    1000.0 * opt_.deadline_margin_ms;
  return static_cast<std::int64_t>(us + 0.5);
}

std::int64_t LinrsClient::answer_deadline_us(const Telegram& req) const {
  const std::int64_t cap = static_cast<std::int64_t>(opt_.timeout.count()) * 1000;
  if (!opt_.adaptive_deadline || srtt_us_ < 0) return cap;
  const std::int64_t floor = deadline_floor_us(req);
  // The measured part replaces the turnaround (and latency) of the floor when larger.
  const double measured = srtt_us_ + 4.0 * rttvar_us_;
  const double fixed_turn = 1000.0 * (opt_.turnaround_max_ms + link_.receive_latency_ms());
  double us = static_cast<double>(floor) + std::max(0.0, measured - fixed_turn);
  for (int i = 0; i < backoff_ && us < static_cast<double>(cap); ++i) us *= 2.0;
  return std::min(cap, static_cast<std::int64_t>(us + 0.5));
}

std::int64_t LinrsClient::corrupt_answer_quiet_us() const {
  const double us = 1000.0 * (link_.receive_latency_ms() + opt_.deadline_margin_ms) + wire_us(2);
  return static_cast<std::int64_t>(us + 0.5);
}

void LinrsClient::rtt_sample(double excess_us) {
  excess_us = std::max(0.0, excess_us);
  ++stats_.rtt_samples;
  if (srtt_us_ < 0) {
    srtt_us_ = excess_us;
    rttvar_us_ = excess_us / 2.0;
  } else {
    rttvar_us_ = 0.75 * rttvar_us_ + 0.25 * std::abs(srtt_us_ - excess_us);
    srtt_us_ = 0.875 * srtt_us_ + 0.125 * excess_us;
  }
}

Result<void> LinrsClient::settle_line() {
  ++stats_.settles;
  Millis quiet = opt_.settle;
  if (opt_.adaptive_settle && link_.byte_time_us() > 0.0 && settle_quiet_us_ > 0)
    quiet = std::min(opt_.settle, Millis((settle_quiet_us_ + 999) / 1000));
  bool late_counted = false;
  // Bounded: a line that never goes quiet is a link problem, not an answer.
  for (int reads = 0; reads < 256; ++reads) {
    auto chunk = link_.read_some(quiet);
    if (!chunk.ok()) return std::move(chunk).error();
    if (chunk->empty()) {
      unsettled_ = false;
      return {};
    }
    stats_.bytes_rx += chunk->size();
    stats_.settle_bytes += chunk->size();
    if (!late_counted) {
      // An answer after its deadline (or noise): the deadline was too short
      // for this link; its round trip feeds the estimate (adaptive_deadline).
      late_counted = true;
      ++stats_.late_answers;
      if (opt_.adaptive_deadline && last_send_ns_ > 0) {
        const double rtt_us = static_cast<double>(link_.now_ns() - last_send_ns_) / 1000.0;
        max_rtt_us_ = std::max(max_rtt_us_, rtt_us);
        rtt_sample(rtt_us - wire_us(chunk->size()));
      }
    }
  }
  return Error(Errc::io_error, "the line to drive " + hexid("%02Xh", opt_.id) +
                                   " does not go quiet (" + std::to_string(quiet.count()) +
                                   " ms without bytes never seen in 256 reads)");
}

// One request's exchange, shared by the phases of transact().
struct LinrsClient::Exchange {
  Telegram req;
  Bytes wire;
  std::uint8_t want_sub = 0;
  std::optional<std::uint16_t> want_key;
  Millis timeout{};
  bool ordinary = false;  // may wait the adaptive deadline (see transact)
  // Per attempt:
  int attempt = 0;
  std::int64_t sent_ns = 0;
  bool corrupt_frame = false;  // a complete frame that failed its checksum
  std::optional<Error> garbled;
};

Result<std::int64_t> LinrsClient::send_attempt(Exchange& x) {
  // A late answer to an earlier request may still be on its way: let it pass.
  if (unsettled_ && opt_.settle.count() > 0) LMCFG_TRY(settle_line());
  link_.discard_input();
  decoder_.reset();
  unsettled_ = true;  // until this exchange has its answer
  x.corrupt_frame = false;
  x.garbled.reset();
  const std::int64_t deadline_us =
      x.ordinary ? answer_deadline_us(x.req) : static_cast<std::int64_t>(x.timeout.count()) * 1000;
  if (x.ordinary) {
    stats_.last_deadline_us = static_cast<std::uint64_t>(deadline_us);
    stats_.max_deadline_us =
        std::max(stats_.max_deadline_us, static_cast<std::uint64_t>(deadline_us));
  }
  settle_quiet_us_ = deadline_us;  // a settle after this exchange: see attempt_failed
  x.sent_ns = link_.now_ns();
  last_send_ns_ = x.sent_ns;
  LMCFG_TRY(link_.write(x.wire));
  ++stats_.requests;
  stats_.bytes_tx += x.wire.size();
  if (is_write_request(x.req)) ++stats_.write_requests;
  return deadline_us;
}

std::optional<Telegram> LinrsClient::match_answer(Exchange& x) {
  while (auto item = decoder_.next()) {
    if (!item->ok()) {
      ++stats_.bad_frames;
      noise_seen_ = true;
      x.garbled = std::move(*item).error();
      if (x.garbled->code == Errc::checksum_mismatch) x.corrupt_frame = true;
      continue;
    }
    Telegram t = std::move(*item).value();
    if (opt_.skip_echo && t == x.req) continue;
    if (t.id != opt_.id || t.main != 0x00) continue;  // another drive on the bus, or a request
    // An answer of another sub ID, or naming another UPID / curve / entry,
    // belongs to another request (a late answer): not ours, keep waiting.
    // Error states in the default response form (sub 00h) carry no key and
    // are accepted as the answer to this request.
    const bool default_form_error =
        t.sub == 0x00 && !t.data.empty() && opt_.layout.comm_state && state::is_error(t.data[0]);
    if (t.sub != x.want_sub && !default_form_error) {
      ++stats_.stale_answers;
      x.garbled = Error(Errc::unexpected_response, "answer to " + describe(x.req) + " has sub " +
                                                       hexid("%02Xh", t.sub) + ", expected " +
                                                       hexid("%02Xh", x.want_sub));
      continue;
    }
    // The state byte decides a refusal: LinRS marks the key and value of
    // several answers "No meaning" (§11 transcripts), and a drive may fill
    // them with zeros or anything else when it refuses. A frame that passed
    // its checksum (or reads that agreed) with an error state is the drive's
    // refusal of this request, whatever its key field holds.
    const bool refusal = !t.data.empty() && state::is_error(t.data[0]);
    if (x.want_key && t.sub == x.want_sub && t.data.size() >= 3 && !refusal) {
      const auto key = static_cast<std::uint16_t>(t.data[1] | t.data[2] << 8);
      if (key != *x.want_key) {
        ++stats_.stale_answers;
        x.garbled = Error(Errc::unexpected_response,
                          "answer to " + describe(x.req) + " names key " + hexid("%04Xh", key) +
                              ", expected " + hexid("%04Xh", *x.want_key));
        continue;
      }
    }
    return t;
  }
  return std::nullopt;
}

Result<std::optional<Telegram>> LinrsClient::await_answer(Exchange& x, std::int64_t deadline_us) {
  // Counted in link time (the simulated drive's virtual clock on sim links)
  // from when write() returned (a serial port returns before the bytes are
  // on the wire: the adaptive deadline includes the request's wire time), in
  // whole milliseconds (read_some).
  const std::int64_t end_ns = link_.now_ns() + deadline_us * 1000;
  auto remaining = Millis((end_ns - link_.now_ns() + 999'999) / 1'000'000);
  std::size_t answer_bytes = 0;
  for (;;) {
    // An empty read means the transport waited the whole remaining time.
    if (remaining.count() <= 0) break;
    // A long operation is waited for in slices of a second, with progress.
    const bool sliced = !long_wait_.empty() && opt_.on_long_wait;
    const Millis wait = sliced ? std::min(remaining, Millis(1000)) : remaining;
    auto chunk = link_.read_some(wait);
    if (!chunk.ok()) return std::move(chunk).error();
    if (chunk->empty() && sliced && wait < remaining) {
      remaining -= wait;  // the transport waited the whole slice
      opt_.on_long_wait(long_wait_, x.timeout - remaining);
      continue;
    }
    if (chunk->empty()) break;
    remaining = Millis((end_ns - link_.now_ns() + 999'999) / 1'000'000);
    if (sliced) remaining = std::max(remaining, Millis(0));
    answer_bytes += chunk->size();
    stats_.bytes_rx += chunk->size();
    decoder_.feed(*chunk);
    std::optional<Telegram> answer = match_answer(x);
    if (!answer) {
      // A read whose answer came complete but failed its checksum: nothing
      // better is coming; settle (and retry, or report the garbled answer)
      // rather than wait out the deadline (adaptive timing only; a write
      // waits for a valid answer).
      if (x.corrupt_frame && x.ordinary && opt_.adaptive_deadline) break;
      continue;
    }
    ++stats_.answers;
    unsettled_ = false;
    // Karn's rule: only a first attempt's answer times the link (a retry's
    // answer may be the earlier attempt's).
    if (x.ordinary && x.attempt == 0 && opt_.adaptive_deadline) {
      const double rtt_us = static_cast<double>(link_.now_ns() - x.sent_ns) / 1000.0;
      max_rtt_us_ = std::max(max_rtt_us_, rtt_us);
      rtt_sample(rtt_us - wire_us(x.wire.size() + std::min(answer_bytes, x.wire.size() + 40)));
      backoff_ = 0;
    }
    // Bytes after the answer (noise, a duplicate) must not reach the next exchange.
    decoder_.reset();
    return answer;
  }
  return std::optional<Telegram>();
}

std::optional<Error> LinrsClient::refusal_in(const Exchange& x, const Telegram& answer) {
  // Every group answer starts with the comm state; the default response only when configured
  // so.
  const bool has_state = !answer.data.empty() && (answer.sub != 0x00 || opt_.layout.comm_state);
  if (!has_state || !state::is_error(answer.data[0])) return std::nullopt;
  const std::uint8_t s = answer.data[0];
  Error refusal(make_comm_state_error(s), "drive " + hexid("%02Xh", opt_.id) + " refused " +
                                              describe(x.req) + refused_subject(x.req) + ": " +
                                              state::describe(s));
  // LinRS §16.1 lists C1..C5, C8, C9, LinRS 3V27 p32 adds D7h. Another state is
  // reported with its hex value.
  if (!documented_state(s)) {
    ++stats_.undocumented_states;
    noise_seen_ = true;
    refusal.message = "drive " + hexid("%02Xh", opt_.id) + " answered " + describe(x.req) +
                      refused_subject(x.req) + " with communication state " + hexid("%02Xh", s) +
                      ", which seed 003 §16.1 does not list";
  }
  return refusal;
}

Error LinrsClient::attempt_failed(Exchange& x, std::int64_t deadline_us) {
  if (auto partial = decoder_.flush_idle()) {
    ++stats_.bad_frames;
    noise_seen_ = true;
    x.garbled = std::move(*partial);
  }
  // The settle before the next request: an answer that came garbled needs
  // only the line to go quiet for this exchange's deadline; after no answer
  // at all, a late one may still come: also twice the longest round trip
  // seen (adaptive_settle; settle_line caps it at `settle`).
  if (!x.garbled)
    settle_quiet_us_ = std::max(deadline_us, static_cast<std::int64_t>(2.0 * max_rtt_us_));
  // A complete frame that failed its checksum was this request's answer (the
  // drive sends one answer per request, §4): the line needs to stay quiet only
  // for the adapter's delivery latency and the margin, not a whole deadline.
  else if (x.corrupt_frame && x.ordinary && opt_.adaptive_deadline)
    settle_quiet_us_ = std::min(settle_quiet_us_, corrupt_answer_quiet_us());
  if (x.garbled) {
    noise_seen_ = true;
    return Error(x.garbled->code, "no valid answer from drive " + hexid("%02Xh", opt_.id) + " to " +
                                      describe(x.req) + ": " + x.garbled->message);
  }
  ++stats_.timeouts;
  if (x.ordinary && opt_.adaptive_deadline && srtt_us_ >= 0 && backoff_ < 16) ++backoff_;
  char waited[32];
  std::snprintf(waited, sizeof waited, "%.1f ms", static_cast<double>(deadline_us) / 1000.0);
  return Error(Errc::timeout, "no answer from drive " + hexid("%02Xh", opt_.id) + " within " +
                                  (x.ordinary && opt_.adaptive_deadline
                                       ? std::string(waited) + " (adaptive; --timeout-ms " +
                                             std::to_string(opt_.timeout.count()) + " caps it)"
                                       : std::to_string(x.timeout.count()) + " ms") +
                                  " to " + describe(x.req));
}

Result<Telegram> LinrsClient::transact(const Telegram& req_in, Millis timeout, bool idempotent) {
  Exchange x;
  x.req = req_in;
  x.req.id = opt_.id;
  decoder_.set_checksum(opt_.checksum);
  LMCFG_ASSIGN_OR_RETURN(x.wire, encode(x.req, opt_.checksum));
  x.want_sub = expected_answer_sub(x.req);
  x.want_key = request_key(x.req);
  x.timeout = timeout;
  const int attempts = idempotent ? 1 + opt_.read_retries : 1;
  // An ordinary read (not a write, not a long operation) may wait the adaptive
  // deadline. A write always waits `timeout`: an answer that came after a
  // shorter deadline would count as lost, and a write is never resent blindly.
  x.ordinary = long_wait_.empty() && timeout == opt_.timeout && !is_write_request(x.req);
  Error last(Errc::timeout, "");
  std::optional<std::uint8_t> undocumented;  // an undocumented state seen on an earlier attempt
  for (int attempt = 0; attempt < attempts; ++attempt) {
    if (attempt > 0) ++stats_.retries;
    if (opt_.cancel && opt_.cancel->load())
      return Error(Errc::interrupted, "interrupted by a signal before the next telegram");
    x.attempt = attempt;
    LMCFG_ASSIGN_OR_RETURN(const std::int64_t deadline_us, send_attempt(x));
    LMCFG_ASSIGN_OR_RETURN(auto answer, await_answer(x, deadline_us));
    if (!answer) {
      last = attempt_failed(x, deadline_us);
      continue;
    }
    auto refusal = refusal_in(x, *answer);
    if (!refusal) return std::move(*answer);
    // C1/C2: the drive received our request garbled; a read may be repeated.
    // An undocumented state is taken once for a garbled answer (retried like
    // one): the same state twice in a row is the drive's answer.
    const auto s = static_cast<std::uint8_t>(refusal->code.value());
    const bool garbled_request = s == 0xC1 || s == 0xC2;
    const bool first_undocumented = !documented_state(s) && undocumented != s;
    if (idempotent && attempt + 1 < attempts && (garbled_request || first_undocumented)) {
      if (!documented_state(s)) undocumented = s;
      last = std::move(*refusal);
      continue;
    }
    return std::move(*refusal);
  }
  if (attempts > 1) last.message += " (after " + std::to_string(attempts) + " attempts)";
  return last;
}

Result<DefaultResponse> LinrsClient::decode_default(const Telegram& t, bool value_expected) {
  auto r = decode_default_response(t, opt_.layout);
  if (r.ok() || !opt_.adapt_layout || t.main != 0x00 || t.sub != 0x00) return r;
  std::size_t n = t.data.size();
  if (value_expected && !opt_.layout.mc_response) {
    if (n < 4) return r;
    n -= 4;
  }
  auto layout = layout_for_length(n, opt_.layout);
  if (!layout) return r;
  opt_.layout = *layout;
  return decode_default_response(t, opt_.layout);
}

Result<DefaultResponse> LinrsClient::default_response(ResponseRequest kind) {
  LMCFG_ASSIGN_OR_RETURN(auto t,
                         transact(make_response_request(opt_.id, kind), opt_.timeout, true));
  return decode_default(t, kind != ResponseRequest::default_response);
}

Result<DefaultResponse> LinrsClient::write_control_word(std::uint16_t cw) {
  LMCFG_ASSIGN_OR_RETURN(auto t,
                         transact(make_write_control_word(opt_.id, cw), opt_.timeout, false));
  return decode_default(t, false);
}

Result<std::uint32_t> LinrsClient::read_ram(std::uint16_t upid) {
  return agreed<std::uint32_t>([&]() -> Result<std::uint32_t> {
    LMCFG_ASSIGN_OR_RETURN(
        auto t, transact(make_param_read(opt_.id, ParamOp::read_ram, upid), opt_.timeout, true));
    LMCFG_ASSIGN_OR_RETURN(auto r, decode_default(t, true));
    if (!r.value)
      return Error(Errc::unexpected_response,
                   "RAM read of UPID " + hexid("%04Xh", upid) + " answered without a value");
    return *r.value;
  });
}

Result<void> LinrsClient::write_ram(std::uint16_t upid, std::uint32_t value) {
  LMCFG_TRY(
      transact(make_param_write(opt_.id, ParamOp::write_ram, upid, value), opt_.timeout, false));
  return {};
}

Result<void> LinrsClient::write_ram_rom(std::uint16_t upid, std::uint32_t value) {
  LMCFG_TRY(transact(make_param_write(opt_.id, ParamOp::write_ram_rom, upid, value), opt_.timeout,
                     false));
  return {};
}

Result<IdValueResponse> LinrsClient::id_value(const Telegram& req, std::uint8_t expected_sub,
                                              bool idempotent, Millis timeout) {
  LMCFG_ASSIGN_OR_RETURN(auto t, transact(req, timeout, idempotent));
  return decode_id_value(t, expected_sub);
}

Result<IdValueResponse> LinrsClient::cfg(CfgOp op, std::uint16_t upid, bool idempotent,
                                         Millis timeout) {
  const auto sub = static_cast<std::uint8_t>(op);
  LMCFG_ASSIGN_OR_RETURN(
      auto r, id_value(make_cfg(opt_.id, op, upid), static_cast<std::uint8_t>(0x50 + sub),
                       idempotent, timeout));
  return r;
}

namespace {
Result<std::uint32_t> checked_value(const Result<IdValueResponse>& r, std::uint16_t upid,
                                    const char* what) {
  if (!r.ok()) return r.error();
  if (r->key != upid) {
    return Error(Errc::unexpected_response, std::string(what) + " of UPID " + hexid("%04Xh", upid) +
                                                " answered for UPID " + hexid("%04Xh", r->key));
  }
  return r->value;
}
}  // namespace

Result<std::uint32_t> LinrsClient::read_rom(std::uint16_t upid) {
  return agreed<std::uint32_t>([&] {
    return checked_value(cfg(CfgOp::read_rom, upid, true, opt_.timeout), upid, "ROM read");
  });
}
Result<void> LinrsClient::write_rom(std::uint16_t upid, std::uint32_t value) {
  auto r = id_value(make_cfg_write(opt_.id, upid, value), 0x51, false, opt_.timeout);
  LMCFG_TRY(checked_value(r, upid, "ROM write"));
  return {};
}

Result<void> LinrsClient::write_rom_confirmed(std::uint16_t upid, std::uint32_t value) {
  auto r = write_rom(upid, value);
  if (r.ok()) return {};
  Error e = std::move(r).error();
  if (!is_link_error(e)) return e;
  // The answer was lost or garbled: the write may or may not have landed.
  // Never send it again blindly; read the ROM value back and decide.
  auto back = read_rom(upid);
  if (back.ok() && *back == value) {
    ++stats_.writes_confirmed;
    return {};
  }
  if (back.ok()) {
    e.message += "; read back: ROM of " + hexid("%04Xh", upid) + " holds " + std::to_string(*back) +
                 ", not the value written";
  } else {
    e.message += "; reading the value back failed too: " + back.error().message;
  }
  return e;
}
Result<std::uint16_t> LinrsClient::get_type(std::uint16_t upid) {
  LMCFG_ASSIGN_OR_RETURN(auto v, agreed<std::uint32_t>([&] {
                           return checked_value(cfg(CfgOp::get_type, upid, true, opt_.timeout),
                                                upid, "type query");
                         }));
  return static_cast<std::uint16_t>(v & 0xFFFF);
}
Result<std::optional<std::uint16_t>> LinrsClient::read_address_usage(std::uint16_t upid) {
  auto v = agreed<std::uint32_t>([&] {
    return checked_value(cfg(CfgOp::address_usage, upid, true, opt_.timeout), upid,
                         "address usage query");
  });
  if (v.ok()) return std::optional<std::uint16_t>(static_cast<std::uint16_t>(*v & 0xFFFF));
  const auto& code = v.error().code;
  if (code == make_comm_state_error(0xC3) || code == make_comm_state_error(0xC4))
    return std::optional<std::uint16_t>();  // not known to this drive (seed 003 §10 lacks it)
  return std::move(v).error();
}
Result<std::uint32_t> LinrsClient::get_min(std::uint16_t upid) {
  return agreed<std::uint32_t>([&] {
    return checked_value(cfg(CfgOp::get_min, upid, true, opt_.timeout), upid, "min query");
  });
}
Result<std::uint32_t> LinrsClient::get_max(std::uint16_t upid) {
  return agreed<std::uint32_t>([&] {
    return checked_value(cfg(CfgOp::get_max, upid, true, opt_.timeout), upid, "max query");
  });
}
Result<std::uint32_t> LinrsClient::get_default(std::uint16_t upid) {
  return agreed<std::uint32_t>([&] {
    return checked_value(cfg(CfgOp::get_default, upid, true, opt_.timeout), upid, "default query");
  });
}

Result<void> LinrsClient::default_layer(int layer) {
  if (layer < 1 || layer > 4)
    return Error(Errc::invalid_argument, "layer " + std::to_string(layer) + " is not 1..4");
  LMCFG_ASSIGN_OR_RETURN(
      auto t, transact_long(make_cfg_default_layer(opt_.id, layer), opt_.defaulting_timeout,
                            "defaulting layer " + std::string(lmcfg::layers::name(layer))));
  LMCFG_TRY(decode_id_value(t, static_cast<std::uint8_t>(0x5B + layer)));
  return {};
}

Result<Telegram> LinrsClient::transact_long(const Telegram& req, Millis timeout,
                                            const std::string& what) {
  long_wait_ = what;
  auto r = transact(req, timeout, false);
  long_wait_.clear();
  if (!r.ok() && r.error().code == Errc::timeout) {
    Error e = std::move(r).error();
    e.message += " (" + what + "; the manual gives no upper bound for it)";
    return e;
  }
  return r;
}

Result<Millis> LinrsClient::find_again(const std::string& what) {
  const std::string waiting =
      "waiting for drive " + hexid("%02Xh", opt_.id) + " to answer again after " + what;
  const std::int64_t start_ns = link_.now_ns();
  const std::int64_t budget_ns =
      static_cast<std::int64_t>(opt_.recover_timeout.count()) * 1'000'000;
  std::int64_t reported_s = 0;
  for (;;) {
    auto r = transact(make_response_request(opt_.id, ResponseRequest::default_response),
                      opt_.timeout, false);
    const Millis waited((link_.now_ns() - start_ns) / 1'000'000);
    // Any valid answer shows the drive is back, a refusal too (it has a state).
    if (r.ok() || r.error().code == ErrorClass::drive_refusal) return waited;
    if (!is_link_error(r.error())) return std::move(r).error();  // closed, interrupted
    if (link_.now_ns() - start_ns >= budget_ns) {
      return Error(Errc::timeout,
                   "drive " + hexid("%02Xh", opt_.id) + " did not answer again within " +
                       std::to_string(opt_.recover_timeout.count() / 1000) + " s after " + what +
                       " (polled with §6 default response requests)");
    }
    if (opt_.on_long_wait && waited.count() / 1000 > reported_s) {
      reported_s = waited.count() / 1000;
      opt_.on_long_wait(waiting, waited);
    }
  }
}

// ---- program handling (§13) ----

Result<void> LinrsClient::stop_mc() {
  LMCFG_TRY(transact(make_program(opt_.id, ProgramOp::stop_mc), opt_.timeout, false));
  return {};
}
Result<void> LinrsClient::start_mc() {
  LMCFG_ASSIGN_OR_RETURN(auto t,
                         transact_long(make_program(opt_.id, ProgramOp::start_after_completion),
                                       opt_.reset_timeout, "starting MC"));
  LMCFG_TRY(decode_program_response(t));
  return {};
}
Result<void> LinrsClient::reset() { return reset(opt_.reset_timeout); }
Result<void> LinrsClient::reset(Millis timeout) {
  LMCFG_ASSIGN_OR_RETURN(
      auto t, transact_long(make_program(opt_.id, ProgramOp::reset_after_completion), timeout,
                            "resetting the drive"));
  LMCFG_TRY(decode_program_response(t));
  return {};
}

// ---- error info (§14) ----

Result<std::string> LinrsClient::actual_error_text() {
  LMCFG_ASSIGN_OR_RETURN(auto t, transact(make_error_actual_text(opt_.id), opt_.timeout, true));
  LMCFG_ASSIGN_OR_RETURN(auto r, decode_error_text(t));
  return r.text;
}
Result<std::string> LinrsClient::error_text(std::uint16_t code) {
  LMCFG_ASSIGN_OR_RETURN(auto t, transact(make_error_text(opt_.id, code), opt_.timeout, true));
  LMCFG_ASSIGN_OR_RETURN(auto r, decode_error_text(t));
  return r.text;
}
Result<ErrorCounters> LinrsClient::error_counters() {
  LMCFG_ASSIGN_OR_RETURN(auto t, transact(make_error_counters(opt_.id), opt_.timeout, true));
  return decode_error_counters(t);
}
Result<ErrorLogEntry> LinrsClient::error_log_entry(std::uint16_t index) {
  LMCFG_ASSIGN_OR_RETURN(auto t,
                         transact(make_error_log_entry(opt_.id, index), opt_.timeout, true));
  return decode_error_log_entry(t);
}

}  // namespace lmcfg::client
