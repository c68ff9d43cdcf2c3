#pragma once
// Typed LinRS messages for every message group of LinRS §5-14.
// Requests are built as Telegrams; responses are decoded from Telegrams.
#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "codec/frame.hpp"

namespace lmcfg::codec {

enum class Main : std::uint8_t {
  response = 0x00,        // §6
  control_word = 0x01,    // §7
  motion_command = 0x02,  // §8
  parameter = 0x03,       // §9
  curve = 0x04,           // §11
  param_config = 0x05,    // §10
  program = 0x06,         // §13
  error_info = 0x07,      // §14
  command_table = 0x08,   // §12
};

// Communication state byte, first byte of a response's data (§16.1, §10.2, §11).
namespace state {
inline constexpr std::uint8_t ok = 0x00;
inline constexpr std::uint8_t more_data = 0x04;  // block transfer: more follows
inline constexpr std::uint8_t last_in_list = 0xC6;
inline constexpr std::uint8_t checksum_error = 0xC1;
inline constexpr std::uint8_t end_missing = 0xC2;
inline constexpr std::uint8_t bad_main_id = 0xC3;
inline constexpr std::uint8_t bad_sub_id = 0xC4;
inline constexpr std::uint8_t bad_baud_s1 = 0xC5;
inline constexpr std::uint8_t unknown_upid = 0xC8;
inline constexpr std::uint8_t wrong_type = 0xC9;
bool is_error(std::uint8_t s);
std::string describe(std::uint8_t s);
}  // namespace state

// ---- Requests -------------------------------------------------------------

// §6: 01 default response, 02 + status word, 03 + warn word, 04 + state var.
enum class ResponseRequest : std::uint8_t {
  default_response = 1,
  status_word = 2,
  warn_word = 3,
  state_var = 4
};
Telegram make_response_request(std::uint8_t id, ResponseRequest kind);
// §7
Telegram make_write_control_word(std::uint8_t id, std::uint16_t control_word);
// §8: header then parameters as raw bytes (MC SW §4.3 layouts).
Telegram make_motion_command(std::uint8_t id, std::uint16_t header, ByteView parameters);

// §9 parameter group (main 03), answered with the default response (+4 value bytes on reads).
enum class ParamOp : std::uint8_t {
  read_ram = 0x00,
  write_ram = 0x01,
  read_rom = 0x02,
  write_rom = 0x03,
  write_ram_rom = 0x04,
  get_min = 0x05,
  get_max = 0x06,
  get_default = 0x07,
};
Telegram make_param_read(std::uint8_t id, ParamOp op, std::uint16_t upid);
Telegram make_param_write(std::uint8_t id, ParamOp op, std::uint16_t upid, std::uint32_t value);
// §9 subs 11h-14h: set layer (1 OS .. 4 Appl) ROM values to default.
Telegram make_param_default_layer(std::uint8_t id, int layer);

// §10 parameter configuration group (main 05), answered with sub 50h + request sub.
enum class CfgOp : std::uint8_t {
  read_rom = 0x00,
  write_rom = 0x01,
  // Not in seed 003 §10: LinRS 3V27 p27 "read a parameter's address usage";
  // answered 53h with state, UPID and a 4-byte value whose low word is the
  // address usage. A drive of the seed's generation may not know it.
  address_usage = 0x03,
  get_type = 0x04,
  get_min = 0x05,
  get_max = 0x06,
  get_default = 0x07,
  start_modified = 0x08,
  next_modified = 0x09,
  start_upid_list = 0x0A,
  next_upid = 0x0B,
  default_os = 0x0C,
  default_mc = 0x0D,
  default_intf = 0x0E,
  default_appl = 0x0F,
};
Telegram make_cfg(std::uint8_t id, CfgOp op, std::uint16_t upid);
Telegram make_cfg_write(std::uint8_t id, std::uint16_t upid, std::uint32_t value);
// §10.4 example sends UPID 0000 with the defaulting request.
Telegram make_cfg_default_layer(std::uint8_t id, int layer);

// §11 curves (main 04), answered with sub 40h.
enum class CurveOp : std::uint8_t {
  save_to_flash = 0x00,
  delete_all = 0x01,
  delete_one = 0x02,
  add = 0x04,
  write_info = 0x05,
  write_data = 0x06,
  read_sizes = 0x08,
  read_info = 0x09,
  read_data = 0x0A,
};
Telegram make_curve(std::uint8_t id, CurveOp op);                       // 00, 01
Telegram make_curve(std::uint8_t id, CurveOp op, std::uint16_t curve);  // 02, 08, 09, 0A
Telegram make_curve_add(std::uint8_t id, std::uint16_t curve, std::uint16_t info_size,
                        std::uint16_t data_size);
// 05/06: four bytes of block data per telegram (the last one padded with 00).
Telegram make_curve_write(std::uint8_t id, CurveOp op, std::uint16_t curve,
                          std::array<std::uint8_t, 4> chunk);

// §12 command table (main 08), answered with sub 80h + request sub.
enum class CtOp : std::uint8_t {
  save_to_flash = 0x00,
  delete_all = 0x01,
  delete_one = 0x02,
  setup_write = 0x03,
  write_data = 0x04,
  setup_read = 0x05,
  read_data = 0x06,
  defined_list = 0x07,
};
Telegram make_ct(std::uint8_t id, CtOp op);                       // 00, 01
Telegram make_ct(std::uint8_t id, CtOp op, std::uint16_t entry);  // 02, 05, 06
Telegram make_ct_setup_write(std::uint8_t id, std::uint16_t entry, std::uint32_t size);
Telegram make_ct_write(std::uint8_t id, std::uint16_t entry, std::array<std::uint8_t, 4> chunk);
// 07: block 0..7 (32 entries each). The §12 example pads with 4 dummy bytes (LEN 09);
// the table says LEN 05 (a seed erratum). pad=true reproduces the example.
Telegram make_ct_defined_list(std::uint8_t id, std::uint16_t block, bool pad = true);

// §13 program handling (main 06).
enum class ProgramOp : std::uint8_t {
  reset_after_completion = 0x01,
  reset_immediate = 0x02,
  stop_mc = 0x03,
  start_after_completion = 0x04,
  start_immediate = 0x05,
};
Telegram make_program(std::uint8_t id, ProgramOp op);

// §14 error info (main 07).
Telegram make_error_actual_text(std::uint8_t id);
Telegram make_error_text(std::uint8_t id, std::uint16_t code);
Telegram make_error_counters(std::uint8_t id);
Telegram make_error_log_entry(std::uint8_t id, std::uint16_t entry);

// ---- Responses ------------------------------------------------------------

// Default response layout (§6.1.1.1, §15 "MC Response Configuration"). Factory:
// comm state, status word, state var, monitoring channel 1 (LEN 0Ch), as every
// §6-9 capture shows (§15 lists State Var as "Default Off": the captures win).
struct DefaultResponseLayout {
  bool comm_state = true;
  bool status_word = true;
  bool state_var = true;
  bool error_code = false;
  bool warn_word = false;
  bool echo_header = false;
  bool monitoring_1 = true;
  bool monitoring_2 = false;
  bool mc_response = false;  // 4-byte placeholder for the response-request / read value

