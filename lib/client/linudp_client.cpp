// LinUDP V2 drive client (linudp_client.hpp). Sources by the short names of
// docs/references.md (LinUDP V2, LinUDP DLL, C1250 notes, field reports).
#include "client/linudp_client.hpp"

#include <algorithm>
#include <set>

#include "common/layers.hpp"

namespace lmcfg::client {

using linudp::Cmd;
using linudp::RtcBlock;
namespace udp_status = linudp::status;

namespace {

RtcBlock rtc_of(Cmd id, std::uint16_t w2 = 0, std::uint32_t value = 0) {
  RtcBlock r;
  r.id = static_cast<std::uint8_t>(id);
  r.w2 = w2;
  r.set_value(value);
  return r;
}

std::string upid_subject(std::uint16_t upid) { return "UPID " + hex(upid, 4, "h"); }

std::int64_t ms_to_ns(Millis m) { return static_cast<std::int64_t>(m.count()) * 1'000'000; }

// Poll interval while the drive reports 02h/05h (C1250 notes: the TX tick is
// 5 ms; 50 ms keeps a long operation's polls at 20 a second).
constexpr Millis kBusyPoll{50};
// A long operation (30h-36h) is resent, same count, this often (LinUDP V2 §7:
// a resend is not executed again).
constexpr Millis kLongResend{1000};
// Field reports, C1250 notes: flash saves of 39-75 s, silences of 30-90 s after
// saves. This long after a save was sent, no save it started still runs.
constexpr Millis kSaveOver{90000};
// How long the answer to a save's resend is waited for before the drive is
// looked for again (C1250 notes: their client polls every 5 s).
constexpr Millis kSaveResendWait{5000};

}  // namespace

std::string held_by_other_master_message(const std::string& where) {
  return "the LinUDP drive at " + where +
         " answers with all-zero telegrams: it is held by another master (LinMot-Talk or "
         "another LinUDP client, LinUDP V2 §5); disconnect that master and try again";
}

LinudpClient::LinudpClient(transport::Transport& link, ClientOptions opt)
    : Client(std::move(opt)), link_(link) {}

Capabilities LinudpClient::capabilities() const {
  Capabilities c;
  c.delete_one_curve = false;  // LinUDP V2 p13-p15 curve service: no single-curve delete
  c.parameter_type = false;    // LinUDP V2 p14: no request for the type
  c.protocol = "LinUDP";
  return c;
}

Error LinudpClient::refused(std::uint8_t id, const std::string& subject, std::uint8_t code) const {
  const char* text = linudp::status_text(code);
  return Error(Errc::drive_refused,
               "the LinUDP drive at " + where() + " refused " + linudp::cmd_name(id) +
                   (subject.empty() ? "" : " for " + subject) + ": status " + hex(code, 2, "h") +
                   " " + (text ? text : "(not in the status table)") + " (LinUDP V2 p14)");
}

Result<void> LinudpClient::expect_ok(const Reply& r, std::uint8_t id, const std::string& subject,
                                     bool block) const {
  const std::uint8_t code = r.rtc.id;
  if (code == udp_status::ok || (block && code == udp_status::block_more)) return {};
  return refused(id, subject, code);
}

Result<void> LinudpClient::seed() {
  seeded_ = true;
  // LinUDP V2 §7: the drive runs a command only when the count changes. A NOP
  // (00h) does nothing either way and tells the drive's count (as the C1250
  // notes' client seeds its count).
  LMCFG_ASSIGN_OR_RETURN(auto r, command(rtc_of(Cmd::nop), Kind::ordinary, opt_.timeout));
  (void)r;
  return {};
}

Result<LinudpClient::Reply> LinudpClient::probe(Millis deadline, int attempts) {
  seeded_ = true;  // the probe is the seeding NOP itself
  const int saved = attempts_;
  attempts_ = std::max(1, attempts);
  auto r = command(rtc_of(Cmd::nop), Kind::ordinary, deadline);
  attempts_ = saved;
  return r;
}

Result<LinudpClient::Reply> LinudpClient::command(RtcBlock req, Kind kind, Millis timeout,
                                                  const std::string& subject) {
  if (opt_.cancel && opt_.cancel->load())
    return Error(Errc::interrupted, "interrupted before " + linudp::cmd_name(req.id));
  if (!seeded_) LMCFG_TRY(seed());
  const bool restart = req.id == static_cast<std::uint8_t>(Cmd::restart);
  if (restart && last_echo_ == 0) {
    // The restart goes with count 0 (LinUDP DLL); it must differ from
    // the drive's count to run.
    LMCFG_TRY(command(rtc_of(Cmd::nop), Kind::ordinary, opt_.timeout));
  }
  req.count = restart ? 0 : resend_count_ ? *resend_count_ : counter_.next(last_echo_);
  const Bytes bytes = linudp::encode_request(req);
  ++(resend_count_ ? stats_.retries : stats_.requests);
  if (linudp::is_write_command(req.id)) ++stats_.write_requests;

  const std::int64_t start = link_.now_ns();
  const std::int64_t budget = ms_to_ns(timeout);
  const std::int64_t slice = kind == Kind::ordinary  ? budget
                             : kind == Kind::long_op ? ms_to_ns(kLongResend)
                                                     : budget;
  int sent = 0;
  auto send = [&]() -> Result<void> {
    link_.discard_input();
    stats_.bytes_tx += bytes.size();
    if (sent++ > 0) ++stats_.retries;
    return link_.write(bytes);
  };
  LMCFG_TRY(send());
  std::int64_t slice_start = link_.now_ns();
  std::int64_t busy_since = -1;
  std::int64_t reported_s = 0;
  const std::string what = linudp::cmd_name(req.id) + (subject.empty() ? "" : " for " + subject);
  for (;;) {
    const std::int64_t now = link_.now_ns();
    if (kind != Kind::ordinary && opt_.on_long_wait && (now - start) / 1'000'000'000 > reported_s) {
      reported_s = (now - start) / 1'000'000'000;
      opt_.on_long_wait(what, Millis((now - start) / 1'000'000));
    }
    const bool busy = busy_since >= 0;
    // While the drive reports "running", the budget is that of a long
    // operation (LinUDP V2 p14: 02h/05h keep polling).
    const std::int64_t total = busy ? std::max(budget, ms_to_ns(opt_.reset_timeout)) : budget;
    const std::int64_t total_left =
        kind == Kind::ordinary && !busy ? slice - (now - slice_start) : total - (now - start);
    const std::int64_t slice_left =
        busy ? ms_to_ns(kBusyPoll) - (now - slice_start) : slice - (now - slice_start);
    if (total_left <= 0 || (kind == Kind::ordinary && !busy && slice_left <= 0)) {
      if (kind == Kind::ordinary && !busy && sent < attempts_) {
        ++stats_.timeouts;
        LMCFG_TRY(send());  // same bytes, same count (LinUDP V2 §7)
        slice_start = link_.now_ns();
        continue;
      }
      if (kind == Kind::ordinary && !busy && quiet_expected_ &&
          now - start < ms_to_ns(opt_.recover_timeout)) {
        // C1250 notes: after ROM writes and saves drives were silent for
        // 30-90 s. The same datagram, once a second, up to recover_timeout.
        ++stats_.timeouts;
        if (opt_.on_long_wait)
          opt_.on_long_wait("waiting for the drive to answer " + what + " after " + quiet_after_,
                            Millis((now - start) / 1'000'000));
        (void)link_.read_some(kLongResend);
        LMCFG_TRY(send());
        slice_start = link_.now_ns();
        continue;
      }
      ++stats_.timeouts;
      return no_answer(what, req.count, sent, now - start);
    }
    if (slice_left <= 0) {
      // A long operation resent, or a running command polled: same count.
      if (kind != Kind::once) LMCFG_TRY(send());
      slice_start = link_.now_ns();
      continue;
    }
    std::int64_t wait_ns = std::min(slice_left, total_left);
    if (kind != Kind::ordinary) wait_ns = std::min<std::int64_t>(wait_ns, 1'000'000'000);
    LMCFG_ASSIGN_OR_RETURN(auto got,
                           link_.read_some(Millis(std::max<std::int64_t>(1, wait_ns / 1'000'000))));
    if (got.empty()) continue;
    LMCFG_ASSIGN_OR_RETURN(auto reply, match(got, req.count));
    if (!reply) continue;
    if (linudp::is_busy(reply->rtc.id) && kind != Kind::once) {
      if (busy_since < 0) busy_since = link_.now_ns();
      slice_start = link_.now_ns();
      continue;
    }
    return std::move(*reply);
  }
}

Result<std::optional<LinudpClient::Reply>> LinudpClient::match(const Bytes& got,
                                                               std::uint8_t count) {
  stats_.bytes_rx += got.size();
  auto resp = linudp::decode_response(got);
  if (!resp.ok()) {
    ++stats_.bad_frames;
    return std::optional<Reply>{};
  }
  if (resp->all_zero) return Error(Errc::io_error, held_by_other_master_message(where()));
  if (!resp->rtc) {
    ++stats_.bad_frames;  // no RTC part: not an answer to an RTC request (LinUDP V2 §4.4.2)
    return std::optional<Reply>{};
  }
  last_echo_ = resp->rtc->count;
  if (resp->rtc->count != count) {
    ++stats_.stale_answers;  // C1250 notes: stale echoes are ignored, no resync
    return std::optional<Reply>{};
  }
  ++stats_.answers;
  quiet_expected_ = false;
  return std::optional<Reply>(Reply{*resp->rtc, std::move(*resp)});
}

Error LinudpClient::no_answer(const std::string& what, std::uint8_t count, int sent,
                              std::int64_t waited_ns) const {
  return Error(Errc::timeout,
               "no answer from the LinUDP drive at " + where() + " to " + what + " (count " +
                   std::to_string(count) + ", sent " + std::to_string(sent) + " time" +
                   (sent == 1 ? "" : "s") + ", " + std::to_string(waited_ns / 1'000'000) +
                   " ms in all): check the address and port (linudp://HOST[:PORT], drive "
                   "port 49360), that the drive is powered and on this network, and that "
                   "LinUDP V2 is its interface (LinUDP V2 §3.2, §4.3)");
}

Result<LinudpClient::Reply> LinudpClient::simple(Cmd id, std::uint16_t w2, std::uint32_t value,
                                                 const std::string& subject) {
  return command(rtc_of(id, w2, value), Kind::ordinary, opt_.timeout, subject);
}

Result<codec::DefaultResponse> LinudpClient::default_response(codec::ResponseRequest) {
  // The state words come with every reply (LinUDP V2 §4.4.2); a NOP asks nothing else.
  LMCFG_ASSIGN_OR_RETURN(auto r, simple(Cmd::nop));
  codec::DefaultResponse d;
  d.id = opt_.id;
  d.comm_state = 0;
  d.status_word = r.response.status_word;
  d.state_var = r.response.state_var;
  d.error_code = r.response.error_code;
  d.warn_word = r.response.warn_word;
  if (r.response.monitoring) d.monitoring_1 = (*r.response.monitoring)[0];
  return d;
}

Result<std::uint32_t> LinudpClient::read_value(Cmd id, std::uint16_t upid) {
  LMCFG_ASSIGN_OR_RETURN(auto r, simple(id, upid, 0, upid_subject(upid)));
  LMCFG_TRY(expect_ok(r, static_cast<std::uint8_t>(id), upid_subject(upid)));
  // C1250 notes: some drives echo a stale UPID in w2; the UPID sent
  // is trusted, the value is w3/w4.
  return r.rtc.value();
}

Result<void> LinudpClient::write_value(Cmd id, std::uint16_t upid, std::uint32_t value) {
  LMCFG_ASSIGN_OR_RETURN(auto r, simple(id, upid, value, upid_subject(upid)));
  LMCFG_TRY(expect_ok(r, static_cast<std::uint8_t>(id), upid_subject(upid)));
  if (id != Cmd::write_ram) {
    quiet_expected_ = true;  // C1250 notes: ROM writes may leave the drive silent
    quiet_after_ = "a ROM write";
  }
  return {};
}

Result<std::uint32_t> LinudpClient::read_ram(std::uint16_t upid) {
  return read_value(Cmd::read_ram, upid);
}
Result<void> LinudpClient::write_ram(std::uint16_t upid, std::uint32_t value) {
  return write_value(Cmd::write_ram, upid, value);
}
Result<void> LinudpClient::write_ram_rom(std::uint16_t upid, std::uint32_t value) {
  return write_value(Cmd::write_ram_rom, upid, value);
}
Result<std::uint32_t> LinudpClient::read_rom(std::uint16_t upid) {
  return read_value(Cmd::read_rom, upid);
}
Result<void> LinudpClient::write_rom(std::uint16_t upid, std::uint32_t value) {
  return write_value(Cmd::write_rom, upid, value);
}
Result<void> LinudpClient::write_rom_confirmed(std::uint16_t upid, std::uint32_t value) {
  // The resends keep the count, so a lost answer is recovered by resending;
  // if every attempt went unanswered the ROM value is read back (never a new
  // write), as LinrsClient does.
  auto w = write_rom(upid, value);
  if (w.ok() || w.error().code != make_error_code(Errc::timeout)) return w;
  auto back = read_rom(upid);
  if (back.ok() && *back == value) {
    ++stats_.writes_confirmed;
    return {};
  }
  return w;
}
Result<std::uint16_t> LinudpClient::get_type(std::uint16_t upid) {
  return Error(Errc::drive_refused,
               "LinUDP has no request for the type of " + upid_subject(upid) + " (LinUDP V2 p14)");
}
Result<std::uint32_t> LinudpClient::get_min(std::uint16_t upid) {
  return read_value(Cmd::get_min, upid);
}
Result<std::uint32_t> LinudpClient::get_max(std::uint16_t upid) {
  return read_value(Cmd::get_max, upid);
}
Result<std::uint32_t> LinudpClient::get_default(std::uint16_t upid) {
  return read_value(Cmd::get_default, upid);
}
Result<std::optional<std::uint16_t>> LinudpClient::read_address_usage(std::uint16_t) {
  return std::optional<std::uint16_t>{};  // LinUDP V2 p16: only through the UPID list (21h w3)
}

template <class F>
Result<std::vector<std::uint16_t>> LinudpClient::walk_list(Cmd start, Cmd next, int layer,
                                                           F&& on_item) {
  // Open in LinUDP V2 (p16): a list may stop with C6h at the end of the starting
  // layer (as in LinRS §10.2) or run on into the next layers (as the LinUDP DLL
  // assumes). One pass per layer from its base
  // UPID, stopping at C6h or at the first UPID past the layer, serves both.
  const std::uint16_t lo = linudp::layer_start(layer);
  const std::string lname = "the " + std::string(layers::name(layer)) + " layer";
  LMCFG_ASSIGN_OR_RETURN(auto s, simple(start, lo, 0, lname));
  LMCFG_TRY(expect_ok(s, static_cast<std::uint8_t>(start), lname));
  std::vector<std::uint16_t> seen;
  std::set<std::uint16_t> have;
  for (std::size_t i = 0; i <= 0x10000; ++i) {
    LMCFG_ASSIGN_OR_RETURN(auto r, simple(next, 0, 0, lname));
    if (r.rtc.id == udp_status::end_of_list) break;  // payload of C6h ignored (LinRS §10.2-10.3)
    LMCFG_TRY(expect_ok(r, static_cast<std::uint8_t>(next), lname));
    const std::uint16_t upid = r.rtc.w2;
    if (layers::of_upid(upid) != layer) {
      if (upid > lo) break;  // ran on past the layer
      continue;
    }
    if (!have.insert(upid).second) continue;  // listed twice: once
    seen.push_back(upid);
    on_item(r.rtc);
  }
  return seen;
}

Result<std::vector<ModifiedParam>> LinudpClient::modified_list(int layer) {
  std::vector<ModifiedParam> out;
  LMCFG_TRY(walk_list(Cmd::modified_start, Cmd::modified_next, layer, [&](const RtcBlock& r) {
    out.push_back(ModifiedParam{r.w2, r.value()});  // LinUDP V2 p16: w3/w4 = the data value
  }));
  return out;
}

Result<std::vector<UpidInfo>> LinudpClient::upid_list(
    int layer, const std::function<void(std::size_t)>& progress) {
  std::vector<UpidInfo> out;
  LMCFG_TRY(walk_list(Cmd::upid_list_start, Cmd::upid_list_next, layer, [&](const RtcBlock& r) {
    // LinUDP V2 p16: w3 = address usage; w4 left open there: no type.
    out.push_back(UpidInfo{r.w2, r.w3, 0});
    if (progress) progress(out.size());
  }));
  return out;
}

Result<void> LinudpClient::long_command(Cmd id, Kind kind, Millis timeout,
                                        const std::string& what) {
  auto start = link_.now_ns();
  auto sent = command(rtc_of(id), kind, timeout, what);
  const bool save = id == Cmd::curves_save || id == Cmd::ct_save;
  if (!sent.ok() && save && sent.error().code == make_error_code(Errc::timeout)) {
    sent = resend_save(id, what, start, std::move(sent).error());
    start = link_.now_ns();  // a save the resend started: its own budget
  }
  LMCFG_ASSIGN_OR_RETURN(auto r, std::move(sent));
  quiet_expected_ = true;  // C1250 notes: and after saves, defaulting, restarts
  quiet_after_ = what;
  if (kind == Kind::once && linudp::is_busy(r.rtc.id)) {
    // A save reported running: it is never resent (C1250 notes); its end is
    // polled with NOPs of new counts, as the LinUDP DLL does for 40h.
    for (;;) {
      const auto waited = Millis((link_.now_ns() - start) / 1'000'000);
      if (waited >= timeout) {
        return Error(Errc::timeout, "the LinUDP drive at " + where() + " still reports " +
                                        linudp::cmd_name(r.rtc.id) + " running after " +
                                        std::to_string(waited.count() / 1000) + " s");
      }
      (void)link_.read_some(kLongResend);  // the pause between polls
      LMCFG_ASSIGN_OR_RETURN(auto n, command(rtc_of(Cmd::nop), Kind::once, kLongResend, what));
      if (!linudp::is_busy(n.rtc.id)) return expect_ok(n, static_cast<std::uint8_t>(id), what);
    }
  }
  return expect_ok(r, static_cast<std::uint8_t>(id), what);
}

Result<LinudpClient::Reply> LinudpClient::resend_save(Cmd id, const std::string& what,
                                                      std::int64_t start, Error silence) {
  const auto count = counter_.last();
  if (!count) return silence;
  // C1250 notes: resending 80h while a save is running restarts the save.
  // So not before kSaveOver (field reports, C1250 notes); a late acknowledgement that
  // comes meanwhile is taken.
  for (;;) {
    const std::int64_t left = ms_to_ns(kSaveOver) - (link_.now_ns() - start);
    if (left <= 0) break;
    LMCFG_ASSIGN_OR_RETURN(auto got, link_.read_some(Millis((left + 999'999) / 1'000'000)));
    if (got.empty()) continue;
    LMCFG_ASSIGN_OR_RETURN(auto late, match(got, *count));
    if (late) return std::move(*late);
  }
  // LinUDP V2 §7: a command runs only when the count changes, so the same
  // telegram again: a drive that carried the save out answers (or stays
  // silent, field reports) without saving twice; a drive the request never reached
  // takes the count as new and saves now.
  resend_count_ = count;
  auto r = command(rtc_of(id), Kind::once, kSaveResendWait, what + " (sent again, same count)");
  resend_count_.reset();
  if (!r.ok() && r.error().code == make_error_code(Errc::timeout)) return silence;
  return r;
}

Result<void> LinudpClient::default_layer(int layer) {
  if (layer < 1 || layer > 4)
    return Error(Errc::invalid_argument, "layer " + std::to_string(layer) + " is not 1..4");
  const auto id = static_cast<Cmd>(0x30 + layer);  // LinUDP V2 p13: 31h..34h
  return long_command(id, Kind::long_op, opt_.defaulting_timeout,
                      "defaulting layer " + std::string(layers::name(layer)));
}

Result<Millis> LinudpClient::find_again(const std::string& what) {
  const auto start = link_.now_ns();
  // C1250 notes: silent for 30-90 s after saves and ROM writes. A NOP, resent
  // with its count every second, until the drive answers.
  auto r = command(rtc_of(Cmd::nop), Kind::long_op, opt_.recover_timeout,
                   "waiting for the drive to answer again after " + what);
  if (!r.ok()) {
    if (r.error().code != make_error_code(Errc::timeout)) return std::move(r).error();
    return Error(Errc::timeout, "the LinUDP drive at " + where() + " stayed silent for " +
                                    std::to_string(opt_.recover_timeout.count() / 1000) +
                                    " s after " + what);
  }
  return Millis((link_.now_ns() - start) / 1'000'000);
}

Result<Bytes> LinudpClient::read_chunks(RtcBlock, Cmd chunk, std::uint16_t key, std::size_t size,
                                        const std::string& subject) {
  const std::size_t n = (size + 3) / 4;
  const auto cid = static_cast<std::uint8_t>(chunk);
  Bytes out;
  out.reserve(n * 4);
  std::uint8_t last = udp_status::block_more;
  for (std::size_t i = 0; i < n; ++i) {
    LMCFG_ASSIGN_OR_RETURN(auto r, simple(chunk, key, 0, subject));
    LMCFG_TRY(expect_ok(r, cid, subject, true));
    if (r.rtc.id == udp_status::ok && i + 1 < n) {
      return Error(Errc::unexpected_response,
                   "the LinUDP drive at " + where() + " ended " + linudp::cmd_name(cid) + " for " +
                       subject + " after " + std::to_string(i + 1) + " of " + std::to_string(n) +
                       " chunks (" + std::to_string(size) + " bytes expected)");
    }
    put_u32le(out, r.rtc.value());
    last = r.rtc.id;
  }
  if (last == udp_status::block_more) {
    // Open in LinUDP V2: 00h on one more read (the LinUDP DLL's reading).
    LMCFG_ASSIGN_OR_RETURN(auto r, simple(chunk, key, 0, subject));
    LMCFG_TRY(expect_ok(r, cid, subject));
  }
  out.resize(size);
  return out;
}

Result<void> LinudpClient::write_chunks(Cmd chunk, std::uint16_t key, ByteView bytes,
                                        const std::string& subject) {
  const std::size_t n = (bytes.size() + 3) / 4;
  const auto cid = static_cast<std::uint8_t>(chunk);
  for (std::size_t i = 0; i < n; ++i) {
    std::uint8_t b[4] = {0, 0, 0, 0};
    for (std::size_t k = 0; k < 4 && 4 * i + k < bytes.size(); ++k) b[k] = bytes[4 * i + k];
    LMCFG_ASSIGN_OR_RETURN(auto r, simple(chunk, key, get_u32le(ByteView(b, 4), 0), subject));
    LMCFG_TRY(expect_ok(r, cid, subject, true));
    const bool done = r.rtc.id == udp_status::ok;
    if (done != (i + 1 == n)) {
      return Error(Errc::unexpected_response,
                   "the LinUDP drive at " + where() + " answered " + linudp::cmd_name(cid) +
                       " chunk " + std::to_string(i + 1) + " of " + std::to_string(n) + " for " +
                       subject + " with " + hex(r.rtc.id, 2, "h") +
                       (done ? " (block complete too early)" : " (block still not complete)"));
    }
  }
  return {};
}

Result<std::optional<CurveSizes>> LinudpClient::curve_sizes(std::uint16_t curve) {
  const std::string subject = "curve " + std::to_string(curve);
  LMCFG_ASSIGN_OR_RETURN(auto r, simple(Cmd::curve_get_start, curve, 0, subject));
  if (r.rtc.id == udp_status::curve_presence)
    return std::optional<CurveSizes>{};  // LinUDP V2 p13-p15: D4h, absent
  LMCFG_TRY(expect_ok(r, static_cast<std::uint8_t>(Cmd::curve_get_start), subject));
  if (r.rtc.w3 != 0 && r.rtc.w4 != 0)
    return std::optional<CurveSizes>(CurveSizes{r.rtc.w3, r.rtc.w4});
  // Open in LinUDP V2: the 60h reply may lack the sizes. The info block says
  // them (LinRS §11.1: UINT16 size at 0, setpoint count at 4).
  LMCFG_ASSIGN_OR_RETURN(auto info, read_chunks(r.rtc, Cmd::curve_get_info, curve, 70, subject));
  CurveSizes s;
  s.info = get_u16le(info, 0);
  if (s.info == 0 || s.info > 70) s.info = 70;
  s.data = static_cast<std::uint16_t>(4 * get_u16le(info, 4));
  return std::optional<CurveSizes>(s);
}

Result<Bytes> LinudpClient::read_curve_info(std::uint16_t curve, std::uint16_t size) {
  const std::string subject = "curve " + std::to_string(curve);
  LMCFG_ASSIGN_OR_RETURN(auto r, simple(Cmd::curve_get_start, curve, 0, subject));
  LMCFG_TRY(expect_ok(r, static_cast<std::uint8_t>(Cmd::curve_get_start), subject));
  return read_chunks(r.rtc, Cmd::curve_get_info, curve, size, subject);
}

Result<Bytes> LinudpClient::read_curve_data(std::uint16_t curve, std::uint16_t size) {
  const std::string subject = "curve " + std::to_string(curve);
  LMCFG_ASSIGN_OR_RETURN(auto r, simple(Cmd::curve_get_start, curve, 0, subject));
  LMCFG_TRY(expect_ok(r, static_cast<std::uint8_t>(Cmd::curve_get_start), subject));
  return read_chunks(r.rtc, Cmd::curve_get_data, curve, size, subject);
}

Result<std::optional<Client::CurveBlocks>> LinudpClient::read_curve(std::uint16_t curve) {
  LMCFG_ASSIGN_OR_RETURN(auto sizes, curve_sizes(curve));
  if (!sizes) return std::optional<CurveBlocks>{};
  CurveBlocks b;
  LMCFG_ASSIGN_OR_RETURN(b.info, read_curve_info(curve, sizes->info));
  LMCFG_ASSIGN_OR_RETURN(b.data, read_curve_data(curve, sizes->data));
  return std::optional<CurveBlocks>(std::move(b));
}

Result<void> LinudpClient::write_curve(std::uint16_t curve, ByteView info, ByteView data) {
  const std::string subject = "curve " + std::to_string(curve);
  // LinUDP V2 p13-p15: 50h w2 = ID, w3 = info size, w4 = data size.
  RtcBlock s = rtc_of(Cmd::curve_add_start, curve);
  s.w3 = static_cast<std::uint16_t>(info.size());
  s.w4 = static_cast<std::uint16_t>(data.size());
  LMCFG_ASSIGN_OR_RETURN(auto r, command(s, Kind::ordinary, opt_.timeout, subject));
  LMCFG_TRY(expect_ok(r, s.id, subject));
  LMCFG_TRY(write_chunks(Cmd::curve_add_info, curve, info, subject));
  return write_chunks(Cmd::curve_add_data, curve, data, subject);
}

Result<void> LinudpClient::delete_curve(std::uint16_t curve) {
  return Error(Errc::not_supported, "LinUDP has no request to delete curve " +
                                        std::to_string(curve) +
                                        " alone (LinUDP V2 p13-p15): delete all curves and "
                                        "write the ones to keep");
}

Result<void> LinudpClient::delete_all_curves() {
  return long_command(Cmd::curves_delete_all, Kind::long_op, opt_.defaulting_timeout,
                      "deleting all curves");
}

Result<void> LinudpClient::save_curves() {
  return long_command(Cmd::curves_save, Kind::once, opt_.flash_timeout,
                      "saving the curves to flash");
}

Result<std::vector<std::uint16_t>> LinudpClient::ct_defined_entries() {
  std::vector<std::uint16_t> out;
  for (unsigned k = 0; k < 8; ++k) {
    const auto id = static_cast<Cmd>(linudp::ct_presence_cmd(k));
    LMCFG_ASSIGN_OR_RETURN(
        auto r,
        simple(id, 0, 0, "entries " + std::to_string(32 * k) + "-" + std::to_string(32 * k + 31)));
    LMCFG_TRY(expect_ok(r, static_cast<std::uint8_t>(id), "the command table"));
    const std::uint32_t v = r.rtc.value();
    for (unsigned b = 0; b < 32; ++b)
      if (!((v >> b) & 1u)) out.push_back(static_cast<std::uint16_t>(32 * k + b));  // 0 = used
  }
  return out;
}

Result<std::optional<Bytes>> LinudpClient::probe_ct_entry(std::uint16_t entry) {
  const std::string subject = "command table entry " + std::to_string(entry);
  LMCFG_ASSIGN_OR_RETURN(auto r, simple(Cmd::ct_get_start, entry, 0, subject));
  if (r.rtc.id != udp_status::ok || r.rtc.w3 == 0) {
    if (!forms_.empty_ct_entry) forms_.empty_ct_entry = r.rtc.id;
    return std::optional<Bytes>{};
  }
  LMCFG_ASSIGN_OR_RETURN(auto b, read_chunks(r.rtc, Cmd::ct_get_data, entry, r.rtc.w3, subject));
  return std::optional<Bytes>(std::move(b));
}

Result<Bytes> LinudpClient::read_ct_entry(std::uint16_t entry) {
  LMCFG_ASSIGN_OR_RETURN(auto b, probe_ct_entry(entry));
  if (!b) {
    return Error(Errc::not_found, "the LinUDP drive at " + where() +
                                      " holds no command table entry " + std::to_string(entry));
  }
  return std::move(*b);
}

Result<void> LinudpClient::write_ct_entry(std::uint16_t entry, ByteView bytes) {
  const std::string subject = "command table entry " + std::to_string(entry);
  // C1250 notes: the block size goes in w3 (w4 gives D1h).
  RtcBlock s = rtc_of(Cmd::ct_write_start, entry);
  s.w3 = static_cast<std::uint16_t>(bytes.size());
  LMCFG_ASSIGN_OR_RETURN(auto r, command(s, Kind::ordinary, opt_.timeout, subject));
  LMCFG_TRY(expect_ok(r, s.id, subject));
  return write_chunks(Cmd::ct_write_data, entry, bytes, subject);
}

Result<void> LinudpClient::delete_ct_entry(std::uint16_t entry) {
  const std::string subject = "command table entry " + std::to_string(entry);
  LMCFG_ASSIGN_OR_RETURN(auto r, simple(Cmd::ct_delete, entry, 0, subject));
  return expect_ok(r, static_cast<std::uint8_t>(Cmd::ct_delete), subject);
}

Result<void> LinudpClient::delete_all_ct() {
  return long_command(Cmd::ct_delete_all, Kind::long_op, opt_.defaulting_timeout,
                      "deleting the command table");
}

Result<void> LinudpClient::save_ct() {
  return long_command(Cmd::ct_save, Kind::once, opt_.flash_timeout,
                      "saving the command table to flash");
}

Result<void> LinudpClient::stop_mc() {
  return long_command(Cmd::stop_mc, Kind::long_op, opt_.reset_timeout, "stopping MC");
}
Result<void> LinudpClient::start_mc() {
  return long_command(Cmd::start_mc, Kind::long_op, opt_.reset_timeout, "starting MC");
}
Result<void> LinudpClient::reset() { return reset(opt_.reset_timeout); }
Result<void> LinudpClient::reset(Millis timeout) {
  // Sent once: after the reboot the drive's count is unknown (open in LinUDP
  // V2), and a resend that met another count would restart it again.
  return long_command(Cmd::restart, Kind::once, timeout, "resetting the drive");
}

Result<std::string> LinudpClient::error_text(std::uint16_t code) {
  // LinUDP V2 p17 error log: 74h, 8 stringlets of 4 characters.
  std::string text;
  const std::string subject = "error " + hex(code, 4, "h");
  for (std::uint16_t s = 0; s < 8; ++s) {
    RtcBlock q = rtc_of(Cmd::error_text, code);
    q.w3 = s;
    LMCFG_ASSIGN_OR_RETURN(auto r, command(q, Kind::ordinary, opt_.timeout, subject));
    LMCFG_TRY(expect_ok(r, q.id, subject));
    const std::uint32_t v = r.rtc.value();
    for (int k = 0; k < 4; ++k) text.push_back(static_cast<char>((v >> (8 * k)) & 0xFF));
  }
  if (auto z = text.find('\0'); z != std::string::npos) text.resize(z);
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

Result<std::string> LinudpClient::actual_error_text() {
  // LinUDP V2 p17: no "actual error text" request; the code comes in every reply.
  LMCFG_ASSIGN_OR_RETURN(auto r, simple(Cmd::nop));
  return error_text(r.response.error_code.value_or(0));
}

Result<codec::ErrorCounters> LinudpClient::error_counters() {
  LMCFG_ASSIGN_OR_RETURN(auto r, simple(Cmd::errlog_counts, 0, 0, "the error log"));
  LMCFG_TRY(expect_ok(r, static_cast<std::uint8_t>(Cmd::errlog_counts), "the error log"));
  return codec::ErrorCounters{r.rtc.w3, r.rtc.w4};  // LinUDP V2 p17: w3 logged, w4 occurred
}

Result<codec::ErrorLogEntry> LinudpClient::error_log_entry(std::uint16_t index) {
  const std::string subject = "error log entry " + std::to_string(index);
  codec::ErrorLogEntry e;
  LMCFG_ASSIGN_OR_RETURN(auto c, simple(Cmd::errlog_code, index, 0, subject));
  LMCFG_TRY(expect_ok(c, static_cast<std::uint8_t>(Cmd::errlog_code), subject));
  e.code = c.rtc.w3;
  LMCFG_ASSIGN_OR_RETURN(auto lo, simple(Cmd::errlog_time_low, index, 0, subject));
  LMCFG_TRY(expect_ok(lo, static_cast<std::uint8_t>(Cmd::errlog_time_low), subject));
  e.millis = lo.rtc.value();
  LMCFG_ASSIGN_OR_RETURN(auto hi, simple(Cmd::errlog_time_high, index, 0, subject));
  LMCFG_TRY(expect_ok(hi, static_cast<std::uint8_t>(Cmd::errlog_time_high), subject));
  e.hours = hi.rtc.value();
  return e;
}

}  // namespace lmcfg::client
