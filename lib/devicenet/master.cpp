#include "devicenet/master.hpp"

#include <chrono>

#include "devicenet/catalogue.hpp"

namespace lmcfg::devicenet {
namespace {

using Clock = std::chrono::steady_clock;

std::string mac_name(std::uint8_t mac) { return "DeviceNet MAC ID " + std::to_string(mac); }

std::optional<Motor> first_motor(const std::array<bool, 4>& motors) {
  for (Motor m : kMotors)
    if (motors[static_cast<std::size_t>(m)]) return m;
  return std::nullopt;
}

// Each selected motor's Command Toggle reports the toggle sent (§5.1 "Motor
// X Command Toggle: Actual state of the command toggle bit").
bool toggles_follow(const PollResponse& r, const CommandWord& sent) {
  for (Motor m : kMotors)
    if (sent.motors[static_cast<std::size_t>(m)] && !command_done(r.status, m, sent.toggle))
      return false;
  return true;
}

std::string motor_names(const std::array<bool, 4>& motors) {
  std::string out;
  for (Motor m : kMotors)
    if (motors[static_cast<std::size_t>(m)]) out += (out.empty() ? "" : " and ") + target_name(m);
  return out;
}

// Commands that may run twice without harm: No Command, a Get, the Set of a
// value (Table 5-1's Get + 1), the resets of the warn, error and coded error
// states. Never the toggle commands that move a drive or its reference.
bool may_repeat(std::uint8_t id) {
  if (toggle_command(id)) return false;
  if (id == 0x00 || id == 0x07 || id == 0x09 || id == 0x0B) return true;
  const auto get = static_cast<std::uint8_t>(id & 0x7E);
  const auto* v = value_command(get);
  return v && (id == get || v->settable);
}

}  // namespace

Master::~Master() {
  if (connected_) (void)release();
}

Result<std::optional<can::Frame>> Master::wait_for(std::uint32_t id, transport::Millis timeout) {
  const auto until = Clock::now() + timeout;
  for (;;) {
    const auto left = std::chrono::duration_cast<transport::Millis>(until - Clock::now());
    if (left.count() <= 0) return std::optional<can::Frame>();
    LMCFG_ASSIGN_OR_RETURN(auto f, link_.receive(left));
    if (f && !f->extended && !f->rtr && f->id == id) return f;
  }
}

Result<void> Master::check_own_mac() {
  Bytes data{0x00};  // request, physical port 0
  put_u16le(data, opt_.vendor_id);
  put_u32le(data, opt_.serial_number);
  const auto id = group2_id(opt_.own_mac, Group2::duplicate_mac_check);
  for (int round = 0; round < 2; ++round) {
    LMCFG_TRY(link_.send(can::Frame::standard(id, data)));
    LMCFG_ASSIGN_OR_RETURN(auto answer, wait_for(id, opt_.duplicate_check_wait));
    if (answer) {
      return Error(Errc::invalid_argument,
                   mac_name(opt_.own_mac) +
                       " (this tool's) is already used on the bus by another "
                       "node: choose another with --devicenet-own-macid");
    }
  }
  return {};
}

Result<Explicit> Master::explicit_request(Group2 port, const Explicit& request) {
  LMCFG_TRY(link_.send(can::Frame::standard(group2_id(opt_.slave_mac, port), request.encode())));
  LMCFG_ASSIGN_OR_RETURN(
      auto answer,
      wait_for(group2_id(opt_.slave_mac, Group2::slave_explicit_response), opt_.timeout));
  if (!answer) {
    return silence(std::string(service_name(request.service)) + " within " +
                   std::to_string(opt_.timeout.count()) + " ms");
  }
  return Explicit::decode(answer->payload());
}

// Silence has two usual causes the tool can tell apart by the adapter's error
// flags: at a wrong bit rate no node acknowledges our frames (bus errors); at
// the right rate with a wrong MAC ID the controller acknowledges them on the
// CAN level but does not answer.
Error Master::silence(const std::string& what) {
  std::string text =
      "no answer from " + mac_name(opt_.slave_mac) + " to " + what + " on " + link_.describe();
  auto flags = link_.status_flags();
  if (flags.ok() && *flags && **flags != 0) {
    text += ": the adapter reports CAN bus errors (status flags " + hex(**flags, 2, "h") +
            "): no node acknowledged the frames, so the bit rate is probably wrong: check "
            "--can-bitrate (125000, 250000 or 500000, the controller's DeviceNet\\Baudrate) and "
            "that the adapter is connected to the DeviceNet bus";
  } else if (flags.ok() && *flags) {
    text +=
        ": the bus carried the frames without errors, so the bit rate fits; check "
        "--devicenet-macid (the controller's MAC ID switches) and that the controller is "
        "powered";
  } else {
    text += ": check --can-bitrate (125000, 250000 or 500000), --devicenet-macid and the cabling";
  }
  return Error(Errc::timeout, text);
}

Result<void> Master::connect() {
  const auto request = allocate(opt_.own_mac, kAllocExplicit | kAllocPolled);
  LMCFG_ASSIGN_OR_RETURN(auto answer,
                         explicit_request(Group2::unconnected_explicit_request, request));
  if (auto data = response_data(request, answer); !data.ok()) {
    if (data.error().code == make_error_code(Errc::drive_refused)) {
      return Error(Errc::drive_refused,
                   mac_name(opt_.slave_mac) + " refused the connection: " + data.error().message +
                       "; another master (a PLC's scanner) probably holds it: the controller "
                       "serves one master at a time (seed 000 §2.6)");
    }
    return std::move(data).error();
  }
  connected_ = true;
  // A new connection may meet a controller that restarted or served another
  // master: the toggles are learned again, and the first poll carries No
  // Command (harmless should it run) rather than this master's last command.
  have_status_ = false;
  controller_toggle_.reset();
  last_command_.addressed = {};
  last_command_.addressed_value = 0;
  Bytes rate;
  put_u16le(rate, opt_.expected_packet_rate_ms);
  const auto set =
      set_attribute(opt_.own_mac, kConnectionClass, kPolledConnection, kExpectedPacketRate, rate);
  LMCFG_ASSIGN_OR_RETURN(auto set_answer, explicit_request(Group2::master_explicit_request, set));
  LMCFG_ASSIGN_OR_RETURN(auto granted, response_data(set, set_answer));
  granted_rate_ = granted.size() >= 2 ? get_u16le(granted, 0) : opt_.expected_packet_rate_ms;
  return check_connection_sizes();
}

Result<void> Master::check_connection_sizes() {
  std::uint16_t sizes[2] = {};
  const std::uint8_t attributes[2] = {kConsumedConnectionSize, kProducedConnectionSize};
  for (int i = 0; i < 2; ++i) {
    const auto get =
        get_attribute(opt_.own_mac, kConnectionClass, kPolledConnection, attributes[i]);
    LMCFG_ASSIGN_OR_RETURN(auto answer, explicit_request(Group2::master_explicit_request, get));
    auto data = response_data(get, answer);
    if (!data.ok() || data->size() < 2) return {};  // not told: the layout given is trusted
    sizes[i] = get_u16le(*data, 0);
  }
  consumed_size_ = sizes[0];
  produced_size_ = sizes[1];
  const auto& l = opt_.layout;
  if (consumed_size_ == l.command_size() && produced_size_ == l.response_size()) return {};
  std::string text =
      mac_name(opt_.slave_mac) + "'s polled connection takes " + std::to_string(consumed_size_) +
      " byte(s) and gives " + std::to_string(produced_size_) + ", but the IO layout " +
      std::to_string(l.command_size()) + "/" + std::to_string(l.response_size()) + " was expected";
  if (consumed_size_ < 4 || produced_size_ < 4) {
    text +=
        ": it cannot hold the Addressed In and Addressed Out modules the configuration "
        "commands need (seed 000 §5.1, §5.2). Configure the controller's IO setup with "
        "LinTalk to include Addressed In and Addressed Out (the default: Control In + "
        "Addressed In, Status Out + Addressed Out), then run again";
  } else {
    text +=
        ": give the controller's modules with --io-modules (e.g. "
        "control-in,addressed-in,status-out,addressed-out), as set up with LinTalk (§5.1)";
  }
  return Error(Errc::not_supported, text);
}

Result<void> Master::release() {
  connected_ = false;
  const auto request = devicenet::release(opt_.own_mac, kAllocExplicit | kAllocPolled);
  LMCFG_ASSIGN_OR_RETURN(auto answer,
                         explicit_request(Group2::unconnected_explicit_request, request));
  LMCFG_TRY(response_data(request, answer));
  return {};
}

Result<PollResponse> Master::poll(const PollCommand& c) {
  if (opt_.cancel && opt_.cancel->load())
    return Error(Errc::interrupted, "interrupted between two polls of " + mac_name(opt_.slave_mac));
  const Bytes command = encode_command(opt_.layout, c);
  const bool fragmented_answer = opt_.layout.response_size() > 8;
  const auto poll_id = group2_id(opt_.slave_mac, Group2::master_io_poll);
  const auto answer_id = group1_id(kSlavePollResponse, opt_.slave_mac);
  for (int attempt = 0;; ++attempt) {
    for (const auto& frame : fragment_io(command))
      LMCFG_TRY(link_.send(can::Frame::standard(poll_id, frame)));
    IoReassembler reassembler;
    std::optional<Bytes> response;
    while (!response) {
      LMCFG_ASSIGN_OR_RETURN(auto f, wait_for(answer_id, opt_.timeout));
      if (!f) break;
      auto part = reassembler.feed(f->payload(), fragmented_answer);
      if (!part.ok()) break;  // a lost fragment: poll again
      response = std::move(part).value();
    }
    if (response) {
      LMCFG_ASSIGN_OR_RETURN(auto r, decode_response(opt_.layout, *response));
      status_ = r.status;
      echo_ = r.addressed_echo;
      have_status_ = true;
      if (watch_ && echo_.id == watch_->id && echo_.motors == watch_->motors) watch_seen_ = true;
      if (first_motor(echo_.motors) == std::nullopt) controller_toggle_ = echo_.toggle;
      return r;
    }
    if (attempt >= opt_.retries) {
      return Error(Errc::timeout, "no poll response from " + mac_name(opt_.slave_mac) + " within " +
                                      std::to_string(opt_.timeout.count()) + " ms (after " +
                                      std::to_string(attempt + 1) + " polls)");
    }
  }
}

Result<std::uint16_t> Master::command(std::array<bool, 4> motors, std::uint8_t id,
                                      std::uint16_t value) {
  if (!opt_.layout.addressed_in || !opt_.layout.addressed_out) {
    return Error(Errc::not_supported,
                 "the controller's module layout has no Addressed In/Out: commands need both");
  }
  last_coded_error_ = 0;
  not_taken_ = false;
  witnessed_ = false;
  if (!have_status_) LMCFG_TRY(poll(last_command_));
  const auto target = first_motor(motors);
  const bool error_before = status_.error_pending();
  const CommandWord previous = echo_;
  PollCommand c = last_command_;
  // DeviceNet §5.2 (Start Curve 20h): "the toggle bit T in the command ID has
  // to be the inverse to the Motor x Command Toggle bit of the specified drive
  // in the status High word". The status has no toggle for the controller, so
  // a controller-level command takes the inverse of the last controller-level
  // echo (unknown: 1, corrected by the resend below).
  const bool toggle = target ? toggle_to_send(status_, *target)
                             : !(controller_toggle_ ? *controller_toggle_ : false);
  c.addressed = CommandWord{motors, toggle, static_cast<std::uint8_t>(id & 0x7F)};
  c.addressed_value = value;
  // Completion is what §5.2 guarantees for every command: "In the response
  // the LinMot servo controller simply echoes the command" (the Addressed Out
  // echo shows its ID, motors and toggle). Only when the echo already showed
  // this very word before it was sent does the Command Toggle decide.
  const bool echo_was_word = previous == c.addressed;
  // A repeated poll carries the same toggle, which the controller has already
  // taken, so polling until the echo matches never executes a command twice.
  bool resent = false;
  int stale = 0, unfollowed = 0;
  for (int i = 0; i < kPollsForEcho; ++i) {
    last_command_ = c;
    LMCFG_ASSIGN_OR_RETURN(auto r, poll(c));
    const bool follows = toggles_follow(r, c.addressed);
    const bool echoed = r.addressed_echo == c.addressed && (!echo_was_word || follows);
    // A motor command after which ERROR Pending appears is refused, echoed or
    // not (seed 000 does not say whether a refused command is echoed).
    if (r.status.error_pending() && !error_before && id != 0x0A && (echoed || target)) {
      if (echoed && !target) controller_toggle_ = c.addressed.toggle;
      return refusal(id);
    }
    if (echoed) {
      if (!target) controller_toggle_ = c.addressed.toggle;
      if (follows) {
        // The flipped resend carries the toggle the motor already showed:
        // its Command Toggle cannot witness it.
        witnessed_ = target && !resent;
        return r.addressed_value;
      }
      // Echoed, but the motor's Command Toggle does not take it (a status a
      // poll behind is given kStalePolls polls): a motor without a drive.
      if (++unfollowed > kStalePolls) return not_taken(id, motors, true);
      continue;
    }
    stale = r.addressed_echo == previous ? stale + 1 : 0;
    if (stale < kStalePolls || !may_repeat(id)) continue;
    stale = 0;
    if (!resent) {
      // Not taken: this controller compares the toggle with something
      // else (one toggle for the whole module, a controller-level toggle
      // this master has not seen). Once more with the other toggle; a Get
      // or a Set of a value is harmless should both run.
      c.addressed.toggle = !c.addressed.toggle;
      resent = true;
    } else if (target) {
      // Not taken with either toggle: the controller is asked a
      // controller-level Get. Taking that one while this command's echo
      // never came is the answer (a controller that ignores commands for a
      // motor it does not have), not a time-out.
      // A slow controller that shows this command's echo late, while the
      // 02h is polled, had taken it after all: the command is asked again.
      watch_ = c.addressed;
      watch_seen_ = false;
      auto fence = command({}, 0x02, 0);
      watch_.reset();
      LMCFG_TRY(fence);
      if (watch_seen_) return command(motors, id, value);
      return not_taken(id, motors, false);
    }
  }
  return Error(Errc::timeout, "command " + hex(id, 2, "h") + " to " + mac_name(opt_.slave_mac) +
                                  ": the Addressed Out echo did not show it after " +
                                  std::to_string(kPollsForEcho) + " polls");
}

Error Master::refusal(std::uint8_t id) {
  auto coded = command({}, 0x0A, 0);
  const std::uint16_t code = coded.ok() ? *coded : 0;
  if (coded.ok()) {
    auto reset = command({}, 0x0B, 0);
    if (!reset.ok()) return std::move(reset).error();
  }
  last_coded_error_ = code;
  std::string text = "command " + hex(id, 2, "h") + " to " + mac_name(opt_.slave_mac) +
                     ": the controller reports an error";
  if (coded.ok()) {
    text += ", coded error " + hex(code, 4, "h");
    if (auto t = coded_error_text(code); !t.empty()) text += " " + std::string(t);
  }
  return Error(Errc::drive_refused, text);
}

Error Master::not_taken(std::uint8_t id, const std::array<bool, 4>& motors, bool echoed) {
  not_taken_ = true;
  const std::string m = motor_names(motors);
  return Error(Errc::drive_refused,
               "command " + hex(id, 2, "h") + " to " + m + " of " + mac_name(opt_.slave_mac) +
                   " was not taken: " +
                   (echoed ? "the Addressed Out echo shows it, but " + m +
                                 "'s Command Toggle did not follow (seed 000 §5.1: \"Actual "
                                 "state of the command toggle bit\")"
                           : "the Addressed Out echo kept showing the previous command with "
                             "either toggle, and the controller took the next command (02h) "
                             "instead") +
                   "; " + m + " is probably not a master drive of this controller");
}

}  // namespace lmcfg::devicenet
