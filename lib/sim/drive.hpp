#pragma once
// sim::Drive: a simulated LinMot E1100 drive speaking LinRS (LinRS §6-§16).
// A real peer built on the codec: raw request bytes in (codec::StreamDecoder),
// raw answer bytes out (codec builders + codec::encode). No clock of its own:
// the caller passes the time at which the bytes arrived and gets each answer
// with the delay after which the drive puts it on the line.
// Every choice the manual does not settle is an explicit Options field and is
// listed in docs/simulator.md.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "codec/frame.hpp"
#include "codec/messages.hpp"
#include "common/bytes.hpp"
#include "common/families.hpp"
#include "common/layers.hpp"
#include "common/types.hpp"
#include "transport/transport.hpp"

namespace lmcfg::sim {

// Firmware layers and their UPID ranges (LinRS §10.2): the layer numbers
// of common/layers.hpp as an enum, none = 0 outside every range.
enum class Layer : std::uint8_t {
  none = 0,
  os = layers::kOS,
  mc = layers::kMC,
  intf = layers::kIntf,
  appl = layers::kAppl,
};
Layer layer_of(std::uint16_t upid);
std::uint16_t layer_base(Layer l);  // 0000h, 1000h, 2000h, 3000h
const char* layer_name(Layer l);    // "OS", "MC", "Intf", "Appl", "none"

// Address usage word bits (LinRS §10; "live" is bit 7 or 8, unresolved): resolved bits act.
namespace au {
inline constexpr std::uint16_t ram_read = 0x0001;
inline constexpr std::uint16_t ram_write = 0x0002;
inline constexpr std::uint16_t rom_read = 0x0004;
inline constexpr std::uint16_t rom_write = 0x0008;
inline constexpr std::uint16_t not_for_hash = 0x1000;
inline constexpr std::uint16_t parameter = ram_read | ram_write | rom_read | rom_write;  // 000Fh
}  // namespace au

// One UPID. Values are the raw 4-byte fields of §9 (a word in the two lower bytes...).
struct Parameter {
  std::uint16_t upid = 0;
  std::string name;                                  // informational only, never on the wire
  std::uint16_t type = type_code(TypeCode::UInt16);  // raw: a drive may use codes §10 lacks
  std::uint16_t address_usage = au::parameter;       // raw word, stored as given
  std::uint32_t min = 0;
  std::uint32_t max = 0xFFFFFFFF;
  std::uint32_t def = 0;
  std::uint32_t rom = 0;
  std::uint32_t ram = 0;

