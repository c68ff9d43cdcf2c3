#pragma once
// What a configuration tool reads from a DeviceNet LinMot controller (seed
// 000): the Get commands of §5.2 Table 5-1, which of them have a Set (ID + 1)
// and so can be re-applied, which address a motor and which the controller,
// and which are live values (status, positions, IO) rather than settings.
// Names, ranges and units are the UPID database's (devicenet_commands); this
// table holds only what the database does not say. docs/devicenet.md.
#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "can/frame.hpp"
#include "common/result.hpp"
#include "devicenet/command.hpp"

namespace lmcfg::devicenet {

struct ValueCommand {
  std::uint8_t get = 0;    // the Get command ID; settable ones have their Set at get + 1
  bool settable = false;   // Table 5-1 lists the Set
  bool per_motor = false;  // addresses one motor (else the controller: no motor bit)
  bool live = false;       // a live value (informational), not a setting
  // Reading it needs an add-on module (master encoder or IO module, §5.2
  // "can only be used if ... is attached"): a refusal means "not fitted".
  bool needs_module = false;
};

// In command ID order; the controller's and each motor's are told apart by
// per_motor (Warn/Error State are read both ways: §5.2 "If no drive is
// specified ... the System Warn State is returned, else the Motor Warn State").
std::span<const ValueCommand> value_commands();
const ValueCommand* value_command(std::uint8_t get);

// The IO modules (§5.1) by name: "control-in", "addressed-in", "direct-in",
// "status-out", "addressed-out", "direct-out-1", "direct-out-2", and the
// master drives that carry Direct modules as "master:A".."master:D".
std::vector<std::string> module_names(const IoLayout& l);
// The inverse; a comma-separated list is accepted too ("control-in,addressed-in,...").
// Errc::invalid_argument naming an unknown module.
Result<IoLayout> parse_modules(const std::vector<std::string>& names);
Result<IoLayout> parse_modules(std::string_view comma_separated);

// A frame's DeviceNet meaning for traces: the identifier's group, MAC ID and
// message, then for explicit messages the service (and a response's data),
// for polls of `layout` the Addressed command word, value, status and echo.
std::string describe_frame(const can::Frame& f, const IoLayout& layout);

// Option values, named by `option` in the message (Errc::invalid_argument):
// a MAC ID 0..63 (decimal, or hex with 0x/h), and a motor list "A,B" (commas
// optional, each motor once).
Result<std::uint8_t> parse_mac_id(std::string_view option, std::string_view text);
Result<std::array<bool, 4>> parse_motor_list(std::string_view option, std::string_view text);

// "motor A" / "the controller".
std::string target_name(std::optional<Motor> m);

}  // namespace lmcfg::devicenet
