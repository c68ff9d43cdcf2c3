#include "codec/messages.hpp"

#include <cstdio>

#include "common/bytes.hpp"

namespace lmcfg::codec {

namespace state {
bool is_error(std::uint8_t s) { return s >= 0xC1 && s != last_in_list; }
std::string describe(std::uint8_t s) {
  switch (s) {
    case ok:
      return "00h ok";
    case more_data:
      return "04h more block data follows";
    case last_in_list:
      return "C6h last element of the list";
    default:
      return make_comm_state_error(s).message();
  }
}
}  // namespace state

namespace {

Telegram tg(std::uint8_t id, Main m, std::uint8_t sub, Bytes data = {}) {
  return Telegram{id, sub, static_cast<std::uint8_t>(m), std::move(data)};
}
Bytes u16(std::uint16_t v) {
  Bytes b;
  put_u16le(b, v);
  return b;
}
Bytes u16_u32(std::uint16_t a, std::uint32_t v) {
  Bytes b;
  put_u16le(b, a);
  put_u32le(b, v);
  return b;
}
Bytes u16_chunk(std::uint16_t a, const std::array<std::uint8_t, 4>& c) {
  return Bytes{static_cast<std::uint8_t>(a & 0xFF),
               static_cast<std::uint8_t>(a >> 8),
               c[0],
               c[1],
               c[2],
               c[3]};
}

Error unexpected(const Telegram& t, const std::string& expected) {
  char buf[200];
  std::snprintf(
      buf, sizeof buf,
      "unexpected answer main %02Xh sub %02Xh with %u data byte(s) from ID %02Xh; expected %s",
      t.main, t.sub, static_cast<unsigned>(t.data.size()), t.id, expected.c_str());
  return Error(Errc::unexpected_response, buf);
}

Error refused(const Telegram& t, std::uint8_t s) {
  char buf[200];
  std::snprintf(buf, sizeof buf, "drive %02Xh answered sub %02Xh with communication state %s", t.id,
                t.sub, state::describe(s).c_str());
  return Error(make_comm_state_error(s), buf);
}

}  // namespace

Telegram make_response_request(std::uint8_t id, ResponseRequest kind) {
  return tg(id, Main::response, static_cast<std::uint8_t>(kind));
}
Telegram make_write_control_word(std::uint8_t id, std::uint16_t cw) {
  return tg(id, Main::control_word, 0, u16(cw));
}
Telegram make_motion_command(std::uint8_t id, std::uint16_t header, ByteView parameters) {
  Bytes d;
  d.reserve(2 + parameters.size());
  put_u16le(d, header);
  d.insert(d.end(), parameters.begin(), parameters.end());
  return tg(id, Main::motion_command, 0, std::move(d));
}

Telegram make_param_read(std::uint8_t id, ParamOp op, std::uint16_t upid) {
  return tg(id, Main::parameter, static_cast<std::uint8_t>(op), u16(upid));
}
Telegram make_param_write(std::uint8_t id, ParamOp op, std::uint16_t upid, std::uint32_t value) {
  return tg(id, Main::parameter, static_cast<std::uint8_t>(op), u16_u32(upid, value));
}
Telegram make_param_default_layer(std::uint8_t id, int layer) {
  return tg(id, Main::parameter, static_cast<std::uint8_t>(0x10 + layer));
}

Telegram make_cfg(std::uint8_t id, CfgOp op, std::uint16_t upid) {
  return tg(id, Main::param_config, static_cast<std::uint8_t>(op), u16(upid));
}
Telegram make_cfg_write(std::uint8_t id, std::uint16_t upid, std::uint32_t value) {
  return tg(id, Main::param_config, static_cast<std::uint8_t>(CfgOp::write_rom),
            u16_u32(upid, value));
}
Telegram make_cfg_default_layer(std::uint8_t id, int layer) {
  return tg(id, Main::param_config, static_cast<std::uint8_t>(0x0B + layer), u16(0));
}

Telegram make_curve(std::uint8_t id, CurveOp op) {
  return tg(id, Main::curve, static_cast<std::uint8_t>(op));
}
Telegram make_curve(std::uint8_t id, CurveOp op, std::uint16_t curve) {
  return tg(id, Main::curve, static_cast<std::uint8_t>(op), u16(curve));
}
Telegram make_curve_add(std::uint8_t id, std::uint16_t curve, std::uint16_t info_size,
                        std::uint16_t data_size) {
  Bytes d = u16(curve);
  put_u16le(d, info_size);
  put_u16le(d, data_size);
  return tg(id, Main::curve, static_cast<std::uint8_t>(CurveOp::add), std::move(d));
}
Telegram make_curve_write(std::uint8_t id, CurveOp op, std::uint16_t curve,
                          std::array<std::uint8_t, 4> chunk) {
  return tg(id, Main::curve, static_cast<std::uint8_t>(op), u16_chunk(curve, chunk));
}

Telegram make_ct(std::uint8_t id, CtOp op) {
  return tg(id, Main::command_table, static_cast<std::uint8_t>(op));
}
Telegram make_ct(std::uint8_t id, CtOp op, std::uint16_t entry) {
  return tg(id, Main::command_table, static_cast<std::uint8_t>(op), u16(entry));
}
Telegram make_ct_setup_write(std::uint8_t id, std::uint16_t entry, std::uint32_t size) {
  return tg(id, Main::command_table, static_cast<std::uint8_t>(CtOp::setup_write),
            u16_u32(entry, size));
}
Telegram make_ct_write(std::uint8_t id, std::uint16_t entry, std::array<std::uint8_t, 4> chunk) {
  return tg(id, Main::command_table, static_cast<std::uint8_t>(CtOp::write_data),
            u16_chunk(entry, chunk));
}
Telegram make_ct_defined_list(std::uint8_t id, std::uint16_t block, bool pad) {
  return tg(id, Main::command_table, static_cast<std::uint8_t>(CtOp::defined_list),
            pad ? u16_u32(block, 0) : u16(block));
}

Telegram make_program(std::uint8_t id, ProgramOp op) {
  return tg(id, Main::program, static_cast<std::uint8_t>(op));
}

Telegram make_error_actual_text(std::uint8_t id) { return tg(id, Main::error_info, 0x00); }
Telegram make_error_text(std::uint8_t id, std::uint16_t code) {
  return tg(id, Main::error_info, 0x01, u16(code));
}
Telegram make_error_counters(std::uint8_t id) { return tg(id, Main::error_info, 0x02); }
Telegram make_error_log_entry(std::uint8_t id, std::uint16_t entry) {
  return tg(id, Main::error_info, 0x03, u16(entry));
}

// ---- responses ----

std::size_t DefaultResponseLayout::size() const {
  return (comm_state ? 1u : 0u) + (status_word ? 2u : 0u) + (state_var ? 2u : 0u) +
         (error_code ? 2u : 0u) + (warn_word ? 2u : 0u) + (echo_header ? 2u : 0u) +
         (monitoring_1 ? 4u : 0u) + (monitoring_2 ? 4u : 0u) + (mc_response ? 4u : 0u);
}

namespace {
struct LayoutItem {
  const char* name;
  bool DefaultResponseLayout::*field;
};
constexpr LayoutItem kLayoutItems[] = {
    {"comm_state", &DefaultResponseLayout::comm_state},
    {"status_word", &DefaultResponseLayout::status_word},
    {"state_var", &DefaultResponseLayout::state_var},
    {"error_code", &DefaultResponseLayout::error_code},
    {"warn_word", &DefaultResponseLayout::warn_word},
    {"echo_header", &DefaultResponseLayout::echo_header},
    {"monitoring_1", &DefaultResponseLayout::monitoring_1},
    {"monitoring_2", &DefaultResponseLayout::monitoring_2},
    {"mc_response", &DefaultResponseLayout::mc_response},
};
constexpr unsigned kLayoutCount = sizeof kLayoutItems / sizeof kLayoutItems[0];
}  // namespace

std::optional<DefaultResponseLayout> layout_for_length(std::size_t n,
                                                       const DefaultResponseLayout& cfg) {
  std::optional<DefaultResponseLayout> best;
  unsigned best_cost = ~0u;
  for (unsigned bits = 0; bits < (1u << kLayoutCount); ++bits) {
    DefaultResponseLayout l;
    unsigned cost = 0;
    for (unsigned i = 0; i < kLayoutCount; ++i) {
      l.*kLayoutItems[i].field = (bits >> i & 1u) != 0;
      // A change to an earlier item weighs more: ties keep the first items.
      if (l.*kLayoutItems[i].field != cfg.*kLayoutItems[i].field)
        cost += 1024u + (kLayoutCount - i);
    }
    // The MC Response placeholder decides where a read value goes: kept as configured.
    if (l.mc_response != cfg.mc_response) continue;
    if (l.size() == n && cost < best_cost) {
      best = l;
      best_cost = cost;
    }
  }
  return best;
}

std::string layout_items(const DefaultResponseLayout& l) {
  std::string s;
  for (const auto& item : kLayoutItems)
    if (l.*item.field) s += (s.empty() ? "" : ",") + std::string(item.name);
  return s;
}

std::optional<DefaultResponseLayout> parse_layout_items(std::string_view text) {
  if (text == "factory") return DefaultResponseLayout{};
  DefaultResponseLayout l;
  for (const auto& item : kLayoutItems) l.*item.field = false;
  std::size_t pos = 0;
  while (pos <= text.size()) {
    const auto comma = text.find(',', pos);
    const auto word = text.substr(pos, comma == std::string_view::npos ? text.npos : comma - pos);
    bool known = false;
    for (const auto& item : kLayoutItems) {
      if (word == item.name) {
        l.*item.field = true;
        known = true;
      }
    }
    if (!known) return std::nullopt;
    if (comma == std::string_view::npos) break;
    pos = comma + 1;
  }
  return l;
}

Result<DefaultResponse> decode_default_response(const Telegram& t, const DefaultResponseLayout& L) {
  if (t.main != 0x00 || t.sub != 0x00) return unexpected(t, "default response (main 00h sub 00h)");
  const std::size_t base = L.size();
  const bool has_value = !L.mc_response && t.data.size() == base + 4;
  if (t.data.size() != base && !has_value) {
    char buf[120];
    std::snprintf(buf, sizeof buf, "default response of %u data bytes (%u or %u configured)",
                  static_cast<unsigned>(t.data.size()), static_cast<unsigned>(base),
                  static_cast<unsigned>(base + 4));
    return unexpected(t, buf);
  }
  DefaultResponse r;
  r.id = t.id;
  std::size_t o = 0;
  ByteView d(t.data);
  auto take16 = [&](bool on, std::optional<std::uint16_t>& f) {
    if (on) {
      f = get_u16le(d, o);
      o += 2;
    }
  };
  auto take32 = [&](bool on, std::optional<std::uint32_t>& f) {
    if (on) {
      f = get_u32le(d, o);
      o += 4;
    }
  };
  if (L.comm_state) r.comm_state = d[o++];
  take16(L.status_word, r.status_word);
  take16(L.state_var, r.state_var);
  take16(L.error_code, r.error_code);
  take16(L.warn_word, r.warn_word);
  take16(L.echo_header, r.echo_header);
  take32(L.monitoring_1, r.monitoring_1);
  take32(L.monitoring_2, r.monitoring_2);
  take32(L.mc_response || has_value, r.value);
  return r;
}

Telegram make_default_response(std::uint8_t id, const DefaultResponse& r,
                               const DefaultResponseLayout& L) {
  Bytes d;
  if (L.comm_state) d.push_back(r.comm_state.value_or(0));
  if (L.status_word) put_u16le(d, r.status_word.value_or(0));
  if (L.state_var) put_u16le(d, r.state_var.value_or(0));
  if (L.error_code) put_u16le(d, r.error_code.value_or(0));
  if (L.warn_word) put_u16le(d, r.warn_word.value_or(0));
  if (L.echo_header) put_u16le(d, r.echo_header.value_or(0));
  if (L.monitoring_1) put_u32le(d, r.monitoring_1.value_or(0));
  if (L.monitoring_2) put_u32le(d, r.monitoring_2.value_or(0));
  if (L.mc_response || r.value) put_u32le(d, r.value.value_or(0));
  return tg(id, Main::response, 0x00, std::move(d));
}

std::array<std::uint8_t, 4> IdValueResponse::raw() const {
  return {static_cast<std::uint8_t>(value & 0xFF), static_cast<std::uint8_t>((value >> 8) & 0xFF),
          static_cast<std::uint8_t>((value >> 16) & 0xFF), static_cast<std::uint8_t>(value >> 24)};
}

std::optional<std::uint8_t> error_state_of(const Telegram& t) {
  if (t.main != 0x00 || t.data.empty()) return std::nullopt;
  if (state::is_error(t.data[0])) return t.data[0];
  return std::nullopt;
}

Result<IdValueResponse> decode_id_value(const Telegram& t, std::uint8_t expected_sub) {
  if (auto s = error_state_of(t)) return refused(t, *s);
  if (t.main != 0x00 || t.sub != expected_sub || t.data.size() != 7) {
    return unexpected(t, "response sub " + hex(expected_sub, 2, "h") + " with 7 data bytes");
  }
  IdValueResponse r;
  r.id = t.id;
  r.sub = t.sub;
  r.state = t.data[0];
  r.key = get_u16le(t.data, 1);
  r.value = get_u32le(t.data, 3);
  return r;
}

Telegram make_id_value(std::uint8_t id, std::uint8_t sub, std::uint8_t st, std::uint16_t key,
                       std::uint32_t value) {
  Bytes d{st};
  put_u16le(d, key);
  put_u32le(d, value);
  return tg(id, Main::response, sub, std::move(d));
}

Result<UpidListEntry> decode_upid_list_entry(const Telegram& t) {
  if (auto s = error_state_of(t)) return refused(t, *s);
  if (t.main != 0x00 || t.sub != 0x5B || t.data.size() != 7)
    return unexpected(t, "UPID list entry (sub 5Bh)");
  return UpidListEntry{t.data[0], get_u16le(t.data, 1), get_u16le(t.data, 3), get_u16le(t.data, 5)};
}

Result<std::uint8_t> decode_program_response(const Telegram& t) {
  if (auto s = error_state_of(t)) return refused(t, *s);
  if (t.main != 0x00 || t.sub != 0x60 || t.data.size() != 1)
    return unexpected(t, "program handling response (sub 60h)");
  return t.data[0];
}
Telegram make_program_response(std::uint8_t id, std::uint8_t st) {
  return tg(id, Main::response, 0x60, Bytes{st});
}

namespace {
std::string text_of(ByteView b) {
  std::string s;
  for (auto c : b) {
    if (c == 0) break;
    s.push_back(static_cast<char>(c));
  }
  return s;
}
void put_text32(Bytes& d, std::string_view text) {
  for (std::size_t i = 0; i < 32; ++i)
    d.push_back(i < text.size() ? static_cast<std::uint8_t>(text[i]) : 0);
}
}  // namespace

Result<ErrorTextResponse> decode_error_text(const Telegram& t) {
  if (auto s = error_state_of(t)) return refused(t, *s);
  if (t.main == 0x00 && t.sub == 0x70 && t.data.size() == 33) {
    return ErrorTextResponse{t.data[0], std::nullopt, text_of(ByteView(t.data).subspan(1))};
  }
  if (t.main == 0x00 && t.sub == 0x71 && t.data.size() == 35) {
    return ErrorTextResponse{t.data[0], get_u16le(t.data, 1), text_of(ByteView(t.data).subspan(3))};
  }
  return unexpected(t, "error text (sub 70h with 33 or 71h with 35 data bytes)");
}
Telegram make_error_text_response(std::uint8_t id, std::optional<std::uint16_t> code,
                                  std::string_view text) {
  Bytes d{0x00};
  if (code) put_u16le(d, *code);
  put_text32(d, text);
  return tg(id, Main::response, code ? 0x71 : 0x70, std::move(d));
}

Result<ErrorCounters> decode_error_counters(const Telegram& t) {
  if (auto s = error_state_of(t)) return refused(t, *s);
  if (t.main != 0x00 || t.sub != 0x72 || t.data.size() != 5)
    return unexpected(t, "error counters (sub 72h)");
  return ErrorCounters{get_u16le(t.data, 1), get_u16le(t.data, 3)};
}
Telegram make_error_counters_response(std::uint8_t id, ErrorCounters c) {
  Bytes d{0x00};
  put_u16le(d, c.logged);
  put_u16le(d, c.occurred);
  return tg(id, Main::response, 0x72, std::move(d));
}

Result<ErrorLogEntry> decode_error_log_entry(const Telegram& t) {
  if (auto s = error_state_of(t)) return refused(t, *s);
  if (t.main != 0x00 || t.sub != 0x73 || t.data.size() != 11)
    return unexpected(t, "error log entry (sub 73h)");
  return ErrorLogEntry{get_u16le(t.data, 1), get_u32le(t.data, 3), get_u32le(t.data, 7)};
}
Telegram make_error_log_entry_response(std::uint8_t id, ErrorLogEntry e) {
  Bytes d{0x00};
  put_u16le(d, e.code);
  put_u32le(d, e.millis);
  put_u32le(d, e.hours);
  return tg(id, Main::response, 0x73, std::move(d));
}

std::string describe(const Telegram& t) {
  static const char* kGroups[] = {"response",         "control word", "motion command",
                                  "parameter",        "curve",        "parameter configuration",
                                  "program handling", "error info",   "command table"};
  char buf[160];
  const char* g = t.main < 9 ? kGroups[t.main] : "undefined group";
  std::snprintf(buf, sizeof buf, "ID %02Xh %s (main %02Xh sub %02Xh), %u data byte(s)", t.id, g,
                t.main, t.sub, static_cast<unsigned>(t.data.size()));
  std::string s = buf;
  if (t.main == 0 && !t.data.empty()) s += ", state " + state::describe(t.data[0]);
  return s;
}

}  // namespace lmcfg::codec
