#pragma once
// LinRS framing (LinRS §4): 01 | ID | LEN | 02 SUB MAIN data... | [CHK_LO CHK_HI] | 04
// Pure: bytes in, typed telegrams out. No I/O, no clock.
#include <cstdint>
#include <optional>
#include <string>

#include "common/bytes.hpp"
#include "common/result.hpp"

namespace lmcfg::codec {

inline constexpr std::uint8_t kStartHeader = 0x01;
inline constexpr std::uint8_t kStartData = 0x02;
inline constexpr std::uint8_t kEndTelegram = 0x04;
inline constexpr std::size_t kMinLen =
    3;  // 02 SUB MAIN: the table allows 2, but no message is shorter than 3
inline constexpr std::size_t kMaxLen = 63;  // LinRS §4 table

// crc_ccitt: CRC-16, polynomial 0x1021, MSB first, initial value crc_init
// (0xFFFF "CCITT-FALSE" or 0x0000 "XMODEM"). crc_kermit: the same polynomial
// reflected (LSB first, 0x8408), initial value 0, "CRC-16/KERMIT". Seed 003
// §4.4/§15 say only "CRC CCITT polynomial 16 bit": all three readings are options.
enum class ChecksumMode : std::uint8_t { none, add, crc_ccitt, crc_kermit };

// Which bytes the checksum covers. LinRS §4 places "Checksum Calculation"
// under ID..last data byte; that is the default. The other readings stay
// selectable because the manual does not settle them (LinRS §4, §15: unresolved).
enum class ChecksumCoverage : std::uint8_t { id_through_data, start_through_data, data_only };

struct ChecksumConfig {
  ChecksumMode mode = ChecksumMode::none;
  std::uint16_t crc_init = 0xFFFF;  // crc_ccitt only: CCITT-FALSE; 0x0000 is the XMODEM reading
  ChecksumCoverage coverage = ChecksumCoverage::id_through_data;

  std::size_t size() const { return mode == ChecksumMode::none ? 0 : 2; }
  friend bool operator==(const ChecksumConfig&, const ChecksumConfig&) = default;
};

std::uint16_t checksum_add(ByteView bytes);
// CRC-16 with the CCITT polynomial 0x1021, MSB first, no reflection, no final xor.
std::uint16_t checksum_crc_ccitt(ByteView bytes, std::uint16_t init);
// CRC-16/KERMIT: polynomial 0x1021 reflected (0x8408), LSB first, init 0, no final xor.
std::uint16_t checksum_crc_kermit(ByteView bytes);
std::uint16_t compute_checksum(const ChecksumConfig& cfg, ByteView frame_without_checksum);

// One telegram. data[] holds the message data after SUB and MAIN; LEN = data.size() + 3.
struct Telegram {
  std::uint8_t id = 0;    // MACID
  std::uint8_t sub = 0;   // message sub ID
  std::uint8_t main = 0;  // message main ID
  Bytes data;

  std::uint16_t message_id() const { return static_cast<std::uint16_t>(main << 8 | sub); }
  friend bool operator==(const Telegram&, const Telegram&) = default;
};

// Encodes to wire bytes. Fails (invalid_argument) when data is longer than LEN 63 allows.
Result<Bytes> encode(const Telegram& t, const ChecksumConfig& cfg = {});

// Decodes exactly one complete frame (no leading/trailing bytes). Errors:
// frame_short (fewer bytes than LEN says), frame_overlong (more), frame_malformed
// (bad start/end marker, LEN out of 3..63), checksum_mismatch.
Result<Telegram> decode(ByteView frame, const ChecksumConfig& cfg = {});

// Finds frames in a byte stream that may hold garbage, partial frames and
// several frames at once. Never throws; every anomaly is reported as an Error
// and the decoder resynchronises on the next 01 after the bad start byte.
class StreamDecoder {
 public:
  explicit StreamDecoder(ChecksumConfig cfg = {}) : cfg_(cfg) {}

  void feed(ByteView bytes);
  // Next complete frame, or an error about skipped/broken bytes; nullopt when
  // more input is needed.
  std::optional<Result<Telegram>> next();
  // Call when the line has gone idle (the drive's byte-to-byte time-out, §15):
  // a pending partial frame is reported as frame_short and dropped.
  std::optional<Error> flush_idle();

  std::size_t buffered() const { return buf_.size() - pos_; }
  std::uint64_t garbage_bytes() const { return garbage_; }
  void reset();
  void set_checksum(const ChecksumConfig& cfg) { cfg_ = cfg; }

 private:
  void compact();
  ChecksumConfig cfg_;
  Bytes buf_;
  std::size_t pos_ = 0;
  std::uint64_t garbage_ = 0;
};

}  // namespace lmcfg::codec
