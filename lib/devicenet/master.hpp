#pragma once
// A DeviceNet master for one slave at a time, the way a configuration tool
// talks to a device without a scanner (Group 2 only client of the Predefined
// Master/Slave Connection Set): duplicate MAC ID check of its own MAC ID,
// Allocate (explicit + polled), the polled connection's expected packet rate,
// polled I/O with the controller's module layout (DeviceNet §5.1), the §5.2
// command exchange on the Addressed modules, Release. docs/can.md.
#include <array>
#include <atomic>
#include <cstdint>
#include <optional>

#include "can/link.hpp"
#include "devicenet/command.hpp"
#include "devicenet/messages.hpp"

namespace lmcfg::devicenet {

struct MasterOptions {
  std::uint8_t own_mac = 0x3E;  // 62: the MAC ID configuration tools commonly take
  std::uint8_t slave_mac = 0x3F;
  IoLayout layout;
  std::uint16_t expected_packet_rate_ms = 2000;  // the slave's watchdog: 4x this without a poll
  transport::Millis timeout{200};                // per request
  int retries = 2;                               // polls only; explicit requests are not repeated
  transport::Millis duplicate_check_wait{1000};  // after each of the two checks
  std::uint16_t vendor_id = 0;
  std::uint32_t serial_number = 0x4C4D4346;  // "LMCF"
  // Checked before each poll: set (by a signal handler) -> Errc::interrupted,
  // so the caller can still release the connection.
  const std::atomic<bool>* cancel = nullptr;
};

class Master {
 public:
  Master(can::Link& link, MasterOptions opt) : link_(link), opt_(opt) {}
  Master(const Master&) = delete;
  Master& operator=(const Master&) = delete;
  ~Master();  // releases the connection set when it holds it

  // Twice a Duplicate MAC ID Check request from own_mac, each followed by
  // duplicate_check_wait of listening. A response means another node has
  // this MAC ID: Errc::invalid_argument naming it.
  Result<void> check_own_mac();
  // Allocate explicit + polled, then the expected packet rate, then the
  // polled connection's produced/consumed sizes, checked against the layout.
  // "Another master owns the connection" (DeviceNet §2.6: one explicit
  // connection, one master at a time) is named when the slave answers
  // Allocate with an error. No answer at all: the message names the bit rate
  // and the MAC ID, and the adapter's bus errors when it reports some. Sizes
  // that do not fit the layout: Errc::not_supported naming the IO setup the
  // commands need (a controller refusing the size query is trusted to have
  // the layout given).
  Result<void> connect();
  Result<void> release();
  bool connected() const { return connected_; }

  // One poll: the command as layout().command_size() bytes (fragmented
  // beyond 8), the response checked against layout().response_size().
  Result<PollResponse> poll(const PollCommand& c);

  // One §5.2 command on the Addressed In module. The toggle follows seed
  // 000's rule (docs/devicenet.md "The command toggle"): a command to a motor
  // carries the inverse of that motor's Command Toggle in the latest status
  // high word (one poll first when no status has been seen); a command to the
  // controller (no motor bit) carries the inverse of the toggle of the last
  // controller-level command the Addressed Out echo showed. It has run when
  // the echo shows its ID, motors and toggle (§5.2: "In the response the
  // LinMot servo controller simply echoes the command") and, for a motor
  // command, the motor's Command Toggle reports the toggle sent; echoed
  // without the toggle following for kStalePolls more polls, it was not
  // taken (last_not_taken()). A Get or value-Set whose echo still shows the
  // previous command after kStalePolls good polls is sent once more with the
  // toggle flipped (a controller whose rule differs); the toggle commands of
  // toggle_command() never are. A motor command not taken with either toggle
  // is followed by Get Status Low Word (02h): when the controller takes that,
  // the motor did not take its command (last_not_taken()), without waiting
  // out kPollsForEcho. A command after which the controller reports ERROR
  // Pending (a motor command: echoed or not) is followed by Get Coded Error (0Ah)
  // and Reset Coded Error (0Bh: the error is this command's, and the next
  // command must not be blamed for it), and fails with Errc::drive_refused
  // naming the code and its text; coded_error() then holds the code.
  Result<std::uint16_t> command(std::array<bool, 4> motors, std::uint8_t id, std::uint16_t value);

  // The command was refused without a coded error because the selected
  // motor did not take it (echoed without its Command Toggle following, or
  // never echoed while the controller took a controller-level Get after it):
  // a motor that is not a master drive of this controller, under the
  // readings of docs/devicenet.md "A motor the controller does not have".
  bool last_not_taken() const { return not_taken_; }

  // The last motor command ran and its motor's Command Toggle changed to the
  // toggle sent. False after the resend with the toggle flipped (which
  // carries the toggle the motor already showed): then only the echo said
  // it ran, as it also does for a motor the controller does not have under
  // the echo-only reading.
  bool last_toggle_witnessed() const { return witnessed_; }

  static constexpr int kPollsForEcho = 50;
  static constexpr int kStalePolls = 5;

  const Status& last_status() const { return status_; }
  std::uint16_t last_coded_error() const { return last_coded_error_; }
  // The polled connection's sizes as the controller reported them (0: not asked or refused).
  std::uint16_t produced_size() const { return produced_size_; }
  std::uint16_t consumed_size() const { return consumed_size_; }
  std::uint16_t granted_packet_rate() const { return granted_rate_; }

 private:
  Result<Explicit> explicit_request(Group2 port, const Explicit& request);
  Result<std::optional<can::Frame>> wait_for(std::uint32_t id, transport::Millis timeout);

  can::Link& link_;
  MasterOptions opt_;
  bool connected_ = false;
  bool have_status_ = false;
  // The toggle of the last controller-level command an echo showed; none
  // seen yet: unknown.
  std::optional<bool> controller_toggle_;
  Status status_;
  CommandWord echo_;
  Result<void> check_connection_sizes();
  Error silence(const std::string& what);
  // Get Coded Error and Reset Coded Error after command `id` raised ERROR
  // Pending: Errc::drive_refused naming the code.
  Error refusal(std::uint8_t id);
  Error not_taken(std::uint8_t id, const std::array<bool, 4>& motors, bool echoed);
  bool not_taken_ = false;
  bool witnessed_ = false;
  // While the 02h after a command not taken is polled: whether the echo
  // showed that command after all (its ID and motors, either toggle).
  std::optional<CommandWord> watch_;
  bool watch_seen_ = false;

  std::uint16_t granted_rate_ = 0;
  std::uint16_t last_coded_error_ = 0;
  std::uint16_t produced_size_ = 0, consumed_size_ = 0;
  PollCommand last_command_;
};

}  // namespace lmcfg::devicenet
