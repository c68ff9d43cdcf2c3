#pragma once
// RFC 2217 (Telnet Com Port Control Option) client for serial-to-Ethernet
// servers (Moxa NPort, Lantronix, ser2net's telnet(rfc2217) accepter): the
// client sets the rate, data size, parity and stop bits of the server's serial
// port. Two parts: a pure Telnet/RFC 2217 codec on bytes (this header,
// unit-testable without sockets) and the socket transport (open_rfc2217).
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "transport/transport.hpp"

namespace lmcfg::transport {

// TCP client that negotiates RFC 2217 with the server and sets its serial port
// to `s` (s.device is ignored), checking every confirmation within
// `connect_timeout` (which also bounds the TCP connect). describe():
// "rfc2217 host:port 57600 8N1". reconfigure() changes the server's port.
// discard_input() also asks the server to purge its receive buffer.
Result<std::unique_ptr<Transport>> open_rfc2217(const std::string& host, std::uint16_t port,
                                                const SerialSettings& s, Millis connect_timeout);

namespace rfc2217 {

// RFC 854 "TELNET COMMAND STRUCTURE".
inline constexpr std::uint8_t kSE = 240;
inline constexpr std::uint8_t kSB = 250;
inline constexpr std::uint8_t kWILL = 251;
inline constexpr std::uint8_t kWONT = 252;
inline constexpr std::uint8_t kDO = 253;
inline constexpr std::uint8_t kDONT = 254;
inline constexpr std::uint8_t kIAC = 255;
// Options: RFC 856 (BINARY), RFC 858 (SUPPRESS-GO-AHEAD), RFC 2217 (COM-PORT-OPTION).
inline constexpr std::uint8_t kBinary = 0;
inline constexpr std::uint8_t kEcho = 1;
inline constexpr std::uint8_t kSuppressGoAhead = 3;
inline constexpr std::uint8_t kComPort = 44;

// RFC 2217 client-to-server command codes; the server answers with code + 100.
enum class Command : std::uint8_t {
  signature = 0,
  set_baudrate = 1,
  set_datasize = 2,
  set_parity = 3,
  set_stopsize = 4,
  set_control = 5,
  notify_linestate = 6,
  notify_modemstate = 7,
  flowcontrol_suspend = 8,
  flowcontrol_resume = 9,
  set_linestate_mask = 10,
  set_modemstate_mask = 11,
  purge_data = 12,
};
inline constexpr std::uint8_t kServerOffset = 100;
// "SET-BAUDRATE", "PURGE-DATA"...; "code N" for others.
std::string command_name(std::uint8_t client_code);

// One Telnet command found in the stream (everything but data).
struct Event {
  enum class Kind : std::uint8_t {
    negotiation,     // IAC WILL/WONT/DO/DONT option: `verb`, `option`
    subnegotiation,  // IAC SB option ... IAC SE: `option`, `payload` (IAC IAC undone)
    command,         // another two-byte command (NOP, GA, BRK...): `verb`
  };
  Kind kind = Kind::command;
  std::uint8_t verb = 0;
  std::uint8_t option = 0;
  Bytes payload;
  friend bool operator==(const Event&, const Event&) = default;
};

// Splits the byte stream from the server into data and Telnet commands. Keeps
// its state between feeds: a command or a subnegotiation may be split over reads.
class Decoder {
 public:
  // Appends data bytes to `data` and found commands to `events`.
  void feed(ByteView in, Bytes& data, std::vector<Event>& events);
  // True while a command or subnegotiation is incomplete.
  bool in_command() const noexcept { return state_ != State::data; }

 private:
  enum class State : std::uint8_t { data, iac, option, sb_option, sb, sb_iac };
  State state_ = State::data;
  std::uint8_t verb_ = 0;
  Event sb_;
};

// Data to the server with every 0xFF doubled (RFC 854: "IAC ... must be
// doubled" to be sent as data).
Bytes escape_data(ByteView data);
// IAC verb option.
Bytes encode_negotiation(std::uint8_t verb, std::uint8_t option);
// IAC SB COM-PORT-OPTION code value... IAC SE, 0xFF in the value doubled.
Bytes encode_command(Command code, ByteView value);
// The value bytes of each setting (RFC 2217 "SET-BAUDRATE" ... "SET-STOPSIZE").
Bytes baud_value(unsigned baud);  // 4 bytes, network byte order
std::uint8_t parity_value(Parity p);
std::uint8_t stopsize_value(unsigned stop_bits);
inline constexpr std::uint8_t kDataSize8 = 8;
inline constexpr std::uint8_t kControlNoFlowControl = 1;
inline constexpr std::uint8_t kPurgeReceiveBuffer = 1;

// The value of a confirmation as text for messages ("57600", "even", "2 stop bits").
std::string value_text(Command code, ByteView value);
// Checks a server's COM-PORT-OPTION subnegotiation payload (code + value)
// against what was asked: ok when it is code + 100 with the same value; an
// invalid_argument error naming both values otherwise, e.g. "the server
// confirmed SET-BAUDRATE 9600, asked 57600".
Result<void> check_confirmation(Command asked, ByteView asked_value, ByteView payload);

// Telnet option negotiation of the client (RFC 854 "TELNET OPTION
// NEGOTIATION", RFC 855): BINARY both ways, SUPPRESS-GO-AHEAD both ways,
// COM-PORT-OPTION on our side; everything else refused.
class Negotiator {
 public:
  // What the client sends on connecting: WILL COM-PORT-OPTION, WILL/DO BINARY,
  // WILL/DO SUPPRESS-GO-AHEAD.
  Bytes start();
  // The answer to one IAC WILL/WONT/DO/DONT of the server ("" when none is due).
  Bytes answer(std::uint8_t verb, std::uint8_t option);

  enum class Side : std::uint8_t { off, asked, on, refused };
  // Our side ("we will") and the server's side ("they will") of an option.
  Side ours(std::uint8_t option) const noexcept { return ours_[option]; }
  Side theirs(std::uint8_t option) const noexcept { return theirs_[option]; }

 private:
  std::array<Side, 256> ours_{};
  std::array<Side, 256> theirs_{};
};

}  // namespace rfc2217
}  // namespace lmcfg::transport
