#pragma once
// A simulated DeviceNet LinMot controller (seed 000) on a can::VirtualBus:
// the Predefined Master/Slave Connection Set (duplicate MAC ID check,
// Allocate/Release, the polled connection's expected packet rate) and the
// §5.2 command protocol on the Addressed modules, sharing lib/devicenet's
// codec with the master. Runtime values are kept per motor and command;
// fault hooks: lost poll responses, another master holding the connection,
// a reset mid-session. docs/can.md.
#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string_view>

#include "can/virtual_bus.hpp"
#include "devicenet/command.hpp"
#include "devicenet/messages.hpp"

namespace lmcfg::sim {

// When an Addressed command executes. DeviceNet §5.2 gives the rule for the
// toggle commands only ("the toggle bit T in the command ID has to be the
// inverse to the Motor x Command Toggle bit of the specified drive in the
// status High word") and draws bit 7 of every other command as "X"; the
// readings a firmware may have made of that (docs/devicenet.md):
enum class ToggleRule {
  // Every motor command by its motors' Command Toggle, every controller-level
  // command by a controller toggle of its own (the default).
  seed,
  // Only the toggle commands (devicenet::toggle_command) follow the seed's
  // rule; any other command executes whenever the Addressed In words differ
  // from the previous poll's, whatever its toggle.
  get_set_ignore_toggle,
  // One toggle for the whole module: any command executes on a change of
  // bit 7 from the previous poll (and the first command after power-up).
  module_wide,
};
// "seed", "get-set-ignore", "module"; nullopt for anything else.
std::optional<ToggleRule> parse_toggle_rule(std::string_view name);

// What the controller does with an Addressed command that selects a motor it
// does not have (not a master drive). Seed 000 lists the coded error 8111h
// "Drive not master" (Get Coded Error, §5.2) but says nothing of when it is
// raised, which toggle the command is compared with, what the Addressed Out
// echo and the status words show; the readings (docs/devicenet.md "A motor
// the controller does not have"):
enum class AbsentMotor {
  // Executed and refused: echoed, the motor's Command Toggle follows,
  // ERROR Pending with coded error 8111h (the default).
  coded_error,
  // As coded_error with 8110h "Drive not specified".
  coded_error_8110,
  // Echoed with ERROR Pending and 8111h, but the absent motor's Command
  // Toggle stays (there is no drive to hold it).
  no_toggle,
  // ERROR Pending and 8111h only: the echo keeps the previous command.
  error_no_echo,
  // Echoed (value 0), no error, the absent motor's Command Toggle stays.
  echo_only,
  // Ignored entirely: no echo, no status change, no error.
  ignore,
};
// "coded-error", "coded-error-8110", "no-toggle", "error-no-echo",
// "echo-only", "ignore"; nullopt for anything else.
std::optional<AbsentMotor> parse_absent_motor(std::string_view name);
// The names above, comma-separated, for messages and help.
const char* absent_motor_names();

struct DeviceNetControllerOptions {
  std::uint8_t mac = 0x3F;
  devicenet::IoLayout layout;
  std::array<bool, 4> motors{true, false, false, false};  // present (master drives)
  bool encoder_module = false;  // a master encoder module: commands 60h..6Bh work
  // Fault: each poll response is lost with this probability (the command it
  // answers has still executed, as when the frame is lost on the bus).
  double lose_poll_responses = 0;
  // Firmware variant (seed 000 leaves it open): a coded error also takes the
  // controller out of RUN into ERROR State until it is reset.
  bool error_leaves_run = false;
  std::uint32_t seed = 1;
  // Fault: a controller reset (power dip) right after this many executed Set
  // commands, once; 0 = never. The connection is gone, values are kept.
  std::uint64_t reset_after_sets = 0;
  ToggleRule toggle_rule = ToggleRule::seed;
  AbsentMotor absent_motor = AbsentMotor::coded_error;
};

class DeviceNetController {
 public:
  explicit DeviceNetController(DeviceNetControllerOptions o) : opt_(o), rng_(o.seed | 1u) {}
  // Serves on `bus` from now on (the bus keeps a callback to this object).
  void attach(can::VirtualBus& bus);

  // The runtime value behind a Get command ID (Table 5-1) for a motor, or
  // for the controller when motor is nullopt.
  std::uint16_t value(std::optional<devicenet::Motor> motor, std::uint8_t get_id) const;
  void set_value(std::optional<devicenet::Motor> motor, std::uint8_t get_id, std::uint16_t v);
  // A commissioned controller: every settable value of each present motor
  // (and of the controller) set to a plausible value inside this firmware's
  // range, different per motor; deterministic.
  void commission();

  // Fault hooks.
  void hold_for_other_master(std::uint8_t mac) { allocated_by_ = mac; }
  void drop_poll_responses(int n) { drop_polls_ = n; }
  void reset();  // power cycle: connection released, status cleared, values kept

  std::optional<std::uint8_t> allocated_by() const { return allocated_by_; }
  std::uint16_t expected_packet_rate() const { return packet_rate_; }
  std::uint64_t commands_executed() const { return executed_; }
  std::uint64_t poll_responses_lost() const { return lost_; }
  std::uint64_t curves_started() const { return curves_started_; }

 private:
  void on_frame(const can::Frame& f, can::VirtualBus& bus);
  void explicit_message(const can::Frame& f, bool unconnected, can::VirtualBus& bus);
  void poll(const can::Frame& f, can::VirtualBus& bus);
  std::uint16_t execute(const devicenet::CommandWord& w, std::uint16_t value);
  void coded_error(std::uint16_t code);
  // Whether this poll's Addressed In command executes, by opt_.toggle_rule.
  bool takes(const devicenet::CommandWord& w, std::uint16_t value) const;
  // The command selects a motor this controller does not have.
  bool selects_absent(const devicenet::CommandWord& w) const;
  // Runs a command taken by takes(): its value, echo and Command Toggles,
  // played by opt_.absent_motor when it selects an absent motor. False: the
  // controller reset (reset_after_sets) and sends no response.
  bool run(const devicenet::CommandWord& w, std::uint16_t value);

  DeviceNetControllerOptions opt_;
  std::optional<std::uint8_t> allocated_by_;
  std::uint8_t allocation_ = 0;
  std::uint16_t packet_rate_ = 0;
  int drop_polls_ = 0;
  bool last_toggle_ = false;  // module_wide: bit 7 of the previous poll
  bool seen_command_ = false;
  bool controller_toggle_ = false;  // seed: the last controller-level command's toggle
  std::uint16_t last_word_ = 0, last_value_ = 0;  // the previous poll's Addressed In
  bool stopped_by_error_ = false;
  devicenet::Status status_;
  devicenet::CommandWord echo_;
  std::uint16_t echo_value_ = 0;
  std::uint16_t coded_error_ = 0;
  std::map<std::pair<int, std::uint8_t>, std::uint16_t> values_;
  devicenet::IoReassembler reassembler_;
  std::uint64_t executed_ = 0;
  std::uint64_t lost_ = 0;
  std::uint64_t sets_ = 0;
  std::uint64_t curves_started_ = 0;
  std::uint32_t rng_;
};

}  // namespace lmcfg::sim
