#pragma once
// Internal helpers shared by json_io.cpp and xml_io.cpp. Not a public API.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/bytes.hpp"
#include "common/result.hpp"

namespace lmcfg::config::detail {

inline constexpr std::size_t kBytesPerRow = 16;

// "13A2" (4 upper-case hex digits).
std::string upid_hex(std::uint32_t upid);
// Exactly 4 hex digits (either case).
std::optional<std::uint16_t> parse_upid_hex(std::string_view s) noexcept;
// Rows of at most 16 bytes, "46 00 03 ..." upper case.
std::vector<std::string> block_rows(ByteView b);
// One row: 1..16 bytes as two hex digits separated by single spaces.
std::optional<Bytes> parse_row(std::string_view s);
// Unsigned decimal without sign, leading zeros or blanks: "0", "4294967295".
std::optional<std::uint64_t> parse_decimal(std::string_view s) noexcept;
// Signed decimal ("-5", "7"), within int64.
std::optional<std::int64_t> parse_signed_decimal(std::string_view s) noexcept;

// DeviceNet section: a value's motor as written, "controller" or "A".."D"
// (model: kDevicenetController, 0..3), and a command ID as 2 upper-case hex
// digits ("34"), read in either case.
std::string devicenet_motor_text(int motor);
std::optional<int> parse_devicenet_motor(std::string_view s) noexcept;  // "A".."D" or "controller"
std::optional<int> parse_motor_letter(std::string_view s) noexcept;     // "A".."D" only
std::string command_hex(std::uint8_t id);
std::optional<std::uint8_t> parse_command_hex(std::string_view s) noexcept;

// format / format_version check shared by both readers. `where` prefixes the
// message ("f.json:2:13: /format" or "f.xml: /lmcfg/@format").
Result<void> check_format_id(std::string_view format, const std::string& where);
// Version must be within kOldestFormatVersion..kFormatVersion.
Result<void> check_format_version(std::int64_t version, std::string_view name,
                                  const std::string& where);

}  // namespace lmcfg::config::detail
