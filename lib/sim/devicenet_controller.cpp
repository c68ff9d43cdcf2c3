#include "sim/devicenet_controller.hpp"

#include "devicenet/catalogue.hpp"

namespace lmcfg::sim {
namespace {

using devicenet::Group2;
using devicenet::Motor;

int key_of(std::optional<Motor> m) { return m ? static_cast<int>(*m) : -1; }

// The ranges this firmware checks on Set (Table 5-1 where it gives one; a
// real controller's firmware is the truth, the database describes the seed).
// Commands without an entry accept any value.
struct Range {
  std::uint8_t get;
  std::int32_t min, max;
};
constexpr Range kRanges[] = {
    {0x10, -32256, 32256}, {0x24, 0, 63},         {0x26, 0, 63},         {0x28, -32256, 32256},
    {0x2A, 0, 4096},       {0x2C, 0, 4096},       {0x34, 0, 32640},      {0x36, 0, 32640},
    {0x38, 0, 32640},      {0x3A, 0, 255},        {0x3C, 0, 32640},      {0x3E, 0, 32640},
    {0x40, -32256, 32256}, {0x42, -32256, 32256}, {0x44, -32256, 32256}, {0x46, -32256, 32256},
    {0x48, 2, 511},        {0x4A, 2, 511},        {0x4C, 4, 511},        {0x4E, 4, 511},
    {0x50, 6, 24576},      {0x52, 6, 1536},       {0x56, -32256, 32256}, {0x58, -32256, 32256},
    {0x5A, -32256, 32256}, {0x5C, -32256, 32256}, {0x70, 0, 7},          {0x72, 0, 7},
    {0x74, 0, 7},          {0x76, 0, 7},
};

const Range* range_of(std::uint8_t get) {
  for (const auto& r : kRanges)
    if (r.get == get) return &r;
  return nullptr;
}

// The Table 5-1 entry behind a command ID: a Get, or the Set one above it.
// Warn/Error State exist for the controller and per motor: `motor_given` picks.
const devicenet::ValueCommand* entry_of(std::uint8_t id, bool motor_given) {
  const auto get = static_cast<std::uint8_t>(id & 0x7E);
  const devicenet::ValueCommand* found = nullptr;
  for (const auto& c : devicenet::value_commands()) {
    if (c.get != get || (id != get && !c.settable)) continue;
    if (!found || c.per_motor == motor_given) found = &c;
  }
  return found;
}

}  // namespace

std::optional<ToggleRule> parse_toggle_rule(std::string_view name) {
  if (name == "seed") return ToggleRule::seed;
  if (name == "get-set-ignore") return ToggleRule::get_set_ignore_toggle;
  if (name == "module") return ToggleRule::module_wide;
  return std::nullopt;
}

namespace {
struct AbsentName {
  const char* name;
  AbsentMotor reading;
};
constexpr AbsentName kAbsentNames[] = {
    {"coded-error", AbsentMotor::coded_error}, {"coded-error-8110", AbsentMotor::coded_error_8110},
    {"no-toggle", AbsentMotor::no_toggle},     {"error-no-echo", AbsentMotor::error_no_echo},
    {"echo-only", AbsentMotor::echo_only},     {"ignore", AbsentMotor::ignore},
};
}  // namespace

std::optional<AbsentMotor> parse_absent_motor(std::string_view name) {
  for (const auto& n : kAbsentNames)
    if (name == n.name) return n.reading;
  return std::nullopt;
}

const char* absent_motor_names() {
  return "coded-error, coded-error-8110, no-toggle, error-no-echo, echo-only, ignore";
}

void DeviceNetController::attach(can::VirtualBus& bus) {
  bus.attach([this](const can::Frame& f, can::VirtualBus& b) { on_frame(f, b); });
}

std::uint16_t DeviceNetController::value(std::optional<Motor> motor, std::uint8_t get_id) const {
  auto it = values_.find({key_of(motor), get_id});
  return it == values_.end() ? 0 : it->second;
}

void DeviceNetController::set_value(std::optional<Motor> motor, std::uint8_t get_id,
                                    std::uint16_t v) {
  values_[{key_of(motor), get_id}] = v;
}

void DeviceNetController::commission() {
  int n = 0;
  for (const auto& c : devicenet::value_commands()) {
    if (!c.settable || c.live) continue;
    for (int m = c.per_motor ? 0 : -1; m < (c.per_motor ? 4 : 0); ++m) {
      if (m >= 0 && !opt_.motors[static_cast<std::size_t>(m)]) continue;
      const auto* r = range_of(c.get);
      const std::int32_t lo = r ? r->min : 0, hi = r ? r->max : 1000;
      const std::int32_t v = lo + (37 * ++n + 11 * (m + 1)) % (hi - lo + 1);
      set_value(m < 0 ? std::nullopt : std::optional<Motor>(static_cast<Motor>(m)), c.get,
                static_cast<std::uint16_t>(v));
    }
  }
}

void DeviceNetController::reset() {
  allocated_by_.reset();
  allocation_ = 0;
  packet_rate_ = 0;
  status_ = {};
  echo_ = {};
  echo_value_ = 0;
  coded_error_ = 0;
  seen_command_ = false;
  last_toggle_ = false;
  controller_toggle_ = false;
  last_word_ = last_value_ = 0;
  stopped_by_error_ = false;
  reassembler_ = {};
}

void DeviceNetController::on_frame(const can::Frame& f, can::VirtualBus& bus) {
  if (f.extended || f.rtr || f.id < 0x400 || f.id >= 0x600) return;
  const auto mac = static_cast<std::uint8_t>((f.id >> 3) & 0x3F);
  const auto message = static_cast<Group2>(f.id & 7);
  if (message == Group2::duplicate_mac_check) {
    if (mac == opt_.mac && f.len > 0 && !(f.data[0] & 0x80)) {
      can::Frame answer = f;
      answer.data[0] |= 0x80;  // response: this MAC ID is taken
      bus.put(answer);
    }
    return;
  }
  if (mac != opt_.mac) return;
  switch (message) {
    case Group2::unconnected_explicit_request:
      explicit_message(f, true, bus);
      break;
    case Group2::master_explicit_request:
      if (allocated_by_ && (allocation_ & devicenet::kAllocExplicit))
        explicit_message(f, false, bus);
      break;
    case Group2::master_io_poll:
      if (allocated_by_ && (allocation_ & devicenet::kAllocPolled)) poll(f, bus);
      break;
    default:
      break;
  }
}

void DeviceNetController::explicit_message(const can::Frame& f, bool unconnected,
                                           can::VirtualBus& bus) {
  auto request = devicenet::Explicit::decode(f.payload());
  if (!request.ok() || request->response) return;
  devicenet::Explicit answer{false, false, request->mac, true, request->service, {}};
  auto refuse = [&](std::uint8_t general, std::uint8_t additional) {
    answer.service = devicenet::kErrorResponse;
    answer.data = {general, additional};
  };
  const Bytes& d = request->data;
  if (unconnected && request->service == devicenet::kAllocate && d.size() >= 4) {
    if (allocated_by_ && *allocated_by_ != d[3]) {
      refuse(0x0C, 0x01);  // object state conflict: another master holds the set
    } else {
      allocated_by_ = d[3];
      allocation_ |= d[2];
      answer.data = {0x00};  // message body format 8/8
    }
  } else if (unconnected && request->service == devicenet::kRelease && d.size() >= 3) {
    if (!allocated_by_ || *allocated_by_ != request->mac) {
      refuse(0x0C, 0x02);
    } else {
      allocation_ &= static_cast<std::uint8_t>(~d[2]);
      if (allocation_ == 0) allocated_by_.reset();
    }
  } else if (!unconnected && request->service == devicenet::kSetAttributeSingle && d.size() >= 5 &&
             d[0] == devicenet::kConnectionClass && d[1] == devicenet::kPolledConnection &&
             d[2] == devicenet::kExpectedPacketRate) {
    // Rounded up to the controller's 10 ms timer, as slaves report the rate they use.
    const auto asked = get_u16le(d, 3);
    packet_rate_ = static_cast<std::uint16_t>((asked + 9) / 10 * 10);
    answer.data.clear();
    put_u16le(answer.data, packet_rate_);
  } else if (!unconnected && request->service == devicenet::kGetAttributeSingle && d.size() >= 3 &&
             d[0] == devicenet::kConnectionClass && d[1] == devicenet::kPolledConnection &&
             (d[2] == devicenet::kProducedConnectionSize ||
              d[2] == devicenet::kConsumedConnectionSize)) {
    answer.data.clear();
    put_u16le(answer.data, static_cast<std::uint16_t>(d[2] == devicenet::kProducedConnectionSize
                                                          ? opt_.layout.response_size()
                                                          : opt_.layout.command_size()));
  } else {
    refuse(0x08, 0xFF);  // service not supported
  }
  bus.put(can::Frame::standard(devicenet::group2_id(opt_.mac, Group2::slave_explicit_response),
                               answer.encode()));
}

void DeviceNetController::coded_error(std::uint16_t code) {
  coded_error_ = code;
  status_.low |= 0x0040;  // ERROR Pending
  if (opt_.error_leaves_run) stopped_by_error_ = true;
}

std::uint16_t DeviceNetController::execute(const devicenet::CommandWord& w, std::uint16_t v) {
  ++executed_;
  std::optional<Motor> motor;
  int selected = 0;
  for (Motor m : devicenet::kMotors) {
    if (!w.motors[static_cast<int>(m)]) continue;
    ++selected;
    motor = m;
  }
  // A command to one drive: 8110h unless exactly one motor is selected,
  // 8111h unless it is a master drive of this controller.
  const auto one_master_drive = [&] {
    if (selected != 1) {
      coded_error(0x8110);  // Drive not specified
      return false;
    }
    if (!opt_.motors[static_cast<int>(*motor)]) {
      coded_error(0x8111);  // Drive not master
      return false;
    }
    return true;
  };
  switch (w.id) {
    case 0x00:
      return 0;
    case 0x02:
      return status_.low;
    case 0x03:
      return status_.high;
    case 0x0A:
      return coded_error_;
    case 0x0B:
      coded_error_ = 0;
      status_.low &= static_cast<std::uint16_t>(~0x0040);
      return 0;
    case 0x20:  // Start Curve
    case 0x22:  // Start Curve Incremental: nothing moves here, the start is counted
      if (!one_master_drive()) return 0;
      if (v > 63) {
        coded_error(0x8118);  // Range error: curves 0 to 63 (Table 5-1)
        return 0;
      }
      ++curves_started_;
      return v;
  }
  const auto* entry = entry_of(w.id, selected > 0);
  if (!entry) {
    coded_error(0x8108);  // Unknown command
    return 0;
  }
  if (entry->needs_module && !opt_.encoder_module) {
    coded_error(0x8120);  // Encoder not exists
    return 0;
  }
  if (entry->per_motor) {
    if (!one_master_drive()) return 0;
  } else {
    motor.reset();
  }
  if (w.id == entry->get) return value(motor, entry->get);
  if (const auto* r = range_of(entry->get)) {
    const auto signed_value =
        r->min < 0 ? static_cast<std::int16_t>(v) : static_cast<std::int32_t>(v);
    if (signed_value < r->min || signed_value > r->max) {
      coded_error(0x8118);  // Range error
      return 0;
    }
  }
  set_value(motor, entry->get, v);
  ++sets_;
  return v;
}

bool DeviceNetController::takes(const devicenet::CommandWord& w, std::uint16_t value) const {
  // DeviceNet §5.2 (Start Curve 20h): "the toggle bit T in the command ID has
  // to be the inverse to the Motor x Command Toggle bit of the specified
  // drive in the status High word". With several motors selected, the
  // inverse of any one's is taken. The status has no toggle for the
  // controller (§5.1 lists "Motor X Command Toggle" only), so this firmware
  // keeps one inside, reported only by the Addressed Out echo.
  const auto by_seed = [&] {
    bool any_motor = false;
    for (Motor m : devicenet::kMotors) {
      if (!w.motors[static_cast<int>(m)]) continue;
      any_motor = true;
      if (status_.command_toggle(m) != w.toggle) return true;
    }
    return !any_motor && w.toggle != controller_toggle_;
  };
  switch (opt_.toggle_rule) {
    case ToggleRule::seed:
      return by_seed();
    case ToggleRule::get_set_ignore_toggle:
      // Bit 7 is "X" (don't care) for these: a firmware that does not look at
      // it still must not run a command again on every poll, so it takes a
      // new one when the words change, as a PLC writes a new command.
      if (devicenet::toggle_command(w.id)) return by_seed();
      return w.encode() != last_word_ || value != last_value_;
    case ToggleRule::module_wide:
      return !seen_command_ || w.toggle != last_toggle_;
  }
  return false;
}

bool DeviceNetController::selects_absent(const devicenet::CommandWord& w) const {
  for (Motor m : devicenet::kMotors)
    if (w.motors[static_cast<int>(m)] && !opt_.motors[static_cast<int>(m)]) return true;
  return false;
}

bool DeviceNetController::run(const devicenet::CommandWord& w, std::uint16_t value) {
  const bool absent = w.id != 0x00 && selects_absent(w);
  const auto reading = absent ? opt_.absent_motor : AbsentMotor::coded_error;
  if (reading == AbsentMotor::ignore) return true;
  bool echo = true, toggles_absent = true;
  switch (reading) {
    case AbsentMotor::coded_error_8110:
      ++executed_;
      coded_error(0x8110);  // Drive not specified
      echo_value_ = 0;
      break;
    case AbsentMotor::echo_only:
      ++executed_;
      echo_value_ = 0;
      toggles_absent = false;
      break;
    case AbsentMotor::error_no_echo:
    case AbsentMotor::no_toggle:
      echo = reading == AbsentMotor::no_toggle;
      toggles_absent = false;
      [[fallthrough]];
    default:
      // 8111h "Drive not master" (or 8110h for several motors) from execute().
      if (echo) {
        echo_value_ = execute(w, value);
      } else {
        ++executed_;
        coded_error(0x8111);
      }
      break;
  }
  if (opt_.reset_after_sets != 0 && sets_ == opt_.reset_after_sets) {
    opt_.reset_after_sets = 0;
    reset();
    return false;
  }
  if (!echo) return true;
  echo_ = w;
  // §5.1 "Motor X Command Toggle: Actual state of the command toggle bit":
  // the toggle of the command the motor last took.
  bool any_motor = false;
  for (Motor m : devicenet::kMotors) {
    if (!w.motors[static_cast<int>(m)]) continue;
    any_motor = true;
    if (!toggles_absent && !opt_.motors[static_cast<int>(m)]) continue;
    const auto bit = static_cast<std::uint16_t>(0x8u << (4 * static_cast<int>(m)));
    status_.high = w.toggle ? (status_.high | bit) : (status_.high & ~bit);
  }
  if (!any_motor) controller_toggle_ = w.toggle;
  return true;
}

void DeviceNetController::poll(const can::Frame& f, can::VirtualBus& bus) {
  auto whole = reassembler_.feed(f.payload(), opt_.layout.command_size() > 8);
  if (!whole.ok() || !*whole) return;
  auto command = devicenet::decode_command(opt_.layout, **whole);
  if (!command.ok()) return;
  if (opt_.layout.addressed_in) {
    const auto& w = command->addressed;
    if (takes(w, command->addressed_value) && !run(w, command->addressed_value)) return;
    seen_command_ = true;
    last_toggle_ = w.toggle;
    last_word_ = w.encode();
    last_value_ = command->addressed_value;
  }
  status_.low |= 0x0001;  // INIT Done
  if (stopped_by_error_) {
    status_.low = static_cast<std::uint16_t>((status_.low & ~0x0002) | 0x0004);  // ERROR State
  } else {
    status_.low |= 0x0002;  // RUN State
  }
  if (drop_polls_ > 0) {
    --drop_polls_;
    ++lost_;
    return;
  }
  if (opt_.lose_poll_responses > 0) {
    rng_ ^= rng_ << 13;  // xorshift32: deterministic per seed
    rng_ ^= rng_ >> 17;
    rng_ ^= rng_ << 5;
    if (static_cast<double>(rng_) / 4294967296.0 < opt_.lose_poll_responses) {
      ++lost_;
      return;
    }
  }
  devicenet::PollResponse r;
  r.status = status_;
  r.addressed_echo = echo_;
  r.addressed_value = echo_value_;
  for (const auto& frame : devicenet::fragment_io(devicenet::encode_response(opt_.layout, r))) {
    bus.put(
        can::Frame::standard(devicenet::group1_id(devicenet::kSlavePollResponse, opt_.mac), frame));
  }
}

}  // namespace lmcfg::sim