  bool has_rom() const { return (address_usage & au::rom_write) != 0; }
  // ROM differs from default on a parameter with ROM write usage (the §10.2 list).
  bool modified() const { return has_rom() && rom != def; }
  friend bool operator==(const Parameter&, const Parameter&) = default;
};

// Value within [min, max], compared as the type's signedness says (SINT types
// sign-extend their low 8/16 bits; STRING-like types are never range-checked).
bool in_range(const Parameter& p, std::uint32_t value);

// A curve as the drive stores it: info block and data block bytes (§11).
struct Curve {
  Bytes info;
  Bytes data;
  friend bool operator==(const Curve&, const Curve&) = default;
};

// Values the drive measures or derives; the simulator cannot know them, so they
// are state (tests set them to reproduce a capture's default response).
struct LiveValues {
  std::uint16_t status_word = 0x4C37;  // as in the §6.1.2 / §9 captures
  std::uint16_t state_var = 0x08C2;
  std::uint16_t warn_word = 0x0080;
  std::uint16_t error_code = 0x0000;  // actual error (§14.1)
  std::uint32_t monitoring_1 = 0;
  std::uint32_t monitoring_2 = 0;
  friend bool operator==(const LiveValues&, const LiveValues&) = default;
};

// Durations in microseconds (LinRS §6.1.1.1, §10.4, §11, §12, §13).
struct Timing {
  std::int64_t turnaround_us = 1'000;           // every answer (§6.1.1.1: 0.5..1.5 ms)
  std::int64_t defaulting_us = 1'200'000;       // defaulting a layer (§10.4 "more than 1 s")
  std::int64_t flash_save_us = 2'000'000;       // curves / CT RAM -> flash
  std::int64_t flash_save_max_us = 10'000'000;  // documented worst case (§11, §12 "timeout 10s")
  std::int64_t reset_us = 3'000'000;            // §13.1 "ca. 3s"
  std::int64_t start_us = 3'000'000;            // §13.4 "ca. 3s"
  std::int64_t rx_timeout_us = 20'000;          // byte-to-byte receive time-out (§15); 0 = off
  friend bool operator==(const Timing&, const Timing&) = default;
};

// What a refusal (an answer with an error state) carries in the fields LinRS
// marks "No meaning" for it (the §11 curve transcripts): the request's key and
// a zero value, zeros in both, or arbitrary bytes.
enum class RefusalFields : std::uint8_t { echo, zeros, arbitrary };

// What to do with a write the parameter's min/max or address usage forbids.
enum class WritePolicy : std::uint8_t {
  reject,  // no change; answer with Options::reject_state (default C9)
  clamp,   // store the value clamped to [min, max] (address usage still enforced)
  accept,  // store whatever comes
};

// The manual's gaps, as options. Defaults are documented in docs/simulator.md.
struct Options {
  // §10.2 empty modified list: the first get-next answers this state/UPID/value 0.
  // Also the answer to get-next after the list has ended and without a start.
  std::uint8_t empty_list_state = codec::state::last_in_list;
  std::uint16_t empty_list_upid = 0xFFFF;
  // §11 read sizes of a missing curve: true = state 00 with sizes 0/0, false = state C8.
  bool missing_curve_zero_sizes = true;
  // RAM/ROM writes out of [min, max] or without the write address-usage bit.
  WritePolicy write_policy = WritePolicy::reject;
  std::uint8_t reject_state = codec::state::wrong_type;  // C9
  // Flash save of curves / CT while MC runs (§11, §12 "MC SW has to be stopped").
  std::uint8_t flash_refused_state = codec::state::bad_sub_id;  // C4
  // ROM writes (§9 write ROM, write RAM+ROM; §10 write ROM) and layer defaulting (§10.4)
  // while MC runs. LinRS §10: "For configuring it is needed to stop the MC-SW
  // of the servo controller first", yet the §9.2 capture writes a ROM value
  // with MC running and gets state 00 ("it is recommended to change the ROM
  // values only in the stopped MC-SW mode"): both readings, accept by default.
  bool refuse_config_while_mc_runs = false;
  std::uint8_t config_refused_state = codec::state::bad_sub_id;  // C4, as flash saves
  // Block transfer to/from a curve or CT entry that does not exist.
  std::uint8_t missing_object_state = codec::state::unknown_upid;  // C8
  // "Respond On Msg With Error" (§15, factory: both on).
  bool respond_on_checksum_error = true;
  bool respond_on_end_missing = true;
  // RAM curves / CT are reloaded from flash at reset and at MC start (like
  // parameter RAM from ROM).
  bool reload_tables_on_start = true;
  // Busy while a delayed answer is pending or rebooting: requests are ignored.
  bool ignore_while_busy = true;
  // Raw values of "Baud Rate Parameter Def" (2012h) -> baud rate. Seed 003 states
  // only 8 = 38400 (§10.2 example); the others are this simulator's assumption
  // (powers of two in the order §15 lists the rates). A code not in the table
  // leaves the drive at its S1 switch rate.
  std::map<std::uint32_t, unsigned> baud_codes = default_baud_codes();
  // Checksum, parity and stop bits at start-up. LinRS §15 names them
  // ("LinRS\Protocol Config\Checksum": None, Add, CRC CCITT; "LinRS\RS
  // Config\Parity": None, Even, Odd; "LinRS\RS Config\Stop Bit": 1, 2) but
  // gives neither their UPIDs nor their raw values, so each is this option:
  // unset (the default), a reset leaves the setting as the state holds it; set,
  // a reset takes the ROM value of `upid` through `codes` (raw value -> the
  // setting as the tools' options spell it: "none", "add", "crc-ffff",
  // "crc-0000", "crc-kermit"; "none", "even", "odd"; "1", "2"). A raw value not
  // in `codes` leaves the setting as it was.
  struct CommParam {
    std::uint16_t upid = 0;
    std::map<std::uint32_t, std::string> codes;
    friend bool operator==(const CommParam&, const CommParam&) = default;
  };
  std::optional<CommParam> checksum_param, parity_param, stop_bits_param;
  // Fault injection: after a reset the drive answers nothing until the
  // simulator is restarted (a drive lost at settings no master tries).
  bool silent_after_reset = false;
  // ---- docs/reliability.md (drive variance) ----
  // §12 setup read (08h 05h) of an entry that does not exist: true = state 00
  // with size 0, false = state `missing_object_state` (C8).
  bool missing_ct_entry_zero_size = true;
  // §10.2 empty modified list: the C6 answer carries the get-next request's
  // UPID field (the layer base the client sends) instead of empty_list_upid.
  bool empty_list_echo_upid = false;
  // The key and value fields of an answer with an error state (C1..C9 but C6).
  RefusalFields refusal_fields = RefusalFields::echo;
  // ---- docs/field.md "Slow saves" ----
  // Flash saves (§11, §12) and layer defaulting (§10.4) are done, the drive
  // is deaf for their duration (Timing::flash_save_us, defaulting_us), and
  // never answers them: "A command table flash save took about 39 s and was
  // never acknowledged" (field reports). Answers late (false, the
  // default) is the other reading: set Timing to 40 s for that.
  bool unanswered_saves = false;
  // The padding bytes of a block read's last chunk (after a 70-byte curve info
  // block: 2 bytes). false = zero (seed 003 §11.1's capture); true = stale
  // data that differs from read to read (EtherCAT curves: real drives leave
  // "not zero (stale data)" there).
  bool stale_block_padding = false;
  // ---- docs/families.md: the drive family this simulator plays ----
  // A name of common/families.hpp ("E1100", "B1100", "C1100", "E1200",
  // "E1400"; unknown names play E1100). B1100: the curve (04h) and command
  // table (08h) groups answer C3h undefined main ID ("not on B1100", 3V27
  // §11-§12), default reads and layer defaulting C4h (DCF p8: no stored
  // defaults). C1100: curve/CT changes act on flash directly and "save to
  // flash" answers 00h at once, doing nothing (3V27 p32).
  std::string family = "E1100";
  // LinRS 3V27 p27: 05h sub 03h, a parameter's address usage, answered 53h.
  // false (the seed's generation): C4h undefined sub ID.
  bool address_usage_request = false;
  friend bool operator==(const Options&, const Options&) = default;

