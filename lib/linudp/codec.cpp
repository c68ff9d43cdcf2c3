#include "linudp/codec.hpp"

#include <algorithm>

namespace lmcfg::linudp {

const char* status_text(std::uint8_t code) noexcept {
  // LinUDP V2 p14 (where the LinUDP DLL manual's decimal column is off by one for
  // C5h/C6h, the hex codes win).
  switch (code) {
    case status::ok:
      return "OK, done";
    case status::running:
      return "command running";
    case status::block_more:
      return "block not finished";
    case status::busy:
      return "busy";
    case status::upid_error:
      return "UPID error";
    case status::type_error:
      return "parameter type error";
    case status::range_error:
      return "range error";
    case status::address_usage_error:
      return "address usage error";
    case status::next_without_start:
      return "get next without a prior start";
    case status::end_of_list:
      return "end of UPID list";
    case status::odd_address:
      return "odd address";
    case status::size_error:
      return "size error";
    case status::curve_presence:
      return "curve already defined or not present";
    default:
      return nullptr;
  }
}

namespace {
struct CmdRow {
  Cmd id;
  const char* name;
};
// LinUDP V2 p13-p19, the names of its tables.
constexpr CmdRow kCmdNames[] = {
    {Cmd::nop, "no operation"},
    {Cmd::read_rom, "read ROM value"},
    {Cmd::read_ram, "read RAM value"},
    {Cmd::write_rom, "write ROM value"},
    {Cmd::write_ram, "write RAM value"},
    {Cmd::write_ram_rom, "write RAM and ROM"},
    {Cmd::get_min, "get minimum"},
    {Cmd::get_max, "get maximum"},
    {Cmd::get_default, "get default"},
    {Cmd::upid_list_start, "start UPID list"},
    {Cmd::upid_list_next, "next UPID list item"},
    {Cmd::modified_start, "start modified-UPID list"},
    {Cmd::modified_next, "next modified item"},
    {Cmd::restart, "restart drive"},
    {Cmd::default_os, "default OS ROM"},
    {Cmd::default_mc, "default MC ROM"},
    {Cmd::default_intf, "default interface ROM"},
    {Cmd::default_appl, "default application ROM"},
    {Cmd::stop_mc, "stop MC"},
    {Cmd::start_mc, "start MC"},
    {Cmd::curves_save, "save curves to flash"},
    {Cmd::curves_delete_all, "delete all curves"},
    {Cmd::curve_add_start, "start adding a curve"},
    {Cmd::curve_add_info, "add curve info data"},
    {Cmd::curve_add_data, "add curve data"},
    {Cmd::curve_get_start, "start getting a curve"},
    {Cmd::curve_get_info, "get curve info data"},
    {Cmd::curve_get_data, "get curve data"},
    {Cmd::errlog_counts, "error log counts"},
    {Cmd::errlog_code, "error log entry code"},
    {Cmd::errlog_time_low, "error log entry time (ms)"},
    {Cmd::errlog_time_high, "error log entry time (hours)"},
    {Cmd::error_text, "error text"},
    {Cmd::ct_save, "save command table to flash"},
    {Cmd::ct_delete_all, "delete all command table entries"},
    {Cmd::ct_delete, "delete command table entry"},
    {Cmd::ct_write_start, "write command table entry"},
    {Cmd::ct_write_data, "write command table entry data"},
    {Cmd::ct_get_start, "get command table entry"},
    {Cmd::ct_get_data, "get command table entry data"},
};
}  // namespace

std::string cmd_name(std::uint8_t id) {
  const char* n = id >= 0x87 && id <= 0x8E ? "command table presence list" : "command";
  for (const auto& r : kCmdNames)
    if (static_cast<std::uint8_t>(r.id) == id) n = r.name;
  return std::string(n) + " (" + hex(id, 2, "h") + ")";
}

bool is_write_command(std::uint8_t id) noexcept {
  switch (static_cast<Cmd>(id)) {
    case Cmd::write_rom:
    case Cmd::write_ram:
    case Cmd::write_ram_rom:
    case Cmd::restart:
    case Cmd::default_os:
    case Cmd::default_mc:
    case Cmd::default_intf:
    case Cmd::default_appl:
    case Cmd::stop_mc:
    case Cmd::start_mc:
    case Cmd::curves_save:
    case Cmd::curves_delete_all:
    case Cmd::curve_add_start:
    case Cmd::curve_add_info:
    case Cmd::curve_add_data:
    case Cmd::ct_save:
    case Cmd::ct_delete_all:
    case Cmd::ct_delete:
    case Cmd::ct_write_start:
    case Cmd::ct_write_data:
      return true;
    default:
      return false;
  }
}

namespace {
void put_rtc(Bytes& out, const RtcBlock& r) {
  out.push_back(static_cast<std::uint8_t>(r.count & 0x0F));  // bits 4-7 reserved: 0 (LinUDP V2 §7)
  out.push_back(r.id);
  put_u16le(out, r.w2);
  put_u16le(out, r.w3);
  put_u16le(out, r.w4);
}
RtcBlock get_rtc(ByteView b, std::size_t off) {
  RtcBlock r;
  r.count = static_cast<std::uint8_t>(b[off] & 0x0F);
  r.id = b[off + 1];
  r.w2 = get_u16le(b, off + 2);
  r.w3 = get_u16le(b, off + 4);
  r.w4 = get_u16le(b, off + 6);
  return r;
}
Error short_datagram(const char* what, std::size_t need, std::size_t have) {
  return Error(Errc::frame_short, std::string("LinUDP datagram of ") + std::to_string(have) +
                                      " bytes ends before its " + what + " (needs " +
                                      std::to_string(need) + " bytes, LinUDP V2 §4.4)");
}
}  // namespace

Bytes encode_request(const RtcBlock& rtc, std::uint32_t response_def) {
  Bytes out;
  out.reserve(16);
  put_u32le(out, req::rtc);
  put_u32le(out, response_def);
  put_rtc(out, rtc);
  return out;
}

Result<Request> decode_request(ByteView b) {
  if (b.size() < 8) return short_datagram("header", 8, b.size());
  Request r;
  r.request_def = get_u32le(b, 0);
  r.response_def = get_u32le(b, 4);
  std::size_t off = 8;
  if (r.request_def & req::control_word) {
    if (b.size() < off + 2) return short_datagram("control word", off + 2, b.size());
    r.control_word = get_u16le(b, off);
    off += 2;
  }
  if (r.request_def & req::mc_interface) {
    if (b.size() < off + 32) return short_datagram("MC command part", off + 32, b.size());
    r.has_mc = true;
    off += 32;
  }
  if (r.request_def & req::rtc) {
    if (b.size() < off + 8) return short_datagram("RTC part", off + 8, b.size());
    r.rtc = get_rtc(b, off);
  }
  return r;
}

Result<Response> decode_response(ByteView b) {
  if (b.size() < 8) return short_datagram("header", 8, b.size());
  Response r;
  r.all_zero = std::all_of(b.begin(), b.end(), [](std::uint8_t x) { return x == 0; });
  r.request_def = get_u32le(b, 0);
  r.response_def = get_u32le(b, 4);
  std::size_t off = 8;
  auto need = [&](std::size_t n, const char* what) -> Result<void> {
    if (b.size() < off + n) return short_datagram(what, off + n, b.size());
    return {};
  };
  const std::uint32_t d = r.response_def;
  if (d & resp::status_word) {
    LMCFG_TRY(need(2, "status word"));
    r.status_word = get_u16le(b, off);
    off += 2;
  }
  if (d & resp::state_var) {
    LMCFG_TRY(need(2, "state var"));
    r.state_var = get_u16le(b, off);
    off += 2;
  }
  if (d & resp::actual_pos) {
    LMCFG_TRY(need(4, "actual position"));
    r.actual_pos = static_cast<std::int32_t>(get_u32le(b, off));
    off += 4;
  }
  if (d & resp::demand_pos) {
    LMCFG_TRY(need(4, "demand position"));
    r.demand_pos = static_cast<std::int32_t>(get_u32le(b, off));
    off += 4;
  }
  if (d & resp::current) {
    LMCFG_TRY(need(2, "current"));
    r.current = static_cast<std::int16_t>(get_u16le(b, off));
    off += 2;
  }
  if (d & resp::warn_word) {
    LMCFG_TRY(need(2, "warn word"));
    r.warn_word = get_u16le(b, off);
    off += 2;
  }
  if (d & resp::error_code) {
    LMCFG_TRY(need(2, "error code"));
    r.error_code = get_u16le(b, off);
    off += 2;
  }
  if (d & resp::monitoring) {
    LMCFG_TRY(need(16, "monitoring channels"));
    std::array<std::uint32_t, 4> m{};
    for (std::size_t i = 0; i < 4; ++i) m[i] = get_u32le(b, off + 4 * i);
    r.monitoring = m;
    off += 16;
  }
  // LinUDP V2 §4.4.2: present only when request bit 2 and response bit 8.
  if ((d & resp::rtc) && (r.request_def & req::rtc)) {
    LMCFG_TRY(need(8, "RTC reply"));
    r.rtc = get_rtc(b, off);
  }
  return r;
}

Bytes encode_response(const Response& r) {
  Bytes out;
  out.reserve(kPaddedSize);
  put_u32le(out, r.request_def);
  put_u32le(out, r.response_def);
  const std::uint32_t d = r.response_def;
  if (d & resp::status_word) put_u16le(out, r.status_word.value_or(0));
  if (d & resp::state_var) put_u16le(out, r.state_var.value_or(0));
  if (d & resp::actual_pos) put_u32le(out, static_cast<std::uint32_t>(r.actual_pos.value_or(0)));
  if (d & resp::demand_pos) put_u32le(out, static_cast<std::uint32_t>(r.demand_pos.value_or(0)));
  if (d & resp::current)
    put_u16le(out, static_cast<std::uint16_t>(r.current.value_or(std::int16_t{0})));
  if (d & resp::warn_word) put_u16le(out, r.warn_word.value_or(0));
  if (d & resp::error_code) put_u16le(out, r.error_code.value_or(0));
  if (d & resp::monitoring) {
    const auto m = r.monitoring.value_or(std::array<std::uint32_t, 4>{});
    for (auto v : m) put_u32le(out, v);
  }
  if ((d & resp::rtc) && (r.request_def & req::rtc)) put_rtc(out, r.rtc.value_or(RtcBlock{}));
  if (out.size() < kPaddedSize) out.resize(kPaddedSize, 0);  // LinUDP V2 §4.4.2 padding
  return out;
}

std::uint8_t Counter::next(std::optional<std::uint8_t> avoid) {
  auto step = [](std::uint8_t c) {
    return static_cast<std::uint8_t>(c >= kLast || c < kFirst ? kFirst : c + 1);
  };
  std::uint8_t c = step(last_.value_or(kLast));
  if (avoid && c == (*avoid & 0x0F)) c = step(c);
  last_ = c;
  return c;
}

std::uint16_t layer_start(int layer) {
  // LinRS §10.2, §10.4 (the layers of LinUDP V2's 31h-34h): OS 0000h, MC 1000h, Intf 2000h,
  // Appl 3000h.
  return static_cast<std::uint16_t>((layer - 1) * 0x1000);
}

}  // namespace lmcfg::linudp
