#pragma once
// The polled I/O of the DeviceNet LinMot controllers of seed 000 (§5.1 IO
// Data Modules, §5.2 General Purpose Command/Response Modules) as pure code:
// which module sits where in the poll command and response, the Addressed and
// Direct command words, the status words, the coded errors. No CAN, no
// connection handling (that is the master's, above the CAN link).
//
// Byte order: each 16-bit word travels low byte first (DeviceNet's byte order;
// the seed lists words, not bytes).
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/bytes.hpp"
#include "common/result.hpp"

namespace lmcfg::devicenet {

enum class Motor : std::uint8_t { A = 0, B = 1, C = 2, D = 3 };
char motor_letter(Motor m);
inline constexpr Motor kMotors[] = {Motor::A, Motor::B, Motor::C, Motor::D};

// Word 1 of Addressed In/Out and Direct In (§5.1): bits 15..12 select motors
// D, C, B, A (Addressed only), bit 7 is the start-command toggle, bits 6..0
// the command ID (bit 0 = R/W).
struct CommandWord {
  std::array<bool, 4> motors{};  // index Motor
  bool toggle = false;
  std::uint8_t id = 0;  // 0..7Fh (Table 5-1)

  std::uint16_t encode() const;
  static CommandWord decode(std::uint16_t w);
  bool operator==(const CommandWord&) const = default;
};

// Status Out (§5.1): the low word (controller state) and the high word (four
// bits per motor).
struct Status {
  std::uint16_t low = 0, high = 0;
  bool init_done() const { return low & 0x0001; }
  bool run_state() const { return low & 0x0002; }
  bool error_state() const { return low & 0x0004; }
  bool init_state() const { return low & 0x0008; }
  bool disable_state() const { return low & 0x0010; }
  bool emergency_stop() const { return low & 0x0020; }
  bool error_pending() const { return low & 0x0040; }
  bool warning_pending() const { return low & 0x0080; }
  bool curve_done_toggle(Motor m) const { return low & (0x0100u << static_cast<int>(m)); }
  bool in_position(Motor m) const { return low & (0x1000u << static_cast<int>(m)); }
  bool following_error(Motor m) const { return high & (0x1u << (4 * static_cast<int>(m))); }
  bool position_range(Motor m) const { return high & (0x2u << (4 * static_cast<int>(m))); }
  bool over_temperature(Motor m) const { return high & (0x4u << (4 * static_cast<int>(m))); }
  bool command_toggle(Motor m) const { return high & (0x8u << (4 * static_cast<int>(m))); }
  // The names of the bits set ("RUN State", "Motor A Command Toggle", ...).
  std::vector<std::string> names() const;
};

// §5.2 "Start Curve": a command executes when its toggle bit is the inverse of
// the motor's Command Toggle in the status high word; the controller then
// copies the toggle there. So the toggle to send to `m` is the inverse of
// what the status reports now, and the command has run when the status
// reports the toggle that was sent.
bool toggle_to_send(const Status& s, Motor m);
bool command_done(const Status& s, Motor m, bool sent_toggle);

// The commands whose bit 7 §5.2 draws as the toggle ("Toggle" or "T") and
// which say "For the execution of this command the toggle bit T in the
// command ID has to be the inverse to the Motor x Command Toggle bit of the
// specified drive in the status High word": Increment Position Setpoint 13h,
// Move Home Position 15h, Set Actual Position 19h, Start Curve 20h, Start
// Curve Incremental 22h. Every other command draws bit 7 as "X". These move
// a drive or its position reference: never sent twice.
bool toggle_command(std::uint8_t id);

// The modules a controller is configured with (LinTalk, §5.1) and the master
// drives that have Direct modules. The default: Control In + Addressed In
// (6 bytes to the slave), Status Out + Addressed Out (8 bytes back).
struct IoLayout {
  bool control_in = true, addressed_in = true, direct_in = false;
  bool status_out = true, addressed_out = true, direct_out1 = false, direct_out2 = false;
  std::array<bool, 4> masters{true, false, false, false};  // index Motor

  std::size_t command_size() const;   // master -> slave, bytes
  std::size_t response_size() const;  // slave -> master, bytes
};

struct PollCommand {
  std::uint16_t control = 0;
  CommandWord addressed;
  std::uint16_t addressed_value = 0;
  std::array<CommandWord, 4> direct{};  // per master motor
  std::array<std::uint16_t, 4> direct_value{};
};

struct PollResponse {
  Status status;
  CommandWord addressed_echo;
  std::uint16_t addressed_value = 0;
  std::array<std::uint16_t, 4> direct_out1{}, direct_out2{};
};

// In the order of §5.1 "Example IO Data Exchange": Control Word, Addressed
// Command ID and Value, then per master motor its Direct Command ID and Value.
Bytes encode_command(const IoLayout& l, const PollCommand& c);
// The controller's side of the same exchange (the simulated controller).
Result<PollCommand> decode_command(const IoLayout& l, ByteView bytes);
Bytes encode_response(const IoLayout& l, const PollResponse& r);
// Status Low, Status High, Addressed echo and value, then per master motor
// Direct Out 1 and Direct Out 2. Errc::frame_short / frame_overlong when the
// size does not match the layout (the message gives both sizes).
Result<PollResponse> decode_response(const IoLayout& l, ByteView bytes);

// The application's coded errors of "Get Coded Error" (0Ah, §5.2), e.g.
// 8112h "Drive not in serial mode"; "" for codes the seed does not list
// (the basic LinMot manuals have those).
std::string_view coded_error_text(std::uint16_t code);

}  // namespace lmcfg::devicenet
