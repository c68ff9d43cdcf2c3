#include "sim/drive.hpp"

#include <algorithm>
#include <array>

#include "codec/requests.hpp"
#include "common/layers.hpp"

namespace lmcfg::sim {

using codec::CfgOp;
using codec::ErrorInfoOp;
using codec::Main;
using codec::ParamOp;
using codec::ProgramOp;
using codec::ResponseRequest;
using codec::Telegram;
namespace st = codec::state;

// sim::Layer values are the layer numbers of common/layers.hpp (none = 0).
static_assert(static_cast<int>(Layer::appl) == layers::kCount);
Layer layer_of(std::uint16_t upid) { return static_cast<Layer>(layers::of_upid(upid)); }

std::uint16_t layer_base(Layer l) { return layers::base_upid(static_cast<int>(l)); }

const char* layer_name(Layer l) {
  return l == Layer::none ? "none" : layers::name(static_cast<int>(l)).data();
}

namespace {

// The field as a number of its type for range checks: signed types
// sign-extended from their width; other and unknown codes as unsigned.
std::int64_t as_number(std::uint16_t code, std::uint32_t v) {
  const auto t = type_from_code(code);
  if (!t || !is_signed_type(*t)) return static_cast<std::int64_t>(v);
  const unsigned bits = 8 * type_size(*t);
  if (bits >= 32) return static_cast<std::int32_t>(v);
  const std::uint32_t field = v & ((1u << bits) - 1);
  const std::uint32_t sign = 1u << (bits - 1);
  return (field & sign) ? static_cast<std::int64_t>(field) - (std::int64_t{1} << bits)
                        : static_cast<std::int64_t>(field);
}

// LIN_FLOAT and the text types have no integer range; an unknown code is
// checked as unsigned.
bool range_checked(std::uint16_t code) {
  const auto t = type_from_code(code);
  return !t || !(is_text_type(*t) || *t == TypeCode::LinFloat);
}

}  // namespace

bool in_range(const Parameter& p, std::uint32_t value) {
  if (!range_checked(p.type)) return true;
  const auto v = as_number(p.type, value);
  return v >= as_number(p.type, p.min) && v <= as_number(p.type, p.max);
}

std::map<std::uint16_t, std::string> default_error_texts() {
  return {
      {0x0000, "No Error"},                       // LinRS §14.1
      {0x0001, "Err: X4 Logic Supply Too Low"},   // LinRS §14.2
      {0x000C, "Err. Pos Lag Standing Too Big"},  // LinRS §14.4
  };
}

Drive::Drive() : Drive(DriveState{}) {}

Drive::Drive(DriveState state) : s_(std::move(state)), decoder_(s_.checksum) {
  if (s_.error_texts.empty()) s_.error_texts = default_error_texts();
  if (!s_.switches) s_.switches = HexSwitches{s_.macid, s_.link.baud};
}

void Drive::apply_comm_parameters() {
  constexpr std::uint32_t kByParameterBaud = 2;   // LinRS §10.2: 200Eh value 2 "By Parameter"
  constexpr std::uint32_t kByParameterMacid = 3;  // LinRS §10.2: 206Ch value 3 "By Parameter"
  const HexSwitches sw = s_.switches.value_or(HexSwitches{s_.macid, s_.link.baud});
  unsigned baud = sw.baud;
  if (rom(0x200E) == kByParameterBaud) {
    if (auto code = rom(0x2012)) {
      if (auto it = s_.options.baud_codes.find(*code); it != s_.options.baud_codes.end())
        baud = it->second;
    }
  }
  std::uint8_t id = sw.macid;
  if (rom(0x206C) == kByParameterMacid) {
    if (auto v = rom(0x2076)) id = static_cast<std::uint8_t>(*v & 0xFF);
  }
  s_.link.baud = baud;
  s_.macid = id;
  // The settings LinRS §15 names without a UPID (Options::checksum_param ...).
  auto code_of = [&](const std::optional<Options::CommParam>& p) -> const std::string* {
    if (!p) return nullptr;
    auto v = rom(p->upid);
    if (!v) return nullptr;
    auto it = p->codes.find(*v);
    return it == p->codes.end() ? nullptr : &it->second;
  };
  if (const std::string* c = code_of(s_.options.checksum_param)) {
    const codec::ChecksumCoverage coverage = s_.checksum.coverage;
    if (*c == "none") s_.checksum = {codec::ChecksumMode::none, 0xFFFF, coverage};
    if (*c == "add") s_.checksum = {codec::ChecksumMode::add, 0xFFFF, coverage};
    if (*c == "crc" || *c == "crc-ffff")
      s_.checksum = {codec::ChecksumMode::crc_ccitt, 0xFFFF, coverage};
    if (*c == "crc-0000") s_.checksum = {codec::ChecksumMode::crc_ccitt, 0x0000, coverage};
    if (*c == "crc-kermit") s_.checksum = {codec::ChecksumMode::crc_kermit, 0x0000, coverage};
  }
  if (const std::string* c = code_of(s_.options.parity_param)) {
    if (auto p = transport::parity_from_name(*c)) s_.link.parity = *p;
  }
  if (const std::string* c = code_of(s_.options.stop_bits_param)) {
    if (*c == "1" || *c == "2") s_.link.stop_bits = *c == "1" ? 1U : 2U;
  }
}

Parameter* Drive::find(std::uint16_t upid) {
  auto it = s_.params.find(upid);
  return it == s_.params.end() ? nullptr : &it->second;
}
std::optional<std::uint32_t> Drive::ram(std::uint16_t upid) const {
  auto it = s_.params.find(upid);
  if (it == s_.params.end()) return std::nullopt;
  return it->second.ram;
}
std::optional<std::uint32_t> Drive::rom(std::uint16_t upid) const {
  auto it = s_.params.find(upid);
  if (it == s_.params.end()) return std::nullopt;
  return it->second.rom;
}

// ---- byte front end ----------------------------------------------------------

std::vector<Answer> Drive::receive(ByteView bytes, std::int64_t now_ns) {
  std::vector<Answer> out;
  // Byte-to-byte receive time-out (§15): a partial telegram is dropped.
  if (s_.timing.rx_timeout_us > 0 && have_last_byte_ && decoder_.buffered() > 0 &&
      now_ns - last_byte_ns_ > s_.timing.rx_timeout_us * 1000) {
    if (decoder_.flush_idle()) ++stats_.bad_frames;
    window_.clear();
  }
  const std::size_t chk = s_.checksum.size();
  // Bytes are fed one at a time (as a UART delivers them), so when the decoder
  // reports a broken frame, that frame ends at the byte just fed.
  auto frame_id_ending_here = [&](bool want_end_marker) -> std::optional<std::uint8_t> {
    const std::size_t n = window_.size();
    const std::size_t lo = n > 70 ? n - 70 : 0;
    for (std::size_t s = lo; s + 4 <= n; ++s) {
      if (window_[s] != codec::kStartHeader || window_[s + 3] != codec::kStartData) continue;
      if (s + 3 + window_[s + 2] + chk + 1 != n) continue;
      if (want_end_marker != (window_.back() == codec::kEndTelegram)) continue;
      return window_[s + 1];
    }
    return std::nullopt;
  };
  for (std::uint8_t b : bytes) {
    window_.push_back(b);
    if (window_.size() > 512) window_.erase(window_.begin(), window_.end() - 128);
    decoder_.feed(ByteView(&b, 1));
    while (auto r = decoder_.next()) {
      if (r->ok()) {
        if (auto a = handle(r->value(), now_ns)) out.push_back(std::move(*a));
        continue;
      }
      ++stats_.bad_frames;
      const auto code = r->error().code;
      std::optional<std::uint8_t> id;
      std::uint8_t state = 0;
      if (code == make_error_code(Errc::checksum_mismatch) &&
          s_.options.respond_on_checksum_error) {
        id = frame_id_ending_here(true);
        state = st::checksum_error;
      } else if (code == make_error_code(Errc::frame_short) && s_.options.respond_on_end_missing) {
        id = frame_id_ending_here(false);
        state = st::end_missing;
      }
      if (id && *id == s_.macid) {
        if (auto a = error_answer(state, now_ns)) out.push_back(std::move(*a));
      }
    }
  }
  last_byte_ns_ = now_ns;
  have_last_byte_ = true;
  return out;
}

// ---- answer construction -----------------------------------------------------

Telegram Drive::default_response(std::uint8_t comm_state,
                                 std::optional<std::uint32_t> value) const {
  codec::DefaultResponse r;
  r.comm_state = comm_state;
  // MC stopped: status word and state var read 0 (LinRS §13.3 and §10.1 captures).
  r.status_word = s_.mc_running ? s_.live.status_word : 0;
  r.state_var = s_.mc_running ? s_.live.state_var : 0;
  r.error_code = s_.live.error_code;
  r.warn_word = s_.live.warn_word;
  r.echo_header = last_motion_header_;
  r.monitoring_1 = s_.live.monitoring_1;
  r.monitoring_2 = s_.live.monitoring_2;
  r.value = value;
  return codec::make_default_response(s_.macid, r, s_.layout);
}

Telegram Drive::id_value(std::uint8_t sub, std::uint8_t state, std::uint16_t key,
                         std::uint32_t value) const {
  // LinRS §11 marks the key and value of several answers "No meaning": a
  // drive may fill them with anything when it refuses. The bytes chosen for
  // `arbitrary` depend on the request only, so a repeated read agrees.
  if (codec::state::is_error(state)) {
    switch (s_.options.refusal_fields) {
      case RefusalFields::echo:
        break;
      case RefusalFields::zeros:
        key = 0;
        value = 0;
        break;
      case RefusalFields::arbitrary:
        key = static_cast<std::uint16_t>(key * 0x9E37u + sub * 0x3Bu + 0x5A5Au);
        value = 0xA5C3'0F96u ^ (std::uint32_t{key} << 8) ^ sub;
        break;
    }
  }
  return codec::make_id_value(s_.macid, sub, state, key, value);
}

Answer Drive::finish(const Telegram& reply, std::int64_t extra_us, std::int64_t now_ns) {
  Answer a;
  auto enc = codec::encode(reply, s_.checksum);
  if (enc.ok()) a.bytes = std::move(enc).value();
  a.delay_ns = (s_.timing.turnaround_us + extra_us) * 1000;
  if (extra_us > 0) busy_until_ns_ = std::max(busy_until_ns_, now_ns + a.delay_ns);
  ++stats_.answers;
  if (!reply.data.empty() && st::is_error(reply.data[0])) ++stats_.error_answers;
  return a;
}

std::optional<Answer> Drive::finish_long(const Telegram& reply, std::int64_t duration_us,
                                         std::int64_t now_ns) {
  if (!s_.options.unanswered_saves) return finish(reply, duration_us, now_ns);
  busy_until_ns_ =
      std::max(busy_until_ns_, now_ns + (s_.timing.turnaround_us + duration_us) * 1000);
  return std::nullopt;
}

std::optional<Answer> Drive::error_answer(std::uint8_t comm_state, std::int64_t now_ns) {
  if (s_.options.ignore_while_busy && busy(now_ns)) {
    ++stats_.ignored_busy;
    return std::nullopt;
  }
  return finish(default_response(comm_state), 0, now_ns);
}

// ---- telegram front end ------------------------------------------------------

std::optional<Answer> Drive::handle(const Telegram& t, std::int64_t now) {
  ++stats_.telegrams_seen;
  if (t.id != s_.macid) {
    ++stats_.ignored_other_id;
    return std::nullopt;
  }
  ++stats_.telegrams_for_me;
  if (silenced_ || (s_.options.ignore_while_busy && busy(now))) {
    ++stats_.ignored_busy;
    return std::nullopt;
  }
  // The codec's request table (LinRS §5-14) decides which requests exist
  // and what they carry; the handlers below only act on them.
  if (!codec::known_main(t.main)) return error_answer(st::bad_main_id, now);
  const auto spec = codec::request_spec(t.main, t.sub);
  if (!spec || t.data.size() < spec->data_len) return error_answer(st::bad_sub_id, now);
  switch (static_cast<Main>(t.main)) {
    case Main::response:
      return on_response_request(t, now);
    case Main::control_word:
      control_word_ = get_u16le(t.data, 0);
      return finish(default_response(st::ok), 0, now);
    case Main::motion_command:
      last_motion_header_ = get_u16le(t.data, 0);
      return finish(default_response(st::ok), 0, now);
    case Main::parameter:
      if (!family().stored_defaults && (t.sub == static_cast<std::uint8_t>(ParamOp::get_default) ||
                                        t.sub >= codec::kParamDefaultLayerFirst))
        return error_answer(st::bad_sub_id, now);  // DCF p8: no stored defaults
      return on_parameter(t, now);
    case Main::curve:
      if (!family().curves) return error_answer(st::bad_main_id, now);  // 3V27 §11
      return on_family_table(t, now);
    case Main::param_config:
      if (!family().stored_defaults && (t.sub == static_cast<std::uint8_t>(CfgOp::get_default) ||
                                        t.sub >= static_cast<std::uint8_t>(CfgOp::default_os)))
        return error_answer(st::bad_sub_id, now);
      return on_param_config(t, now);
    case Main::program:
      return on_program(t, now);
    case Main::error_info:
      return on_error_info(t, now);
    case Main::command_table:
      if (!family().command_table) return error_answer(st::bad_main_id, now);  // 3V27 §12
      return on_family_table(t, now);
  }
  return error_answer(st::bad_main_id, now);
}

const families::Family& Drive::family() const {
  const families::Family* f = families::find(s_.options.family);
  return f ? *f : families::reference();
}

// Curves and command table as the family keeps them. LinRS 3V27 p32: on a
// C1100 add and delete act on flash directly, "save to flash" has no function.
std::optional<Answer> Drive::on_family_table(const Telegram& t, std::int64_t now) {
  const bool curve = t.main == static_cast<std::uint8_t>(Main::curve);
  if (family().flash_save) return curve ? on_curve(t, now) : on_command_table(t, now);
  if (t.sub == 0x00)  // save to flash (§11 04h 00h, §12 08h 00h): nothing to do
    return finish(id_value(codec::expected_answer_sub(t), st::ok, 0, 0), 0, now);
  auto a = curve ? on_curve(t, now) : on_command_table(t, now);
  s_.curves_flash = s_.curves_ram;
  s_.ct_flash = s_.ct_ram;
  return a;
}

std::optional<Answer> Drive::on_response_request(const Telegram& t, std::int64_t now) {
  switch (static_cast<ResponseRequest>(t.sub)) {
    case ResponseRequest::default_response:
      return finish(default_response(st::ok), 0, now);
    case ResponseRequest::status_word:
      return finish(default_response(st::ok, s_.mc_running ? s_.live.status_word : 0u), 0, now);
    case ResponseRequest::warn_word:
      return finish(default_response(st::ok, s_.live.warn_word), 0, now);
    case ResponseRequest::state_var:
      return finish(default_response(st::ok, s_.mc_running ? s_.live.state_var : 0u), 0, now);
  }
  return error_answer(st::bad_sub_id, now);
}

// ---- parameters (§9, §10) ----------------------------------------------------

bool Drive::refuses_configuration() const {
  return s_.options.refuse_config_while_mc_runs && s_.mc_running;
}

std::uint8_t Drive::write_value(Parameter& p, bool ram, bool rom, std::uint32_t value) {
  const auto& o = s_.options;
  if (rom && refuses_configuration()) return o.config_refused_state;
  if (o.write_policy != WritePolicy::accept) {
    const bool au_ok =
        (!ram || (p.address_usage & au::ram_write)) && (!rom || (p.address_usage & au::rom_write));
    if (!au_ok) return o.reject_state;
    if (!in_range(p, value)) {
      if (o.write_policy == WritePolicy::reject) return o.reject_state;
      value = as_number(p.type, value) < as_number(p.type, p.min) ? p.min : p.max;
    }
  }
  if (ram) p.ram = value;
  if (rom) p.rom = value;
  return st::ok;
}

void Drive::default_layer(Layer l) {
  for (auto& [upid, p] : s_.params)
    if (layer_of(upid) == l && p.has_rom()) p.rom = p.def;
}

void Drive::load_ram_from_rom() {
  for (auto& [upid, p] : s_.params)
    if (p.has_rom()) p.ram = p.rom;
  if (s_.options.reload_tables_on_start) {
    s_.curves_ram = s_.curves_flash;
    s_.ct_ram = s_.ct_flash;
  }
  xfer_ = {};
}

std::optional<Answer> Drive::on_parameter(const Telegram& t, std::int64_t now) {
  if (t.sub >= codec::kParamDefaultLayerFirst && t.sub <= codec::kParamDefaultLayerLast) {
    if (refuses_configuration())
      return finish(default_response(s_.options.config_refused_state), 0, now);
    default_layer(static_cast<Layer>(t.sub - codec::kParamDefaultLayerFirst + 1));
    return finish_long(default_response(st::ok), s_.timing.defaulting_us, now);
  }
  const std::uint16_t upid = get_u16le(t.data, 0);
  Parameter* p = find(upid);
  if (!p) return error_answer(st::unknown_upid, now);
  const auto op = static_cast<ParamOp>(t.sub);
  switch (op) {
    case ParamOp::read_ram:
      return finish(default_response(st::ok, p->ram), 0, now);
    case ParamOp::read_rom:
      return finish(default_response(st::ok, p->rom), 0, now);
    case ParamOp::get_min:
      return finish(default_response(st::ok, p->min), 0, now);
    case ParamOp::get_max:
      return finish(default_response(st::ok, p->max), 0, now);
    case ParamOp::get_default:
      return finish(default_response(st::ok, p->def), 0, now);
    case ParamOp::write_ram:
    case ParamOp::write_rom:
    case ParamOp::write_ram_rom:
      break;
  }
  const std::uint32_t v = get_u32le(t.data, 2);
  const std::uint8_t state = write_value(*p, op != ParamOp::write_rom, op != ParamOp::write_ram, v);
  return finish(default_response(state), 0, now);
}

std::optional<Answer> Drive::on_param_config(const Telegram& t, std::int64_t now) {
  const std::uint8_t sub = codec::expected_answer_sub(t);
  const auto& o = s_.options;
  const auto op = static_cast<CfgOp>(t.sub);
  if (op >= CfgOp::default_os && op <= CfgOp::default_appl) {
    const auto layer =
        static_cast<std::uint8_t>(t.sub - static_cast<std::uint8_t>(CfgOp::default_os) + 1);
    const std::uint16_t key = t.data.size() >= 2 ? get_u16le(t.data, 0) : 0;
    if (refuses_configuration())
      return finish(id_value(sub, o.config_refused_state, key, layer), 0, now);
    default_layer(static_cast<Layer>(layer));
    return finish_long(id_value(sub, st::ok, key, layer), s_.timing.defaulting_us, now);
  }
  // 09h/0Bh: the UPID field is ignored (a seed erratum; §10.3 "not used").
  if (op == CfgOp::next_modified) {
    auto& c = modified_;
    auto empty = [&] {
      c.ended = true;
      const std::uint16_t upid =
          o.empty_list_echo_upid && t.data.size() >= 2 ? get_u16le(t.data, 0) : o.empty_list_upid;
      return finish(id_value(sub, o.empty_list_state, upid, 0), 0, now);
    };
    if (!c.active || c.ended) return empty();
    auto it = c.last ? s_.params.upper_bound(*c.last) : s_.params.lower_bound(layer_base(c.layer));
    auto is_next = [&](const auto& kv) {
      return layer_of(kv.first) == c.layer && kv.second.modified();
    };
    auto found = std::find_if(it, s_.params.end(), is_next);
    if (found == s_.params.end()) return empty();
    const bool more = std::find_if(std::next(found), s_.params.end(), is_next) != s_.params.end();
    c.last = found->first;
    if (!more) c.ended = true;
    return finish(id_value(sub, more ? st::ok : st::last_in_list, found->first, found->second.rom),
                  0, now);
  }
  if (op == CfgOp::next_upid) {
    auto& c = upids_;
    auto entry = [&](std::uint8_t state, const Parameter& p) {
      return finish(id_value(sub, state, p.upid,
                             static_cast<std::uint32_t>(p.address_usage | (p.type << 16))),
                    0, now);
    };
    if (!c.active) return finish(id_value(sub, o.empty_list_state, o.empty_list_upid, 0), 0, now);
    if (!c.ended) {
      auto it =
          c.last ? s_.params.upper_bound(*c.last) : s_.params.lower_bound(layer_base(c.layer));
      if (it != s_.params.end() && layer_of(it->first) == c.layer) {
        c.last = it->first;
        return entry(st::ok, it->second);
      }
      c.ended = true;
    }
    // End of list: C6 repeating the previous UPID (§10.3).
    if (c.last) {
      if (auto* p = find(*c.last)) return entry(st::last_in_list, *p);
    }
    return finish(id_value(sub, o.empty_list_state, o.empty_list_upid, 0), 0, now);
  }
  const std::uint16_t upid = get_u16le(t.data, 0);
  if (op == CfgOp::start_modified || op == CfgOp::start_upid_list) {
    const Layer l = layer_of(upid);
    if (l == Layer::none) return finish(id_value(sub, st::unknown_upid, upid, 0), 0, now);
    ListCursor& c = op == CfgOp::start_modified ? modified_ : upids_;
    c = ListCursor{true, false, l, std::nullopt};
    return finish(id_value(sub, st::ok, upid, 0), 0, now);
  }
  Parameter* p = find(upid);
  if (!p) return finish(id_value(sub, st::unknown_upid, upid, 0), 0, now);
  switch (op) {
    case CfgOp::read_rom:
      return finish(id_value(sub, st::ok, upid, p->rom), 0, now);
    case CfgOp::write_rom: {
      const std::uint8_t state = write_value(*p, false, true, get_u32le(t.data, 2));
      return finish(id_value(sub, state, upid, p->rom), 0, now);
    }
    case CfgOp::get_type:
      return finish(id_value(sub, st::ok, upid, p->type), 0, now);
    case CfgOp::get_min:
      return finish(id_value(sub, st::ok, upid, p->min), 0, now);
    case CfgOp::get_max:
      return finish(id_value(sub, st::ok, upid, p->max), 0, now);
    case CfgOp::get_default:
      return finish(id_value(sub, st::ok, upid, p->def), 0, now);
    case CfgOp::address_usage:  // LinRS 3V27 p27: the usage in the value's low word
      if (!o.address_usage_request) break;
      return finish(id_value(sub, st::ok, upid, p->address_usage), 0, now);
    default:  // lists and layer defaults: handled above
      break;
  }
  return error_answer(st::bad_sub_id, now);
}

// ---- program handling (§13) --------------------------------------------------

void Drive::reset(std::int64_t now_ns, bool make_busy) {
  const bool reload = s_.options.reload_tables_on_start;
  s_.options.reload_tables_on_start = true;  // a reset always reloads RAM from flash
  load_ram_from_rom();
  s_.options.reload_tables_on_start = reload;
  s_.mc_running = true;
  apply_comm_parameters();
  if (s_.options.silent_after_reset) silenced_ = true;
  xfer_ = {};
  modified_ = {};
  upids_ = {};
  decoder_.reset();
  decoder_.set_checksum(s_.checksum);
  window_.clear();
  ++stats_.resets;
  if (make_busy) busy_until_ns_ = std::max(busy_until_ns_, now_ns + s_.timing.reset_us * 1000);
}

std::optional<Answer> Drive::on_program(const Telegram& t, std::int64_t now) {
  switch (static_cast<ProgramOp>(t.sub)) {
    case ProgramOp::reset_after_completion:
      reset(now, false);
      return finish(codec::make_program_response(s_.macid, st::ok), s_.timing.reset_us, now);
    case ProgramOp::reset_immediate: {  // deaf until the reboot completes
      reset(now, false);
      auto a = finish(default_response(st::ok), 0, now);
      busy_until_ns_ = std::max(busy_until_ns_, now + s_.timing.reset_us * 1000);
      return a;
    }
    case ProgramOp::stop_mc:
      s_.mc_running = false;
      return finish(default_response(st::ok), 0, now);
    case ProgramOp::start_after_completion:
      load_ram_from_rom();
      s_.mc_running = true;
      return finish(codec::make_program_response(s_.macid, st::ok), s_.timing.start_us, now);
    case ProgramOp::start_immediate: {
      load_ram_from_rom();
      s_.mc_running = true;
      auto a = finish(default_response(st::ok), 0, now);
      busy_until_ns_ = std::max(busy_until_ns_, now + s_.timing.start_us * 1000);
      return a;
    }
    default:
      return error_answer(st::bad_sub_id, now);
  }
}

// ---- error info (§14) --------------------------------------------------------

std::optional<Answer> Drive::on_error_info(const Telegram& t, std::int64_t now) {
  auto text_of = [&](std::uint16_t code) {
    auto it = s_.error_texts.find(code);
    return it == s_.error_texts.end() ? std::string() : it->second;
  };
  switch (static_cast<ErrorInfoOp>(t.sub)) {
    case ErrorInfoOp::actual_text:
      return finish(
          codec::make_error_text_response(s_.macid, std::nullopt, text_of(s_.live.error_code)), 0,
          now);
    case ErrorInfoOp::text_of_code: {
      const std::uint16_t code = get_u16le(t.data, 0);
      return finish(codec::make_error_text_response(s_.macid, code, text_of(code)), 0, now);
    }
    case ErrorInfoOp::counters:
      return finish(
          codec::make_error_counters_response(
              s_.macid,
              {static_cast<std::uint16_t>(std::min<std::size_t>(s_.error_log.size(), 0xFFFF)),
               s_.errors_occurred}),
          0, now);
    case ErrorInfoOp::log_entry: {
      const std::uint16_t n = get_u16le(t.data, 0);
      codec::ErrorLogEntry e{};
      if (n < s_.error_log.size()) e = s_.error_log[n];
      return finish(codec::make_error_log_entry_response(s_.macid, e), 0, now);
    }
    default:
      return error_answer(st::bad_sub_id, now);
  }
}

}  // namespace lmcfg::sim