  static std::map<std::uint32_t, unsigned> default_baud_codes() {
    return {{1, 4800}, {2, 9600}, {4, 19200}, {8, 38400}, {16, 57600}, {32, 115200}};
  }
};

// Everything the state file holds (see state_file.hpp, docs/simulator.md).
// What the hex switches S1 (baud rate, §3.2.1) and S2 (ID, §3.2.2) select.
struct HexSwitches {
  std::uint8_t macid = 0x11;
  unsigned baud = 57600;
  friend bool operator==(const HexSwitches&, const HexSwitches&) = default;
};

struct DriveState {
  // The MACID and line settings the drive uses now. A reset recomputes MACID
  // and baud rate from the ROM values of 206Ch/2076h and 200Eh/2012h (source
  // "By Parameter") or else from `switches` (Drive::apply_comm_parameters).
  std::uint8_t macid = 0x11;       // §15 "MACID Parameter Value" default 11h
  transport::SerialSettings link;  // baud / parity / stop bits (device unused)
  // Unset: the switches select what `macid` and `link.baud` hold at load.
  std::optional<HexSwitches> switches;
  codec::ChecksumConfig checksum;
  codec::DefaultResponseLayout layout;
  bool mc_running = true;
  LiveValues live;
  std::map<std::uint16_t, Parameter> params;
  std::map<std::uint16_t, Curve> curves_ram, curves_flash;
  std::map<std::uint16_t, Bytes> ct_ram, ct_flash;   // entry 0..255 -> bytes
  std::vector<codec::ErrorLogEntry> error_log;       // [0] = newest (§14.4)
  std::uint16_t errors_occurred = 0;                 // §14.3 total
  std::map<std::uint16_t, std::string> error_texts;  // code -> short text (§14.1/14.2)
  Timing timing;
  Options options;

