#pragma once
// LinUDP V2 framing of the configuration (RTC) channel, pure: telegram bytes
// in and out, no socket, no clock. Every layout is cited to its source by
// short name and section (docs/references.md: LinUDP V2, LinUDP DLL, C1250 notes).
//
// The only request this codec builds carries the RTC part alone (request
// definition 0x00000004) with the response definition 0x1FF (our reading of
// LinUDP V2 §4.4 and the C1250 notes): never the control word (bit 0) nor the MC command
// interface (bit 1), so nothing it encodes can move an axis.
#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "common/bytes.hpp"
#include "common/result.hpp"

namespace lmcfg::linudp {

// LinUDP V2 §4.3: drive port 49360 (0xC0D0), master port 41136 (0xA0B0).
inline constexpr std::uint16_t kDrivePort = 49360;
inline constexpr std::uint16_t kMasterPort = 41136;

// LinUDP V2 §4.4.1 request-definition bits, §4.4.2 response-definition bits.
namespace req {
inline constexpr std::uint32_t control_word = 0x1;  // never sent by lmcfg
inline constexpr std::uint32_t mc_interface = 0x2;  // never sent by lmcfg
inline constexpr std::uint32_t rtc = 0x4;
}  // namespace req
namespace resp {
inline constexpr std::uint32_t status_word = 0x001;
inline constexpr std::uint32_t state_var = 0x002;
inline constexpr std::uint32_t actual_pos = 0x004;
inline constexpr std::uint32_t demand_pos = 0x008;
inline constexpr std::uint32_t current = 0x010;
inline constexpr std::uint32_t warn_word = 0x020;
inline constexpr std::uint32_t error_code = 0x040;
inline constexpr std::uint32_t monitoring = 0x080;
inline constexpr std::uint32_t rtc = 0x100;
inline constexpr std::uint32_t all = 0x1FF;  // C1250 notes, LinUDP DLL: proven on hardware
}  // namespace resp

// LinUDP V2 §4.4.2: a response shorter than 64 bytes is zero-padded to 64.
inline constexpr std::size_t kPaddedSize = 64;

// LinUDP V2 p14: parameter status codes (byte 1 of the RTC reply).
namespace status {
inline constexpr std::uint8_t ok = 0x00;
inline constexpr std::uint8_t running = 0x02;
inline constexpr std::uint8_t block_more = 0x04;
inline constexpr std::uint8_t busy = 0x05;
inline constexpr std::uint8_t upid_error = 0xC0;
inline constexpr std::uint8_t type_error = 0xC1;
inline constexpr std::uint8_t range_error = 0xC2;
inline constexpr std::uint8_t address_usage_error = 0xC3;
inline constexpr std::uint8_t next_without_start = 0xC5;
inline constexpr std::uint8_t end_of_list = 0xC6;
inline constexpr std::uint8_t odd_address = 0xD0;
inline constexpr std::uint8_t size_error = 0xD1;
inline constexpr std::uint8_t curve_presence = 0xD4;
}  // namespace status
// The meaning of a status code (LinUDP V2 p14), or nullptr for one the table lacks.
const char* status_text(std::uint8_t code) noexcept;
// 02h and 05h: the command still runs (LinUDP V2 §7, p14).
constexpr bool is_busy(std::uint8_t code) {
  return code == status::running || code == status::busy;
}

// LinUDP V2 p13-p19: the command IDs lmcfg sends (configuration channel only).
enum class Cmd : std::uint8_t {
  nop = 0x00,
  read_rom = 0x10,
  read_ram = 0x11,
  write_rom = 0x12,
  write_ram = 0x13,
  write_ram_rom = 0x14,
  get_min = 0x15,
  get_max = 0x16,
  get_default = 0x17,
  upid_list_start = 0x20,
  upid_list_next = 0x21,
  modified_start = 0x22,
  modified_next = 0x23,
  restart = 0x30,
  default_os = 0x31,  // 31h..34h: layers 1..4
  default_mc = 0x32,
  default_intf = 0x33,
  default_appl = 0x34,
  stop_mc = 0x35,
  start_mc = 0x36,
  curves_save = 0x40,
  curves_delete_all = 0x41,
  curve_add_start = 0x50,
  curve_add_info = 0x51,
  curve_add_data = 0x52,
  curve_get_start = 0x60,
  curve_get_info = 0x61,
  curve_get_data = 0x62,
  errlog_counts = 0x70,
  errlog_code = 0x71,
  errlog_time_low = 0x72,
  errlog_time_high = 0x73,
  error_text = 0x74,
  ct_save = 0x80,
  ct_delete_all = 0x81,
  ct_delete = 0x82,
  ct_write_start = 0x83,
  ct_write_data = 0x84,
  ct_get_start = 0x85,
  ct_get_data = 0x86,
  ct_presence_0 = 0x87,  // 87h..8Eh: entries 32k..32k+31
};
// "read ROM value (10h)" for messages.
std::string cmd_name(std::uint8_t id);
// Commands that change what the drive holds (everything but reads, lists, NOP).
bool is_write_command(std::uint8_t id) noexcept;

// LinUDP V2 §7: the 8-byte RTC block, same layout both ways.
struct RtcBlock {
  std::uint8_t count = 0;  // low nibble (bits 4-7 reserved, sent 0)
  std::uint8_t id = 0;     // command ID (request) / parameter status (reply)
  std::uint16_t w2 = 0;
  std::uint16_t w3 = 0;
  std::uint16_t w4 = 0;
  // w3 low, w4 high: a little-endian int32 at block bytes 4-7 (LinUDP V2 §7).
  std::uint32_t value() const { return std::uint32_t{w3} | (std::uint32_t{w4} << 16); }
  void set_value(std::uint32_t v) {
    w3 = static_cast<std::uint16_t>(v & 0xFFFF);
    w4 = static_cast<std::uint16_t>(v >> 16);
  }
  friend bool operator==(const RtcBlock&, const RtcBlock&) = default;
};

// The one request lmcfg sends: 16 bytes, reqdef 0x04, respdef 0x1FF, the RTC
// block (as the C1250 notes' client sends every RTC request: 16 bytes).
Bytes encode_request(const RtcBlock& rtc, std::uint32_t response_def = resp::all);

// A request as a drive sees it (LinUDP V2 §4.4.1): the parts its definition selects,
// in ascending bit order. The simulator decodes with this; lmcfg never sends
// bits 0/1, but a drive must still locate the RTC part behind them.
struct Request {
  std::uint32_t request_def = 0;
  std::uint32_t response_def = 0;
  std::optional<std::uint16_t> control_word;
  bool has_mc = false;
  std::optional<RtcBlock> rtc;
};
Result<Request> decode_request(ByteView bytes);

// LinUDP V2 §4.4.2: a response's parts, located from its response-definition bits.
struct Response {
  std::uint32_t request_def = 0;  // echoed (C1250 notes; the manual does not say)
  std::uint32_t response_def = 0;
  std::optional<std::uint16_t> status_word;
  std::optional<std::uint16_t> state_var;
  std::optional<std::int32_t> actual_pos;
  std::optional<std::int32_t> demand_pos;
  std::optional<std::int16_t> current;
  std::optional<std::uint16_t> warn_word;
  std::optional<std::uint16_t> error_code;
  std::optional<std::array<std::uint32_t, 4>> monitoring;
  std::optional<RtcBlock> rtc;
  // Every byte of the datagram is zero (C1250 notes: what a drive held by
  // another master, e.g. LinMot-Talk, sends).
  bool all_zero = false;
};
// Errors (Errc::frame_short / frame_malformed) name what is missing.
Result<Response> decode_response(ByteView bytes);
// The response a drive sends (LinUDP V2 §4.4.2): the parts `response_def` asks
// for (RTC only when the request had bit 2, §4.4.2), padded to 64.
Bytes encode_response(const Response& r);

// LinUDP V2 §7: the command count. The LinUDP DLL cycles 2..15 (0 for restart),
// the C1250 notes' client 1..14; whether the drive accepts 15 or a backward step
// is open in LinUDP V2, so lmcfg uses only the counts both clients send: 2..14,
// always forward, never the count the drive echoed last.
class Counter {
 public:
  static constexpr std::uint8_t kFirst = 2;
  static constexpr std::uint8_t kLast = 14;
  // The count for the next command: the one after the last used, skipping
  // `avoid` (the drive's last echo, when known).
  std::uint8_t next(std::optional<std::uint8_t> avoid = std::nullopt);
  std::optional<std::uint8_t> last() const { return last_; }
  // Continue after `echo` (seeding from the drive's last echo, C1250 notes).
  void seed(std::uint8_t echo) { last_ = static_cast<std::uint8_t>(echo & 0x0F); }

 private:
  std::optional<std::uint8_t> last_;
};

// The per-layer start UPID of the UPID and modified lists (open in LinUDP V2
// whether one list spans the layers; our reading: iterate per layer, LinRS §10.2).
std::uint16_t layer_start(int layer);
// CT presence command for entries 32*k..32*k+31, k = 0..7 (LinUDP V2 p17-p19, 87h-8Eh).
constexpr std::uint8_t ct_presence_cmd(unsigned k) { return static_cast<std::uint8_t>(0x87 + k); }

}  // namespace lmcfg::linudp
