// sim::LinudpDrive (linudp_drive.hpp). Sources by the short names of docs/references.md.
#include "sim/linudp_drive.hpp"

#include <algorithm>
#include <array>
#include <map>

#include "codec/frame.hpp"
#include "codec/messages.hpp"
#include "common/layers.hpp"

namespace lmcfg::sim {

using codec::CfgOp;
using codec::CtOp;
using codec::CurveOp;
using codec::ParamOp;
using codec::ProgramOp;
using linudp::RtcBlock;
namespace lst = linudp::status;

namespace {

std::array<std::uint8_t, 4> chunk_of(std::uint32_t v) {
  return {static_cast<std::uint8_t>(v & 0xFF), static_cast<std::uint8_t>((v >> 8) & 0xFF),
          static_cast<std::uint8_t>((v >> 16) & 0xFF), static_cast<std::uint8_t>(v >> 24)};
}

bool is_table_read(std::uint8_t id) {
  return (id >= 0x60 && id <= 0x62) || (id >= 0x85 && id <= 0x8E);
}

// A LinRS error state as the LinUDP status of the same meaning (LinUDP V2
// p14; LinRS §16.1's codes C1h-C9h mean other things).
std::uint8_t linudp_status_of(std::uint8_t linrs, std::uint8_t id) {
  if (linrs == codec::state::last_in_list) return lst::end_of_list;
  const bool curve = id >= 0x40 && id <= 0x62;
  if (linrs == 0xC8) return curve ? lst::curve_presence : lst::upid_error;  // unknown UPID/object
  if (linrs == 0xC9) return lst::range_error;                               // value refused
  if (linrs == 0xC4) return lst::address_usage_error;                       // not now / not so
  return lst::type_error;
}

struct FieldRow {
  const char* name;
  const char* help;
};
constexpr FieldRow kFieldRows[] = {
    {"unacknowledged_saves", "flash saves never acknowledged, drive deaf while saving"},
    {"save_s", "duration of a flash save in seconds (field reports: 39-75)"},
    {"silent_after_rom_write_s", "silence after each ROM write, seconds"},
    {"stale_echo_every", "every Nth reply preceded by a stale one"},
    {"lose_request_every", "every Nth request lost"},
    {"lose_reply_every", "every Nth reply lost"},
    {"held_by_other_master", "all-zero replies"},
    {"table_reads_need_mc_stopped", "curve/CT reads refused with D1h while MC runs"},
    {"end_on_extra_read", "block reads end with 00h on one more read"},
    {"list_spans_layers", "lists run on through the later layers"},
    {"curve_start_gives_sizes", "60h reply carries the sizes"},
    {"strict_counts", "counts 1, 15 (and 0 but for 30h) ignored"},
    {"running_status", "reply while a long command runs: 2, 5 or 0 = none"},
    {"filter_source_port", "only datagrams from port 41136 answered"},
    {"lose_save_requests", "the first N flash save requests (40h, 80h) lost"},
    {"lose_save_replies", "the replies to the first N flash saves lost"},
    {"silent_after_writes", "the connection cut after N writing commands"},
};

}  // namespace

std::string field_names() {
  std::string s;
  for (const auto& r : kFieldRows) s += std::string("  ") + r.name + ": " + r.help + "\n";
  return s;
}

Result<void> set_field(LinudpField& f, std::string_view spec) {
  const auto eq = spec.find('=');
  const std::string name(spec.substr(0, eq));
  const std::string value = eq == std::string_view::npos ? "1" : std::string(spec.substr(eq + 1));
  const auto num = parse_number(value, false);
  const bool flag = value == "1" || value == "true" || value == "yes";
  const bool unflag = value == "0" || value == "false" || value == "no";
  auto bad = [&](const char* expected) {
    return Error(Errc::invalid_argument,
                 "--linudp-field '" + std::string(spec) + "': " + expected + " expected");
  };
  auto set_bool = [&](bool& b) -> Result<void> {
    if (!flag && !unflag) return bad("true or false");
    b = flag;
    return {};
  };
  auto set_num = [&](unsigned& u) -> Result<void> {
    if (!num) return bad("a number");
    u = *num;
    return {};
  };
  if (name == "unacknowledged_saves") return set_bool(f.unacknowledged_saves);
  if (name == "held_by_other_master") return set_bool(f.held_by_other_master);
  if (name == "table_reads_need_mc_stopped") return set_bool(f.table_reads_need_mc_stopped);
  if (name == "end_on_extra_read") return set_bool(f.end_on_extra_read);
  if (name == "list_spans_layers") return set_bool(f.list_spans_layers);
  if (name == "curve_start_gives_sizes") return set_bool(f.curve_start_gives_sizes);
  if (name == "strict_counts") return set_bool(f.strict_counts);
  if (name == "filter_source_port") return set_bool(f.filter_source_port);
  if (name == "stale_echo_every") return set_num(f.stale_echo_every);
  if (name == "lose_request_every") return set_num(f.lose_request_every);
  if (name == "lose_reply_every") return set_num(f.lose_reply_every);
  if (name == "silent_after_writes") return set_num(f.silent_after_writes);
  if (name == "lose_save_requests") return set_num(f.lose_save_requests);
  if (name == "lose_save_replies") return set_num(f.lose_save_replies);
  if (name == "silent_after_rom_write_s") {
    if (!num) return bad("a number of seconds");
    f.silent_after_rom_write_us = static_cast<std::int64_t>(*num) * 1'000'000;
    return {};
  }
  if (name == "save_s") {
    if (!num) return bad("a number of seconds");
    f.save_us = static_cast<std::int64_t>(*num) * 1'000'000;
    return {};
  }
  if (name == "running_status") {
    if (!num || (*num != 0 && *num != 2 && *num != 5)) return bad("2, 5 or 0");
    f.running_status = static_cast<std::uint8_t>(*num);
    return {};
  }
  return Error(Errc::invalid_argument, "--linudp-field '" + std::string(spec) +
                                           "': unknown name; one of:\n" + field_names());
}

std::vector<std::string> field_words(const LinudpField& f) {
  const LinudpField d;
  std::vector<std::string> w;
  auto b = [&](const char* n, bool v, bool dv) {
    if (v != dv) w.push_back(std::string(n) + "=" + (v ? "true" : "false"));
  };
  auto u = [&](const char* n, long long v, long long dv) {
    if (v != dv) w.push_back(std::string(n) + "=" + std::to_string(v));
  };
  b("unacknowledged_saves", f.unacknowledged_saves, d.unacknowledged_saves);
  u("save_s", f.save_us / 1'000'000, d.save_us / 1'000'000);
  u("silent_after_rom_write_s", f.silent_after_rom_write_us / 1'000'000,
    d.silent_after_rom_write_us / 1'000'000);
  u("stale_echo_every", f.stale_echo_every, d.stale_echo_every);
  u("lose_request_every", f.lose_request_every, d.lose_request_every);
  u("lose_reply_every", f.lose_reply_every, d.lose_reply_every);
  b("held_by_other_master", f.held_by_other_master, d.held_by_other_master);
  b("table_reads_need_mc_stopped", f.table_reads_need_mc_stopped, d.table_reads_need_mc_stopped);
  b("end_on_extra_read", f.end_on_extra_read, d.end_on_extra_read);
  b("list_spans_layers", f.list_spans_layers, d.list_spans_layers);
  b("curve_start_gives_sizes", f.curve_start_gives_sizes, d.curve_start_gives_sizes);
  b("strict_counts", f.strict_counts, d.strict_counts);
  u("running_status", f.running_status, d.running_status);
  b("filter_source_port", f.filter_source_port, d.filter_source_port);
  u("lose_save_requests", f.lose_save_requests, d.lose_save_requests);
  u("lose_save_replies", f.lose_save_replies, d.lose_save_replies);
  u("silent_after_writes", f.silent_after_writes, d.silent_after_writes);
  return w;
}

LinudpDrive::LinudpDrive(std::shared_ptr<Drive> drive, LinudpField field)
    : drive_(std::move(drive)), field_(field) {
  if (field_.save_us > 0) drive_->state().timing.flash_save_us = field_.save_us;
}

Bytes LinudpDrive::reply_bytes(const linudp::Request& req, const RtcBlock& rtc) const {
  const DriveState& s = drive_->state();
  linudp::Response r;
  r.request_def = req.request_def;  // echoed (C1250 notes)
  r.response_def = req.response_def;
  // MC stopped: status word and state var read 0, as the LinRS simulator's.
  r.status_word = s.mc_running ? s.live.status_word : 0;
  r.state_var = s.mc_running ? s.live.state_var : 0;
  r.actual_pos = 0;
  r.demand_pos = 0;
  r.current = 0;
  r.warn_word = s.live.warn_word;
  r.error_code = s.live.error_code;
  r.monitoring = std::array<std::uint32_t, 4>{s.live.monitoring_1, s.live.monitoring_2, 0, 0};
  r.rtc = rtc;
  return linudp::encode_response(r);
}

std::vector<Answer> LinudpDrive::receive(ByteView datagram, std::int64_t now,
                                         std::uint16_t source_port) {
  ++stats_.datagrams;
  ++requests_seen_;
  if (field_.lose_request_every && requests_seen_ % field_.lose_request_every == 0) {
    ++stats_.ignored;
    return {};
  }
  if (field_.filter_source_port && source_port != 0 && source_port != linudp::kMasterPort) {
    ++stats_.ignored;
    return {};
  }
  auto req = linudp::decode_request(datagram);
  if (!req.ok()) {
    ++stats_.ignored;
    return {};
  }
  if (req->control_word || req->has_mc) ++stats_.motion_telegrams;
  const std::int64_t turnaround = drive_->state().timing.turnaround_us * 1000;
  auto out = [&](Bytes b, std::int64_t delay) {
    ++replies_made_;
    std::vector<Answer> v;
    if (field_.lose_reply_every && replies_made_ % field_.lose_reply_every == 0) return v;
    if (field_.stale_echo_every && replies_made_ % field_.stale_echo_every == 0 &&
        !previous_reply_.empty())
      v.push_back(Answer{previous_reply_, delay});  // C1250 notes: the old count first
    v.push_back(Answer{b, delay});
    previous_reply_ = std::move(b);
    return v;
  };
  if (field_.held_by_other_master) return out(Bytes(linudp::kPaddedSize, 0), turnaround);
  if (now < deaf_until_ns_ ||
      (field_.silent_after_writes && writes_ >= field_.silent_after_writes)) {
    ++stats_.ignored;
    return {};
  }
  if (!req->rtc) return out(reply_bytes(*req, RtcBlock{}), turnaround);
  const RtcBlock& rtc = *req->rtc;
  if (last_count_ && rtc.count == *last_count_ && cached_) {
    // LinUDP V2 §7: the same count is not executed again; the reply is repeated.
    ++stats_.resends;
    if (cached_unanswered_) return {};
    if (now < ready_at_ns_) {
      if (field_.running_status == 0) return {};
      RtcBlock b;
      b.count = rtc.count;
      b.id = field_.running_status;
      return out(reply_bytes(*req, b), turnaround);
    }
    return out(reply_bytes(*req, *cached_), turnaround);
  }
  const bool restart = rtc.id == static_cast<std::uint8_t>(linudp::Cmd::restart);
  if (rtc.count == 1 || rtc.count == 15 || (rtc.count == 0 && !restart)) {
    ++stats_.counts_seen_15;
    if (field_.strict_counts) {
      ++stats_.ignored;
      return {};
    }
  }
  const bool save = rtc.id == 0x40 || rtc.id == 0x80;
  if (save && save_requests_lost_ < field_.lose_save_requests && rtc.count != lost_save_count_) {
    ++save_requests_lost_;         // lost on the way: the drive never saw this count
    lost_save_count_ = rtc.count;  // its resend (same count) arrives
    ++stats_.ignored;
    return {};
  }
  ++stats_.commands;
  if (save) ++stats_.saves;
  if (linudp::is_write_command(rtc.id)) ++writes_;
  last_count_ = rtc.count;
  Outcome o = execute(rtc, now);
  o.reply.count = rtc.count;
  cached_ = o.reply;
  cached_unanswered_ = o.unanswered;
  if (save && save_replies_lost_ < field_.lose_save_replies) {
    ++save_replies_lost_;  // carried out, its reply lost; a resend gets it
    ready_at_ns_ = std::max(ready_at_ns_, now + o.duration_ns);
    if (o.unanswered) deaf_until_ns_ = now + o.duration_ns;
    return {};
  }
  if (o.unanswered) {
    deaf_until_ns_ = now + o.duration_ns;
    ready_at_ns_ = deaf_until_ns_;
    return {};
  }
  ready_at_ns_ = std::max(ready_at_ns_, now + o.duration_ns);
  const bool rom_write = rtc.id == 0x12 || rtc.id == 0x14;
  if (rom_write && o.reply.id == lst::ok && field_.silent_after_rom_write_us > 0)
    deaf_until_ns_ = ready_at_ns_ + turnaround + field_.silent_after_rom_write_us * 1000;
  if (ready_at_ns_ <= now + turnaround) return out(reply_bytes(*req, o.reply), turnaround);
  if (field_.running_status == 0) return out(reply_bytes(*req, o.reply), ready_at_ns_ - now);
  RtcBlock b;
  b.count = rtc.count;
  b.id = field_.running_status;
  return out(reply_bytes(*req, b), turnaround);
}

std::optional<codec::Telegram> LinudpDrive::linrs_request(const RtcBlock& r) const {
  const std::uint8_t id = drive_->macid();
  const std::uint16_t k = r.w2;
  const std::uint16_t list_key = layers::base_upid(list_layer_ == 0 ? 1 : list_layer_);
  switch (r.id) {
    case 0x10:
      return codec::make_cfg(id, CfgOp::read_rom, k);
    case 0x11:
      return codec::make_param_read(id, ParamOp::read_ram, k);
    case 0x12:
      return codec::make_cfg_write(id, k, r.value());
    case 0x13:
      return codec::make_param_write(id, ParamOp::write_ram, k, r.value());
    case 0x14:
      return codec::make_param_write(id, ParamOp::write_ram_rom, k, r.value());
    case 0x15:
      return codec::make_cfg(id, CfgOp::get_min, k);
    case 0x16:
      return codec::make_cfg(id, CfgOp::get_max, k);
    case 0x17:
      return codec::make_cfg(id, CfgOp::get_default, k);
    case 0x20:
      return codec::make_cfg(id, CfgOp::start_upid_list, k);
    case 0x21:
      return codec::make_cfg(id, CfgOp::next_upid, list_key);
    case 0x22:
      return codec::make_cfg(id, CfgOp::start_modified, k);
    case 0x23:
      return codec::make_cfg(id, CfgOp::next_modified, list_key);
    case 0x30:
      return codec::make_program(id, ProgramOp::reset_after_completion);
    case 0x31:
    case 0x32:
    case 0x33:
    case 0x34:
      return codec::make_cfg_default_layer(id, r.id - 0x30);
    case 0x35:
      return codec::make_program(id, ProgramOp::stop_mc);
    case 0x36:
      return codec::make_program(id, ProgramOp::start_after_completion);
    case 0x40:
      return codec::make_curve(id, CurveOp::save_to_flash);
    case 0x41:
      return codec::make_curve(id, CurveOp::delete_all);
    case 0x50:
      return codec::make_curve_add(id, k, r.w3, r.w4);
    case 0x51:
      return codec::make_curve_write(id, CurveOp::write_info, k, chunk_of(r.value()));
    case 0x52:
      return codec::make_curve_write(id, CurveOp::write_data, k, chunk_of(r.value()));
    case 0x60:
      return codec::make_curve(id, CurveOp::read_sizes, k);
    case 0x61:
      return codec::make_curve(id, CurveOp::read_info, k);
    case 0x62:
      return codec::make_curve(id, CurveOp::read_data, k);
    case 0x70:
      return codec::make_error_counters(id);
    case 0x71:
    case 0x72:
    case 0x73:
      return codec::make_error_log_entry(id, k);
    case 0x74:
      return codec::make_error_text(id, k);
    case 0x80:
      return codec::make_ct(id, CtOp::save_to_flash);
    case 0x81:
      return codec::make_ct(id, CtOp::delete_all);
    case 0x82:
      return codec::make_ct(id, CtOp::delete_one, k);
    case 0x83:
      return codec::make_ct_setup_write(id, k, r.w3);
    case 0x84:
      return codec::make_ct_write(id, k, chunk_of(r.value()));
    case 0x85:
      return codec::make_ct(id, CtOp::setup_read, k);
    case 0x86:
      return codec::make_ct(id, CtOp::read_data, k);
    default:
      if (r.id >= 0x87 && r.id <= 0x8E)
        return codec::make_ct_defined_list(id, static_cast<std::uint16_t>(r.id - 0x87));
      return std::nullopt;
  }
}

LinudpDrive::Outcome LinudpDrive::execute(const RtcBlock& rtc, std::int64_t now) {
  Outcome o;
  o.reply.w2 = rtc.w2;
  if (owed_end_ && rtc.id == *owed_end_) {
    owed_end_.reset();  // the LinUDP DLL's reading: 00h on one more read
    o.reply.id = lst::ok;
    return o;
  }
  owed_end_.reset();
  if (rtc.id == static_cast<std::uint8_t>(linudp::Cmd::nop)) return o;
  if (field_.table_reads_need_mc_stopped && is_table_read(rtc.id) && drive_->state().mc_running) {
    o.reply.id = lst::size_error;  // the C1250 notes' mock drive's D1h
    return o;
  }
  if (rtc.id == 0x21 || rtc.id == 0x23) return list_next(rtc, rtc.id == 0x23, now);
  if (rtc.id == 0x20 || rtc.id == 0x22) {
    list_layer_ = std::max(1, layers::of_upid(rtc.w2));
    list_modified_ = rtc.id == 0x22;
    list_ended_ = false;
    list_seen_.clear();
  }
  const auto t = linrs_request(rtc);
  if (!t) {
    o.reply.id = lst::type_error;  // an ID LinUDP V2 p13-p19 does not list
    return o;
  }
  return from_linrs(rtc, drive_->handle(*t, now), now);
}

LinudpDrive::Outcome LinudpDrive::from_linrs(const RtcBlock& rtc, const std::optional<Answer>& a,
                                             std::int64_t) {
  Outcome o;
  o.reply.w2 = rtc.w2;
  const DriveState& s = drive_->state();
  const bool save = rtc.id == 0x40 || rtc.id == 0x80;
  if (!a) {
    // The LinRS drive stayed silent: busy, or a save it never answers.
    if (save) {
      o.unanswered = true;
      o.duration_ns = s.timing.flash_save_us * 1000;
      return o;
    }
    o.reply.id = lst::busy;
    return o;
  }
  const std::int64_t turnaround = s.timing.turnaround_us * 1000;
  if (a->delay_ns > 2 * turnaround) o.duration_ns = a->delay_ns;
  auto t = codec::decode(a->bytes, s.checksum);
  if (!t.ok()) {
    o.reply.id = lst::type_error;
    return o;
  }
  if (auto e = codec::error_state_of(*t)) {
    o.reply.id = linudp_status_of(*e, rtc.id);
    o.duration_ns = 0;
    return o;
  }
  if (save && field_.unacknowledged_saves) {
    o.unanswered = true;  // field reports: done, never acknowledged
    return o;
  }
  fill(rtc, *t, o);
  return o;
}

void LinudpDrive::fill(const RtcBlock& rtc, const codec::Telegram& answer, Outcome& o) {
  const DriveState& s = drive_->state();
  const codec::Telegram* t = &answer;
  const Bytes& d = t->data;
  const bool id_value_form = d.size() == 7;
  const std::uint8_t state = id_value_form ? d[0] : lst::ok;
  const std::uint32_t value = id_value_form ? get_u32le(d, 3) : 0;
  o.reply.id = state;
  switch (rtc.id) {
    case 0x11: {
      auto r = codec::decode_default_response(*t, s.layout);
      if (r.ok() && r->value) o.reply.set_value(*r->value);
      break;
    }
    case 0x10:
    case 0x15:
    case 0x16:
    case 0x17:
      o.reply.set_value(value);
      break;
    case 0x60:
      if (value == 0) {
        o.reply.id = lst::curve_presence;  // LinUDP V2 p13-p15: D4h = absent
      } else if (field_.curve_start_gives_sizes) {
        o.reply.w3 = static_cast<std::uint16_t>(value & 0xFFFF);
        o.reply.w4 = static_cast<std::uint16_t>(value >> 16);
      }
      break;
    case 0x61:
    case 0x62:
    case 0x86:
      o.reply.set_value(value);
      if (state == lst::ok && field_.end_on_extra_read) {
        o.reply.id = lst::block_more;
        owed_end_ = rtc.id;
      }
      break;
    case 0x85:
      o.reply.w3 = static_cast<std::uint16_t>(value & 0xFFFF);
      break;
    case 0x70: {
      auto c = codec::decode_error_counters(*t);
      o.reply.id = lst::ok;
      if (c.ok()) {
        o.reply.w3 = c->logged;
        o.reply.w4 = c->occurred;
      }
      break;
    }
    case 0x71:
    case 0x72:
    case 0x73: {
      auto e = codec::decode_error_log_entry(*t);
      o.reply.id = lst::ok;
      if (!e.ok()) {
        o.reply.id = lst::range_error;
      } else if (rtc.id == 0x71) {
        o.reply.w3 = e->code;
      } else {
        o.reply.set_value(rtc.id == 0x72 ? e->millis : e->hours);
      }
      break;
    }
    case 0x74: {
      auto e = codec::decode_error_text(*t);
      o.reply.id = lst::ok;
      std::string text = e.ok() ? e->text : std::string();
      text.resize(32, '\0');
      const std::size_t at = std::min<std::size_t>(rtc.w3, 7) * 4;
      o.reply.set_value(get_u32le(as_bytes(text), at));
      break;
    }
    default:
      if (rtc.id >= 0x87 && rtc.id <= 0x8E) o.reply.set_value(value);
      if (!id_value_form) o.reply.id = lst::ok;  // program and parameter-group answers
      break;
  }
}

LinudpDrive::Outcome LinudpDrive::list_next(const RtcBlock& rtc, bool modified, std::int64_t now) {
  Outcome o;
  if (list_layer_ == 0 || modified != list_modified_) {
    o.reply.id = lst::next_without_start;
    return o;
  }
  const std::uint8_t id = drive_->macid();
  auto item = [&](const codec::Telegram& tg) {
    o.reply.id = lst::ok;
    o.reply.w2 = get_u16le(tg.data, 1);
    if (modified) {
      o.reply.set_value(get_u32le(tg.data, 3));  // LinUDP V2 p16, 23h: w3/w4 = the value
    } else {
      o.reply.w3 = get_u16le(tg.data, 3);  // address usage
      o.reply.w4 = get_u16le(tg.data, 5);  // the type, as on LinRS (open in LinUDP V2)
    }
    return o;
  };
  for (;;) {
    if (!list_ended_) {
      const auto t = linrs_request(rtc);
      const auto a = drive_->handle(*t, now);
      if (!a) {
        o.reply.id = lst::busy;
        return o;
      }
      auto tg = codec::decode(a->bytes, drive_->state().checksum);
      if (!tg.ok() || tg->data.size() < 7) {
        o.reply.id = lst::type_error;
        return o;
      }
      const std::uint16_t upid = get_u16le(tg->data, 1);
      if (tg->data[0] != codec::state::last_in_list) {
        if (auto e = codec::error_state_of(*tg)) {
          o.reply.id = linudp_status_of(*e, rtc.id);
          return o;
        }
        list_seen_.insert(upid);
        return item(*tg);
      }
      // The LinRS list's C6 answer may carry an entry not listed yet (seed
      // 003 §10.2); on LinUDP the end is a C6h of its own (LinUDP V2 p16).
      list_ended_ = true;
      if (layers::of_upid(upid) == list_layer_ && list_seen_.insert(upid).second) return item(*tg);
    }
    if (field_.list_spans_layers && list_layer_ < layers::kCount) {
      // The LinUDP DLL's reading: the list runs on into the next layer.
      ++list_layer_;
      list_ended_ = false;
      const auto base = layers::base_upid(list_layer_);
      (void)drive_->handle(
          codec::make_cfg(id, modified ? CfgOp::start_modified : CfgOp::start_upid_list, base),
          now);
      continue;
    }
    o.reply.id = lst::end_of_list;
    return o;
  }
}

}  // namespace lmcfg::sim