  // Adds or replaces a parameter.
  void put(Parameter p) { params[p.upid] = std::move(p); }
};

// Built-in error texts: 0000 "No Error" and the LinRS §14 examples.
std::map<std::uint16_t, std::string> default_error_texts();

struct DriveStats {
  std::uint64_t telegrams_seen = 0;  // complete, valid telegrams for any ID
  std::uint64_t telegrams_for_me = 0;
  std::uint64_t ignored_other_id = 0;
  std::uint64_t ignored_busy = 0;  // arrived while resetting / processing
  std::uint64_t bad_frames = 0;    // framing / checksum errors seen
  std::uint64_t answers = 0;
  std::uint64_t error_answers = 0;  // answers with state C1..C9
  std::uint64_t flash_saves = 0;
  std::uint64_t resets = 0;
};

// One answer: wire bytes and the delay from the end of the request.
struct Answer {
  Bytes bytes;
  std::int64_t delay_ns = 0;
};

class Drive {
 public:
  Drive();
  explicit Drive(DriveState state);

  // Byte front end: feed what arrived on the line at `now_ns` (time of the last
  // byte). Frames for other MACIDs are ignored.
  std::vector<Answer> receive(ByteView bytes, std::int64_t now_ns);
  // On the drive's clock: when it last heard a byte or, if later, when it
  // stops being busy (start, reset, flash save). A server that skips the
  // modelled delays continues a new connection from here.
  std::int64_t idle_at_ns() const { return std::max(last_byte_ns_, busy_until_ns_); }
  // Telegram front end (the byte front end calls this); nullopt = no answer.
  std::optional<Answer> handle(const codec::Telegram& t, std::int64_t now_ns);

  // Power cycle / reset (§13.1): RAM := ROM, tables reloaded, transfers and
  // list cursors forgotten, MC running. With busy, deaf for timing.reset_us.
  void reset(std::int64_t now_ns, bool busy = true);
  // Start-up choice of MACID and baud rate (LinRS §3.2, §15): MACID Source
  // Select 206Ch = 3 "By Parameter" (§10.2 example) takes MACID Parameter Value
  // 2076h, else the switch ID; Baud Rate Source Select 200Eh = 2 "By Parameter"
  // takes Baud Rate Parameter Def 2012h through Options::baud_codes, else the
  // S1 rate. Checksum, parity and stop bits follow Options::checksum_param,
  // parity_param and stop_bits_param where those are set. Called by reset();
  // ROM values, since RAM := ROM at start-up.
  void apply_comm_parameters();
  // The next flash save takes timing.flash_save_max_us (fault injection).
  void make_next_flash_save_slow() { slow_flash_ = true; }
  bool busy(std::int64_t now_ns) const { return now_ns < busy_until_ns_; }

  DriveState& state() { return s_; }
  const DriveState& state() const { return s_; }
  std::uint8_t macid() const { return s_.macid; }
  // Applies a changed checksum configuration to the receiver.
  void sync_checksum() { decoder_.set_checksum(s_.checksum); }
  const DriveStats& stats() const { return stats_; }