  std::size_t size() const;  // bytes after SUB MAIN
  friend bool operator==(const DefaultResponseLayout&, const DefaultResponseLayout&) = default;
};

// The layout of `data_len` bytes (after SUB MAIN) closest to `configured`:
// fewest items switched on or off, ties broken towards keeping the earlier
// items of the §6.1.1.1 order; mc_response stays as configured. The manual makes the content
// configurable; the length of an answer is all a master sees of it. nullopt above 27 bytes.
std::optional<DefaultResponseLayout> layout_for_length(std::size_t data_len,
                                                       const DefaultResponseLayout& configured);
// "comm_state,status_word,state_var,monitoring_1" (the §6.1.1.1 item names,
// in that order) and back; "factory" parses to the factory layout.
std::string layout_items(const DefaultResponseLayout& l);
std::optional<DefaultResponseLayout> parse_layout_items(std::string_view text);

struct DefaultResponse {
  std::uint8_t id = 0;
  std::optional<std::uint8_t> comm_state;
  std::optional<std::uint16_t> status_word;
  std::optional<std::uint16_t> state_var;
  std::optional<std::uint16_t> error_code;
  std::optional<std::uint16_t> warn_word;
  std::optional<std::uint16_t> echo_header;
  std::optional<std::uint32_t> monitoring_1;
  std::optional<std::uint32_t> monitoring_2;
  // The 4-byte value of a read (§9.1) or response request 02-04 (§6.1.3): the
  // "MC Response" placeholder when configured, else appended after the layout.
  std::optional<std::uint32_t> value;
};
Result<DefaultResponse> decode_default_response(const Telegram& t,
                                                const DefaultResponseLayout& layout = {});
Telegram make_default_response(std::uint8_t id, const DefaultResponse& r,
                               const DefaultResponseLayout& layout = {});

// Responses of main 04, 05, 07, 08 share "sub, state, 2-byte id, 4 bytes".
struct IdValueResponse {
  std::uint8_t id = 0;
  std::uint8_t sub = 0;  // e.g. 50h+op, 40h, 80h+op
  std::uint8_t state = 0;
  std::uint16_t key = 0;    // UPID, curve ID or CT entry
  std::uint32_t value = 0;  // value / 4 data bytes, little-endian
  std::array<std::uint8_t, 4> raw() const;
};
// expected_sub: the answer's sub ID. Fails with unexpected_response on wrong main/sub
// or a body that is not 7 bytes; with drive_refused on an error state.
Result<IdValueResponse> decode_id_value(const Telegram& t, std::uint8_t expected_sub);
Telegram make_id_value(std::uint8_t id, std::uint8_t sub, std::uint8_t state, std::uint16_t key,
                       std::uint32_t value);

// 5Bh: UPID list entry (§10.3): state, UPID, address usage, type.
struct UpidListEntry {
  std::uint8_t state = 0;
  std::uint16_t upid = 0;
  std::uint16_t address_usage = 0;
  std::uint16_t type = 0;
};
Result<UpidListEntry> decode_upid_list_entry(const Telegram& t);

// 60h program handling response (§13.1, §13.4).
Result<std::uint8_t> decode_program_response(const Telegram& t);
Telegram make_program_response(std::uint8_t id, std::uint8_t state);

// 70h/71h error text (§14.1-14.2): 32 characters, NUL padded.
struct ErrorTextResponse {
  std::uint8_t state = 0;
  std::optional<std::uint16_t> code;  // present in 71h
  std::string text;
};
Result<ErrorTextResponse> decode_error_text(const Telegram& t);
Telegram make_error_text_response(std::uint8_t id, std::optional<std::uint16_t> code,
                                  std::string_view text);

// 72h (§14.3).
struct ErrorCounters {
  std::uint16_t logged = 0;
  std::uint16_t occurred = 0;
};
Result<ErrorCounters> decode_error_counters(const Telegram& t);
Telegram make_error_counters_response(std::uint8_t id, ErrorCounters c);

// 73h (§14.4).
struct ErrorLogEntry {
  std::uint16_t code = 0;
  std::uint32_t millis = 0;
  std::uint32_t hours = 0;
};
Result<ErrorLogEntry> decode_error_log_entry(const Telegram& t);
Telegram make_error_log_entry_response(std::uint8_t id, ErrorLogEntry e);

// A drive that refuses answers with the default response carrying an error
// comm state, or with the group's response carrying it. Returns the state
// byte if `t` is a response whose first data byte is an error state.
std::optional<std::uint8_t> error_state_of(const Telegram& t);

// Human-readable one-line description of any telegram, for traces.
std::string describe(const Telegram& t);

}  // namespace lmcfg::codec
