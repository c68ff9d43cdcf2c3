#include "client/client.hpp"

#include <cstdio>

#include "common/layers.hpp"

namespace lmcfg::client {

using namespace codec;

std::uint16_t layer_base(int layer) { return layers::base_upid(layer); }
std::optional<int> layer_of(std::uint16_t upid) {
  const int l = layers::of_upid(upid);
  return l == 0 ? std::nullopt : std::optional<int>(l);
}
const char* layer_name(int layer) { return layers::name(layer).data(); }

std::uint8_t expected_answer_sub(const Telegram& r) {
  switch (static_cast<Main>(r.main)) {
    case Main::curve:
      return 0x40;
    case Main::param_config:
      return static_cast<std::uint8_t>(0x50 + r.sub);
    case Main::program:
      return (r.sub == 0x01 || r.sub == 0x04) ? 0x60 : 0x00;
    case Main::error_info:
      return static_cast<std::uint8_t>(0x70 + r.sub);
    case Main::command_table:
      return static_cast<std::uint8_t>(0x80 + r.sub);
    default:
      return 0x00;
  }
}

bool is_write_request(const Telegram& r) {
  switch (static_cast<Main>(r.main)) {
    case Main::control_word:
    case Main::motion_command:
      return true;
    case Main::parameter:
      return r.sub == 0x01 || r.sub == 0x03 || r.sub == 0x04 || (r.sub >= 0x11 && r.sub <= 0x14);
    case Main::param_config:
      return r.sub == 0x01 || (r.sub >= 0x0C && r.sub <= 0x0F);
    case Main::curve:
      return r.sub <= 0x06;
    case Main::program:
      return true;
    case Main::command_table:
      return r.sub <= 0x04;
    default:
      return false;
  }
}

namespace {
std::string hexid(const char* fmt, unsigned v) {
  char buf[96];
  std::snprintf(buf, sizeof buf, fmt, v);
  return buf;
}
bool is_link_error(const Error& e) {
  return e.code == Errc::timeout || e.code == Errc::frame_short ||
         e.code == Errc::frame_malformed || e.code == Errc::frame_overlong ||
         e.code == Errc::checksum_mismatch || e.code == Errc::unexpected_response;
}
}  // namespace

Client::Client(transport::Transport& link, ClientOptions opt)
    : link_(link), opt_(opt), decoder_(opt.checksum) {}

std::optional<std::uint16_t> request_key(const Telegram& r) {
  if (r.data.size() < 2) return std::nullopt;
  bool keyed = false;
  switch (static_cast<Main>(r.main)) {
    case Main::param_config:
      keyed = r.sub <= 0x01 || (r.sub >= 0x04 && r.sub <= 0x07);
      break;
    case Main::curve:
      keyed = r.sub == 0x02 || (r.sub >= 0x04 && r.sub <= 0x06) || (r.sub >= 0x08 && r.sub <= 0x0A);
      break;
    case Main::command_table:
      keyed = r.sub >= 0x02 && r.sub <= 0x07;
      break;
    default:
      break;
  }
  if (!keyed) return std::nullopt;
  return static_cast<std::uint16_t>(r.data[0] | r.data[1] << 8);
}

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

}  // namespace

Result<void> Client::settle_line() {
  ++stats_.settles;
  // Bounded: a line that never goes quiet is a link problem, not an answer.
  for (int reads = 0; reads < 256; ++reads) {
    auto chunk = link_.read_some(opt_.settle);
    if (!chunk.ok()) return std::move(chunk).error();
    if (chunk->empty()) {
      unsettled_ = false;
      return {};
    }
    stats_.bytes_rx += chunk->size();
    stats_.settle_bytes += chunk->size();
  }
  return Error(Errc::io_error, "the line to drive " + hexid("%02Xh", opt_.id) +
                                   " does not go quiet (" + std::to_string(opt_.settle.count()) +
                                   " ms without bytes never seen in 256 reads)");
}

