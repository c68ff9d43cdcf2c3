#pragma once
// CAN frames and the slcan (Lawicel ASCII) encoding of them: pure bytes, no
// I/O (docs/can.md). DeviceNet (seed 000) uses 11-bit identifiers and at most
// 8 data bytes per frame; extended identifiers and RTR frames are kept so
// that whatever an adapter reports can be shown.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "common/bytes.hpp"
#include "common/result.hpp"

namespace lmcfg::can {

struct Frame {
  std::uint32_t id = 0;   // 11 bits (0..7FFh), or 29 bits when extended
  bool extended = false;  // 29-bit identifier
  bool rtr = false;       // remote transmission request (no data, len = requested length)
  std::uint8_t len = 0;   // 0..8
  std::array<std::uint8_t, 8> data{};

  static Frame standard(std::uint32_t id, ByteView payload);
  ByteView payload() const { return ByteView(data.data(), rtr ? 0 : len); }
  bool operator==(const Frame&) const = default;
};

// "123 [2] AA BB", "1ABCDEF0x [0] RTR": ID in hex (x = extended), length, data.
std::string describe(const Frame& f);
// Errc::invalid_argument: ID beyond 11/29 bits, len > 8.
Result<void> validate(const Frame& f);

namespace slcan {

// The bit rate commands of the Lawicel protocol: S0 10k, S1 20k, S2 50k,
// S3 100k, S4 125k, S5 250k, S6 500k, S7 800k, S8 1M. DeviceNet uses 125,
// 250 and 500 kbit/s (DeviceNet §3 "Baud Rate").
Result<std::string> bitrate_command(unsigned bitrate);  // "S4\r"
std::optional<unsigned> bitrate_of(char digit);         // '4' -> 125000
// "F": read status flags; the answer "Fxx\r" (hex). Lawicel's CAN232/CANUSB
// give bit 5 error passive and bit 7 bus error; other adapters map the bits
// to their CAN controller's status register, so only "not zero" (an error
// since the last read) is taken as meaning something everywhere.
inline constexpr std::string_view kReadStatus = "F\r";
inline constexpr std::string_view kOpen = "O\r";
inline constexpr std::string_view kClose = "C\r";

// "t1232AABB\r" (standard), "T1ABCDEF02AABB\r" (extended), "r1232\r" (RTR).
std::string encode(const Frame& f);

// What an adapter sends: a received frame, the acknowledgement of a command
// ("\r"; after a transmit some adapters send "z\r" / "Z\r"), an error (BEL,
// 07h), or a line it does not understand (kept raw for the message).
struct Ack {
  char kind = 0;  // 0 = bare CR, 'z' / 'Z' = transmit acknowledged
};
struct Bell {};
struct Unknown {
  std::string line;
};
using Event = std::variant<Frame, Ack, Bell, Unknown>;

// Splits the adapter's byte stream into events; keeps a partial line for the
// next feed. Lines longer than any slcan line are dropped as Unknown.
class Decoder {
 public:
  std::vector<Event> feed(ByteView bytes);
  void reset() { line_.clear(); }

 private:
  std::string line_;
};

// One line without its CR ("t1232AABB", timestamps ignored); nullopt when it
// is not a well-formed frame line.
std::optional<Frame> parse_frame_line(std::string_view line);

}  // namespace slcan
}  // namespace lmcfg::can