  // Convenience for tests and tools.
  Parameter* find(std::uint16_t upid);
  std::optional<std::uint32_t> ram(std::uint16_t upid) const;
  std::optional<std::uint32_t> rom(std::uint16_t upid) const;
  bool transfer_active() const { return xfer_.kind != XferKind::none; }

 private:
  enum class XferKind : std::uint8_t {
    none,
    curve_info_w,
    curve_data_w,
    curve_info_r,
    curve_data_r,
    ct_w,
    ct_r
  };
  struct Transfer {
    XferKind kind = XferKind::none;
    std::uint16_t key = 0;
    std::size_t offset = 0;
  };
  struct ListCursor {
    bool active = false;
    bool ended = false;
    Layer layer = Layer::none;
    std::optional<std::uint16_t> last;  // last UPID answered
  };

  Answer finish(const codec::Telegram& reply, std::int64_t delay_us, std::int64_t now_ns);
  // A save or defaulting that takes `duration_us`: finish(), or with
  // Options::unanswered_saves deaf for that long and no answer.
  std::optional<Answer> finish_long(const codec::Telegram& reply, std::int64_t duration_us,
                                    std::int64_t now_ns);
  codec::Telegram default_response(std::uint8_t comm_state,
                                   std::optional<std::uint32_t> value = {}) const;
  codec::Telegram id_value(std::uint8_t sub, std::uint8_t st, std::uint16_t key,
                           std::uint32_t value) const;
  std::optional<Answer> error_answer(std::uint8_t comm_state, std::int64_t now_ns);

  std::optional<Answer> on_response_request(const codec::Telegram& t, std::int64_t now);
  std::optional<Answer> on_parameter(const codec::Telegram& t, std::int64_t now);
  std::optional<Answer> on_param_config(const codec::Telegram& t, std::int64_t now);
  std::optional<Answer> on_curve(const codec::Telegram& t, std::int64_t now);
  // The curve and CT groups as Options::family keeps them (C1100: on flash).
  std::optional<Answer> on_family_table(const codec::Telegram& t, std::int64_t now);
  // Options::family's row (E1100 for an unknown name).
  const families::Family& family() const;
  std::optional<Answer> on_command_table(const codec::Telegram& t, std::int64_t now);
  std::optional<Answer> on_program(const codec::Telegram& t, std::int64_t now);
  std::optional<Answer> on_error_info(const codec::Telegram& t, std::int64_t now);

  // Options::refuse_config_while_mc_runs and MC running.
  bool refuses_configuration() const;
  // Write with the policy; returns the state (00, reject_state or
  // config_refused_state).
  std::uint8_t write_value(Parameter& p, bool ram, bool rom, std::uint32_t value);
  void default_layer(Layer l);
  void load_ram_from_rom();
  std::int64_t flash_save_duration_us();
  // Block transfer helpers. Return the answer state (04 more / 00 last).
  std::uint8_t block_write(Bytes& target, XferKind kind, std::uint16_t key, ByteView chunk);
  std::uint8_t block_read(const Bytes& source, XferKind kind, std::uint16_t key,
                          std::uint32_t& out);

  DriveState s_;
  codec::StreamDecoder decoder_;
  Bytes window_;  // recent raw bytes, to find the ID of a frame that failed its checksum
  std::int64_t last_byte_ns_ = 0;
  bool have_last_byte_ = false;
  std::int64_t busy_until_ns_ = 0;
  Transfer xfer_;
  ListCursor modified_;
  ListCursor upids_;
  std::uint16_t last_motion_header_ = 0;
  std::uint16_t control_word_ = 0;
  bool slow_flash_ = false;
  std::uint8_t stale_ = 0x5A;  // Options::stale_block_padding: changes with every padded read
  bool silenced_ = false;      // Options::silent_after_reset after a reset
  DriveStats stats_;
};

}  // namespace lmcfg::sim