Result<Telegram> Client::transact(const Telegram& req_in, Millis timeout, bool idempotent) {
  Telegram req = req_in;
  req.id = opt_.id;
  decoder_.set_checksum(opt_.checksum);
  LMCFG_ASSIGN_OR_RETURN(Bytes wire, encode(req, opt_.checksum));
  const std::uint8_t want_sub = expected_answer_sub(req);
  const std::optional<std::uint16_t> want_key = request_key(req);
  const int attempts = idempotent ? 1 + opt_.read_retries : 1;
  Error last(Errc::timeout, "");
  for (int attempt = 0; attempt < attempts; ++attempt) {
    if (attempt > 0) ++stats_.retries;
    // A late answer to an earlier request may still be on its way: let it pass.
    if (unsettled_ && opt_.settle.count() > 0) LMCFG_TRY(settle_line());
    link_.discard_input();
    decoder_.reset();
    unsettled_ = true;  // until this exchange has its answer
    LMCFG_TRY(link_.write(wire));
    ++stats_.requests;
    stats_.bytes_tx += wire.size();
    if (is_write_request(req)) ++stats_.write_requests;

    auto remaining = timeout;
    std::optional<Error> garbled;
    for (;;) {
      // An empty read means the transport waited the whole remaining time.
      if (remaining.count() <= 0) break;
      const auto t0 = transport::Clock::now();
      auto chunk = link_.read_some(remaining);
      if (!chunk.ok()) return std::move(chunk).error();
      if (chunk->empty()) break;
      remaining -= std::chrono::duration_cast<Millis>(transport::Clock::now() - t0);
      stats_.bytes_rx += chunk->size();
      decoder_.feed(*chunk);
      std::optional<Telegram> answer;
      while (auto item = decoder_.next()) {
        if (!item->ok()) {
          ++stats_.bad_frames;
          garbled = std::move(*item).error();
          continue;
        }
        Telegram t = std::move(*item).value();
        if (opt_.skip_echo && t == req) continue;
        if (t.id != opt_.id || t.main != 0x00) continue;  // another drive on the bus, or a request
        // An answer of another sub ID, or naming another UPID / curve / entry,
        // belongs to another request (a late answer): not ours, keep waiting.
        // Error states in the default response form (sub 00h) carry no key and
        // are accepted as the answer to this request.
        const bool default_form_error = t.sub == 0x00 && !t.data.empty() &&
                                        opt_.layout.comm_state && state::is_error(t.data[0]);
        if (t.sub != want_sub && !default_form_error) {
          ++stats_.stale_answers;
          garbled = Error(Errc::unexpected_response, "answer to " + describe(req) + " has sub " +
                                                         hexid("%02Xh", t.sub) + ", expected " +
                                                         hexid("%02Xh", want_sub));
          continue;
        }
        if (want_key && t.sub == want_sub && t.data.size() >= 3) {
          const auto key = static_cast<std::uint16_t>(t.data[1] | t.data[2] << 8);
          if (key != *want_key) {
            ++stats_.stale_answers;
            garbled = Error(Errc::unexpected_response,
                            "answer to " + describe(req) + " names key " + hexid("%04Xh", key) +
                                ", expected " + hexid("%04Xh", *want_key));
            continue;
          }
        }
        answer = std::move(t);
        break;
      }
      if (!answer) continue;
      ++stats_.answers;
      unsettled_ = false;
      // Bytes after the answer (noise, a duplicate) must not reach the next exchange.
      decoder_.reset();
      // Every group answer starts with the comm state; the default response only when configured
      // so.
      const bool has_state =
          !answer->data.empty() && (answer->sub != 0x00 || opt_.layout.comm_state);
      if (has_state && state::is_error(answer->data[0])) {
        const std::uint8_t s = answer->data[0];
        return Error(make_comm_state_error(s), "drive " + hexid("%02Xh", opt_.id) + " refused " +
                                                   describe(req) + refused_subject(req) + ": " +
                                                   state::describe(s));
      }
      return std::move(*answer);
    }
    if (auto partial = decoder_.flush_idle()) {
      ++stats_.bad_frames;
      garbled = std::move(*partial);
    }
    if (garbled) {
      last = Error(garbled->code, "no valid answer from drive " + hexid("%02Xh", opt_.id) + " to " +
                                      describe(req) + ": " + garbled->message);
    } else {
      ++stats_.timeouts;
      last = Error(Errc::timeout, "no answer from drive " + hexid("%02Xh", opt_.id) + " within " +
                                      std::to_string(timeout.count()) + " ms to " + describe(req));
    }
  }
  if (attempts > 1) last.message += " (after " + std::to_string(attempts) + " attempts)";
  return last;
}

