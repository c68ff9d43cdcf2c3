#pragma once
// `lmcfg link` (README, docs/link.md): a drive's LinRS settings as it holds
// them, and a safe change of them.
//
// The settings are parameters of the Interface layer (LinRS §15). The manual
// gives the UPIDs of four of them, in its §10.2 example: Baud Rate Source Select
// 200Eh (2 = By Parameter), Baud Rate Parameter Def 2012h (8 = 38400 Baud),
// MACID Source Select 206Ch (3 = By Parameter) and MACID Parameter Value 2076h.
// It names checksum, parity and stop bits with their choices but gives neither
// their UPIDs nor any raw value, nor the raw values of the other baud rates: a
// LinkMap says where each setting lives and what its raw values mean, from the
// manual, the database's labels and the user's --map entries; a value the map
// does not know is refused before anything is written.
//
// A change: plan (read the ROM values, refuse what the map cannot express or a
// MACID another drive answers to), then apply: recovery record, stop MC, write
// ROM (value before its source select), reset, find the drive at the new
// settings (link::reconnect, then link::scan of its MACID), read the ROM values
// back, delete the record.
#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/result.hpp"
#include "db/database.hpp"
#include "link/relink.hpp"
#include "link/session.hpp"

namespace lmcfg::ops {

enum class LinkSetting : std::uint8_t {
  baud_source,
  baud,
  macid_source,
  macid,
  checksum,
  parity,
  stop_bits
};
inline constexpr std::size_t kLinkSettings = 7;
// "baud rate source", "baud rate", "MACID source", "MACID", "checksum", "parity", "stop bits".
std::string_view setting_title(LinkSetting s);
// The --map / JSON key: "baud-source", "baud", "id-source", "id", "checksum", "parity",
// "stop-bits".
std::string_view setting_key(LinkSetting s);

// Where one setting lives on the drive and what its raw values mean. Values are
// spelled as the link options spell them ("115200", "crc-ffff", "even", "2";
// "parameter" for a source select's By Parameter). MACID: the raw value is the ID.
struct SettingMap {
  std::optional<std::uint16_t> upid;
  std::vector<std::pair<std::uint32_t, std::string>> codes;
  std::string source;  // where the UPID and codes come from ("LinRS §10.2", "--map")
  std::optional<std::uint32_t> raw_of(std::string_view value) const;
  std::optional<std::string> value_of(std::uint32_t raw) const;
};

struct LinkMap {
  std::array<SettingMap, kLinkSettings> settings;
  SettingMap& operator[](LinkSetting s) { return settings[static_cast<std::size_t>(s)]; }
  const SettingMap& operator[](LinkSetting s) const {
    return settings[static_cast<std::size_t>(s)];
  }
};

// The manual's UPIDs and codes, the database's labels of 2012h, then each
// `entries` item "SETTING[@UPID]:VALUE=RAW[,VALUE=RAW...]" (e.g.
// "checksum@20A0:none=0,add=1,crc=2", "baud:115200=32"). Errc::invalid_argument
// naming the entry when one is malformed or gives another UPID to a setting
// whose UPID the manual states.
Result<LinkMap> link_map(const db::Database& db, const std::vector<std::string>& entries);

// What the drive itself tells about the map: Baud Rate Parameter Def's
// default (§10 05h 07h) is 57600 Bit/s, "RS baud rate = 57600 Bit/s
// (default)" (LinRS §15), so the drive's default raw value of 2012h is the
// code of 57600 unless the map already has one. A refused read adds nothing.
Result<void> learn_from_drive(link::Session& session, LinkMap& map);

// One setting as the drive holds it.
struct LinkValue {
  std::optional<std::uint16_t> upid;
  std::optional<std::uint32_t> rom;  // the ROM value; nullopt: UPID unknown or the read refused
  std::string text;                  // "57600", "parameter", "hex switch S1", "" when unknown
  std::string note;                  // why it is unknown, or where it comes from
};

struct LinkState {
  std::array<LinkValue, kLinkSettings> values;
  // The settings the session talks with (what the drive uses now).
  link::RelinkCandidate in_use;
  const LinkValue& operator[](LinkSetting s) const { return values[static_cast<std::size_t>(s)]; }
};

// Reads the ROM value of every setting whose UPID the map knows (§10 05h 00h).
// A refused read (C8: this firmware has no such UPID) leaves the value unknown
// with the reason; a link failure is an error.
Result<LinkState> read_link_settings(link::Session& session, const LinkMap& map);

// What the user asks for; unset = keep.
struct LinkChange {
  std::optional<unsigned> baud;
  std::optional<std::uint8_t> macid;
  std::optional<codec::ChecksumConfig> checksum;
  std::optional<transport::Parity> parity;
  std::optional<unsigned> stop_bits;
  bool any() const { return baud || macid || checksum || parity || stop_bits; }
};

struct LinkWrite {
  LinkSetting setting;
  std::uint16_t upid = 0;
  std::optional<std::uint32_t> old_value;
  std::uint32_t value = 0;
  std::string text;  // "2012h baud rate: 16 (57600) -> 32 (115200)"
};

struct LinkPlan {
  std::vector<LinkWrite> writes;  // in the order written
  link::RelinkCandidate after;    // the settings the drive talks with after its reset
  bool nothing_to_do() const { return writes.empty(); }
};

// Errc::invalid_argument when the map cannot express `change` (a setting
// without a UPID, a value without a raw value): checked before the link opens.
// 57600 Bd passes without a code: learn_from_drive may find it, plan_link_change
// refuses it if not.
Result<void> check_link_change(const LinkMap& map, const LinkChange& change);

// Errc::invalid_argument (nothing written) for a value the map has no raw
// value for, a setting without a UPID, or a MACID another drive on the line
// already answers to (probed at the current settings, one default response
// request).
Result<LinkPlan> plan_link_change(link::Session& session, const LinkMap& map, const LinkState& now,
                                  const LinkChange& change);

struct LinkApplyReport {
  link::RelinkReport relink;
  bool scanned = false;  // found by link::scan after reconnect's candidates failed
  LinkState after;
};

// Executes `plan`. The recovery record at `recovery` (command "link", the
// previous ROM values) is written before the first write and deleted once the
// drive answers at its new settings and reads back the written values.
// Errors name the step, the drive's state, the record and the next command:
// not found after the reset: Errc::timeout (exit 4); a value that reads back
// differently: Errc::verify_mismatch.
Result<LinkApplyReport> apply_link_change(link::Session& session, const LinkMap& map,
                                          const LinkPlan& plan, const std::string& port,
                                          const std::filesystem::path& recovery);

}  // namespace lmcfg::ops