Result<DefaultResponse> Client::decode_default(const Telegram& t, bool value_expected) {
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

Result<DefaultResponse> Client::default_response(ResponseRequest kind) {
  LMCFG_ASSIGN_OR_RETURN(auto t,
                         transact(make_response_request(opt_.id, kind), opt_.timeout, true));
  return decode_default(t, kind != ResponseRequest::default_response);
}

Result<DefaultResponse> Client::write_control_word(std::uint16_t cw) {
  LMCFG_ASSIGN_OR_RETURN(auto t,
                         transact(make_write_control_word(opt_.id, cw), opt_.timeout, false));
  return decode_default(t, false);
}

Result<std::uint32_t> Client::read_ram(std::uint16_t upid) {
  LMCFG_ASSIGN_OR_RETURN(
      auto t, transact(make_param_read(opt_.id, ParamOp::read_ram, upid), opt_.timeout, true));
  LMCFG_ASSIGN_OR_RETURN(auto r, decode_default(t, true));
  if (!r.value)
    return Error(Errc::unexpected_response,
                 "RAM read of UPID " + hexid("%04Xh", upid) + " answered without a value");
  return *r.value;
}

Result<void> Client::write_ram(std::uint16_t upid, std::uint32_t value) {
  LMCFG_TRY(
      transact(make_param_write(opt_.id, ParamOp::write_ram, upid, value), opt_.timeout, false));
  return {};
}

Result<void> Client::write_ram_rom(std::uint16_t upid, std::uint32_t value) {
  LMCFG_TRY(transact(make_param_write(opt_.id, ParamOp::write_ram_rom, upid, value), opt_.timeout,
                     false));
  return {};
}

Result<IdValueResponse> Client::id_value(const Telegram& req, std::uint8_t expected_sub,
                                         bool idempotent, Millis timeout) {
  LMCFG_ASSIGN_OR_RETURN(auto t, transact(req, timeout, idempotent));
  return decode_id_value(t, expected_sub);
}

Result<IdValueResponse> Client::cfg(CfgOp op, std::uint16_t upid, bool idempotent, Millis timeout) {
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

Result<std::uint32_t> Client::read_rom(std::uint16_t upid) {
  return checked_value(cfg(CfgOp::read_rom, upid, true, opt_.timeout), upid, "ROM read");
}
Result<void> Client::write_rom(std::uint16_t upid, std::uint32_t value) {
  auto r = id_value(make_cfg_write(opt_.id, upid, value), 0x51, false, opt_.timeout);
  LMCFG_TRY(checked_value(r, upid, "ROM write"));
  return {};
}

Result<void> Client::write_rom_confirmed(std::uint16_t upid, std::uint32_t value) {
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
Result<std::uint16_t> Client::get_type(std::uint16_t upid) {
  LMCFG_ASSIGN_OR_RETURN(
      auto v, checked_value(cfg(CfgOp::get_type, upid, true, opt_.timeout), upid, "type query"));
  return static_cast<std::uint16_t>(v & 0xFFFF);
}
Result<std::uint32_t> Client::get_min(std::uint16_t upid) {
  return checked_value(cfg(CfgOp::get_min, upid, true, opt_.timeout), upid, "min query");
}
Result<std::uint32_t> Client::get_max(std::uint16_t upid) {
  return checked_value(cfg(CfgOp::get_max, upid, true, opt_.timeout), upid, "max query");
}
Result<std::uint32_t> Client::get_default(std::uint16_t upid) {
  return checked_value(cfg(CfgOp::get_default, upid, true, opt_.timeout), upid, "default query");
}

Result<std::vector<ModifiedParam>> Client::modified_list(int layer) {
  const std::uint16_t base = layer_base(layer);
  // Restarting the list is the only safe retry: "get next" advances the drive's cursor.
  Error last(Errc::timeout, "");
  std::optional<std::vector<ModifiedParam>>
      unconfirmed;  // a list that ended oddly, to compare with a rerun
  for (int attempt = 0; attempt <= opt_.read_retries; ++attempt) {
    if (attempt > 0) ++stats_.retries;
    auto start = cfg(CfgOp::start_modified, base, true, opt_.timeout);
    if (!start.ok()) return std::move(start).error();
    std::vector<ModifiedParam> out;
    std::optional<Error> failed;
    for (std::size_t guard = 0; guard <= 0x0F00; ++guard) {
      // §10.2 sends the layer base with "get next" in one example and 0000 in another (erratum 4).
      auto next = cfg(CfgOp::next_modified, base, false, opt_.timeout);
      if (!next.ok()) {
        failed = std::move(next).error();
        break;
      }
      const bool last_one = next->state == state::last_in_list;
      const bool in_layer = layer_of(next->key) == layer;
      const bool seen = !out.empty() && out.back().upid == next->key;
      if (!last_one || (in_layer && !seen)) {
        if (!in_layer) {
          return Error(Errc::unexpected_response,
                       "modified list of layer " + std::string(layer_name(layer)) +
                           " returned UPID " + hexid("%04Xh", next->key) +
                           " outside the layer's range");
        }
        out.push_back({next->key, next->value});
      }
      if (last_one && !in_layer && (!out.empty() || opt_.confirm_empty_lists)) {
        // C6 with a UPID outside the layer: an empty list's end, or the "no
        // list" answer of a drive that lost its cursor (it reset in between).
        // Accept it only when a rerun of the list ends the same way.
        if (unconfirmed && *unconfirmed == out) return out;
        unconfirmed = out;
        failed = Error(Errc::unexpected_response,
                       "modified list of layer " + std::string(layer_name(layer)) +
                           " ended with C6 for UPID " + hexid("%04Xh", next->key) +
                           " outside the layer (drive lost the list cursor?)");
        break;
      }
      if (last_one) return out;
    }
    if (!failed) {
      return Error(Errc::unexpected_response, "modified list of layer " +
                                                  std::string(layer_name(layer)) +
                                                  " did not end (no C6 after 3840 entries)");
    }
    if (!is_link_error(*failed)) return std::move(*failed);
    last = std::move(*failed);
  }
  return last;
}

Result<std::vector<UpidInfo>> Client::upid_list(int layer,
                                                const std::function<void(std::size_t)>& progress) {
  const std::uint16_t base = layer_base(layer);
  Error last(Errc::timeout, "");
  for (int attempt = 0; attempt <= opt_.read_retries; ++attempt) {
    if (attempt > 0) ++stats_.retries;
    auto start = cfg(CfgOp::start_upid_list, base, true, opt_.timeout);
    if (!start.ok()) return std::move(start).error();
    std::vector<UpidInfo> out;
    std::optional<Error> failed;
    for (std::size_t guard = 0; guard <= 0x0F00; ++guard) {
      auto t = transact(make_cfg(opt_.id, CfgOp::next_upid, base), opt_.timeout, false);
      if (!t.ok()) {
        failed = std::move(t).error();
        break;
      }
      auto e = decode_upid_list_entry(*t);
      if (!e.ok()) return std::move(e).error();
      const bool last_one = e->state == state::last_in_list;
      const bool in_layer = layer_of(e->upid) == layer;
      const bool seen = !out.empty() && out.back().upid == e->upid;
      if ((!last_one || !seen) && in_layer) out.push_back({e->upid, e->address_usage, e->type});
      if (progress) progress(out.size());
      if (last_one) return out;
    }
    if (!failed)
      return Error(Errc::unexpected_response, "UPID list did not end (no C6 after 3840 entries)");
    if (!is_link_error(*failed)) return std::move(*failed);
    last = std::move(*failed);
  }
  return last;
}

Result<void> Client::default_layer(int layer) {
  if (layer < 1 || layer > 4)
    return Error(Errc::invalid_argument, "layer " + std::to_string(layer) + " is not 1..4");
  auto r = id_value(make_cfg_default_layer(opt_.id, layer), static_cast<std::uint8_t>(0x5B + layer),
                    false, opt_.defaulting_timeout);
  if (!r.ok()) return std::move(r).error();
  return {};
}

// ---- curves (§11) ----

Result<std::optional<CurveSizes>> Client::curve_sizes(std::uint16_t curve) {
  LMCFG_ASSIGN_OR_RETURN(
      auto r, id_value(make_curve(opt_.id, CurveOp::read_sizes, curve), 0x40, true, opt_.timeout));
  if (r.key != curve) {
    return Error(Errc::unexpected_response, "curve size query for ID " + std::to_string(curve) +
                                                " answered for ID " + std::to_string(r.key));
  }
  CurveSizes s{static_cast<std::uint16_t>(r.value & 0xFFFF),
               static_cast<std::uint16_t>(r.value >> 16)};
  if (s.info == 0 && s.data == 0) return std::optional<CurveSizes>();
  return std::optional<CurveSizes>(s);
}

Result<Bytes> Client::read_block(const Telegram& setup, std::uint8_t setup_sub,
                                 const Telegram& chunk_req, std::uint8_t chunk_sub,
                                 std::size_t size, const char* what) {
  const std::size_t chunks = (size + 3) / 4;
  Error last(Errc::timeout, "");
  for (int attempt = 0; attempt <= opt_.read_retries; ++attempt) {
    if (attempt > 0) {
      ++stats_.retries;
      // Restart the transfer from its setup telegram (resets the drive's block cursor).
      auto s = id_value(setup, setup_sub, true, opt_.timeout);
      if (!s.ok()) return std::move(s).error();
    }
    Bytes out;
    out.reserve(chunks * 4);
    std::optional<Error> failed;
    for (std::size_t i = 0; i < chunks; ++i) {
      auto r = id_value(chunk_req, chunk_sub, false, opt_.timeout);
      if (!r.ok()) {
        failed = std::move(r).error();
        break;
      }
      const bool last_chunk = i + 1 == chunks;
      const std::uint8_t want = last_chunk ? state::ok : state::more_data;
      if (r->state != want) {
        // The drive's block cursor is not where ours is (it reset, or a chunk
        // answer was lost): restart the block from its setup telegram.
        failed = Error(Errc::unexpected_response,
                       std::string(what) + ": chunk " + std::to_string(i + 1) + " of " +
                           std::to_string(chunks) + " has state " + hexid("%02Xh", r->state) +
                           ", expected " + hexid("%02Xh", want));
        break;
      }
      auto raw = r->raw();
      out.insert(out.end(), raw.begin(), raw.end());
    }
    if (!failed) {
      out.resize(size);  // the last chunk carries padding
      return out;
    }
    if (!is_link_error(*failed)) return std::move(*failed);
    last = std::move(*failed);
  }
  last.message = std::string(what) + ": " + last.message;
  return last;
}

Result<Bytes> Client::read_curve_info(std::uint16_t curve, std::uint16_t size) {
  return read_block(make_curve(opt_.id, CurveOp::read_sizes, curve), 0x40,
                    make_curve(opt_.id, CurveOp::read_info, curve), 0x40, size,
                    ("curve " + std::to_string(curve) + " info block").c_str());
}
Result<Bytes> Client::read_curve_data(std::uint16_t curve, std::uint16_t size) {
  return read_block(make_curve(opt_.id, CurveOp::read_sizes, curve), 0x40,
                    make_curve(opt_.id, CurveOp::read_data, curve), 0x40, size,
                    ("curve " + std::to_string(curve) + " data block").c_str());
}

Result<std::optional<Client::CurveBlocks>> Client::read_curve(std::uint16_t curve) {
  LMCFG_ASSIGN_OR_RETURN(auto sizes, curve_sizes(curve));
  if (!sizes) return std::optional<CurveBlocks>();
  CurveBlocks b;
  LMCFG_ASSIGN_OR_RETURN(b.info, read_curve_info(curve, sizes->info));
  LMCFG_ASSIGN_OR_RETURN(b.data, read_curve_data(curve, sizes->data));
  return std::optional<CurveBlocks>(std::move(b));
}

namespace {
// A block write answers 04h while the drive expects more and 00h after the
// last chunk. Anything else means the drive lost the transfer (a reset, a
// restarted block): the write must fail, never report success.
Result<IdValueResponse> check_chunk_state(const IdValueResponse& r, bool last_chunk) {
  const std::uint8_t want = last_chunk ? state::ok : state::more_data;
  if (r.state == want) return r;
  return Error(Errc::unexpected_response, "the drive answered state " + hexid("%02Xh", r.state) +
                                              ", expected " + hexid("%02Xh", want) +
                                              " (block transfer lost on the drive?)");
}

std::array<std::uint8_t, 4> chunk_at(ByteView b, std::size_t i) {
  std::array<std::uint8_t, 4> c{0, 0, 0, 0};
  for (std::size_t k = 0; k < 4 && i * 4 + k < b.size(); ++k) c[k] = b[i * 4 + k];
  return c;
}
}  // namespace

Result<void> Client::write_curve(std::uint16_t curve, ByteView info, ByteView data) {
  if (info.size() > 0xFFFF || data.size() > 0xFFFF) {
    return Error(Errc::invalid_argument,
                 "curve " + std::to_string(curve) + " blocks exceed 65535 bytes");
  }
  LMCFG_TRY(id_value(make_curve_add(opt_.id, curve, static_cast<std::uint16_t>(info.size()),
                                    static_cast<std::uint16_t>(data.size())),
                     0x40, false, opt_.timeout));
  for (auto [op, block] :
       {std::pair{CurveOp::write_info, info}, std::pair{CurveOp::write_data, data}}) {
    const std::size_t chunks = (block.size() + 3) / 4;
    for (std::size_t i = 0; i < chunks; ++i) {
      auto r = id_value(make_curve_write(opt_.id, op, curve, chunk_at(block, i)), 0x40, false,
                        opt_.timeout);
      if (r.ok()) r = check_chunk_state(*r, i + 1 == chunks);
      if (!r.ok()) {
        Error e = std::move(r).error();
        e.message = "curve " + std::to_string(curve) +
                    (op == CurveOp::write_info ? " info" : " data") + " block, chunk " +
                    std::to_string(i + 1) + " of " + std::to_string(chunks) + ": " + e.message;
        return e;
      }
    }
  }
  return {};
}

Result<void> Client::delete_curve(std::uint16_t curve) {
  LMCFG_TRY(id_value(make_curve(opt_.id, CurveOp::delete_one, curve), 0x40, false, opt_.timeout));
  return {};
}
Result<void> Client::delete_all_curves() {
  LMCFG_TRY(id_value(make_curve(opt_.id, CurveOp::delete_all), 0x40, false, opt_.timeout));
  return {};
}
Result<void> Client::save_curves() {
  LMCFG_TRY(id_value(make_curve(opt_.id, CurveOp::save_to_flash), 0x40, false, opt_.flash_timeout));
  return {};
}

// ---- command table (§12) ----

Result<std::vector<std::uint16_t>> Client::ct_defined_entries() {
  std::vector<std::uint16_t> out;
  for (std::uint16_t block = 0; block < 8; ++block) {
    LMCFG_ASSIGN_OR_RETURN(auto r, id_value(make_ct_defined_list(opt_.id, block, opt_.pad_ct_list),
                                            0x87, true, opt_.timeout));
    if (r.key != block) {
      return Error(Errc::unexpected_response, "CT defined-entry list block " +
                                                  std::to_string(block) + " answered for block " +
                                                  std::to_string(r.key));
    }
    for (unsigned bit = 0; bit < 32; ++bit) {
      if ((r.value & (1u << bit)) == 0)
        out.push_back(static_cast<std::uint16_t>(block * 32 + bit));  // 0 = exists
    }
  }
  return out;
}

Result<Bytes> Client::read_ct_entry(std::uint16_t entry) {
  auto setup = make_ct(opt_.id, CtOp::setup_read, entry);
  LMCFG_ASSIGN_OR_RETURN(auto s, id_value(setup, 0x85, true, opt_.timeout));
  if (s.key != entry) {
    return Error(Errc::unexpected_response, "CT setup read of entry " + std::to_string(entry) +
                                                " answered for entry " + std::to_string(s.key));
  }
  if (s.value == 0 || s.value > 0xFFFF) {
    return Error(Errc::unexpected_response, "CT entry " + std::to_string(entry) + " has size " +
                                                std::to_string(s.value) + " (not defined?)");
  }
  return read_block(setup, 0x85, make_ct(opt_.id, CtOp::read_data, entry), 0x86, s.value,
                    ("command table entry " + std::to_string(entry)).c_str());
}

Result<void> Client::write_ct_entry(std::uint16_t entry, ByteView bytes) {
  LMCFG_TRY(id_value(make_ct_setup_write(opt_.id, entry, static_cast<std::uint32_t>(bytes.size())),
                     0x83, false, opt_.timeout));
  const std::size_t chunks = (bytes.size() + 3) / 4;
  for (std::size_t i = 0; i < chunks; ++i) {
    auto r = id_value(make_ct_write(opt_.id, entry, chunk_at(bytes, i)), 0x84, false, opt_.timeout);
    if (r.ok()) r = check_chunk_state(*r, i + 1 == chunks);
    if (!r.ok()) {
      Error e = std::move(r).error();
      e.message = "command table entry " + std::to_string(entry) + ", chunk " +
                  std::to_string(i + 1) + " of " + std::to_string(chunks) + ": " + e.message;
      return e;
    }
  }
  return {};
}

Result<void> Client::delete_ct_entry(std::uint16_t entry) {
  LMCFG_TRY(id_value(make_ct(opt_.id, CtOp::delete_one, entry), 0x82, false, opt_.timeout));
  return {};
}
Result<void> Client::delete_all_ct() {
  LMCFG_TRY(id_value(make_ct(opt_.id, CtOp::delete_all), 0x81, false, opt_.timeout));
  return {};
}
Result<void> Client::save_ct() {
  LMCFG_TRY(id_value(make_ct(opt_.id, CtOp::save_to_flash), 0x80, false, opt_.flash_timeout));
  return {};
}

// ---- program handling (§13) ----

Result<void> Client::stop_mc() {
  LMCFG_TRY(transact(make_program(opt_.id, ProgramOp::stop_mc), opt_.timeout, false));
  return {};
}
Result<void> Client::start_mc() {
  LMCFG_ASSIGN_OR_RETURN(auto t, transact(make_program(opt_.id, ProgramOp::start_after_completion),
                                          opt_.reset_timeout, false));
  LMCFG_TRY(decode_program_response(t));
  return {};
}
Result<void> Client::reset() {
  LMCFG_ASSIGN_OR_RETURN(auto t, transact(make_program(opt_.id, ProgramOp::reset_after_completion),
                                          opt_.reset_timeout, false));
  LMCFG_TRY(decode_program_response(t));
  return {};
}

// ---- error info (§14) ----

Result<std::string> Client::actual_error_text() {
  LMCFG_ASSIGN_OR_RETURN(auto t, transact(make_error_actual_text(opt_.id), opt_.timeout, true));
  LMCFG_ASSIGN_OR_RETURN(auto r, decode_error_text(t));
  return r.text;
}
Result<std::string> Client::error_text(std::uint16_t code) {
  LMCFG_ASSIGN_OR_RETURN(auto t, transact(make_error_text(opt_.id, code), opt_.timeout, true));
  LMCFG_ASSIGN_OR_RETURN(auto r, decode_error_text(t));
  return r.text;
}
Result<ErrorCounters> Client::error_counters() {
  LMCFG_ASSIGN_OR_RETURN(auto t, transact(make_error_counters(opt_.id), opt_.timeout, true));
  return decode_error_counters(t);
}
Result<ErrorLogEntry> Client::error_log_entry(std::uint16_t index) {
  LMCFG_ASSIGN_OR_RETURN(auto t,
                         transact(make_error_log_entry(opt_.id, index), opt_.timeout, true));
  return decode_error_log_entry(t);
}

}  // namespace lmcfg::client
