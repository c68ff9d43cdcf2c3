#pragma once
// Decoding a command table entry (LinRS §12.1; offsets from seed 001
// §4.3.143) with the motion command catalogue.
//   off 0..1   entry version, fixed A701h (DCF: offset 0
//              is the entry version, fixed A701h); another value: nothing
//              else is decoded (version_note says why), the bytes stay raw
//   off 2..3   link ID (FFFFh: no successor)
//   off 4..5   motion command header (master<<8 | sub<<4 | count)
//   off 6..37  the command's parameters: entry offset = 4 + catalogue offset
//   off 38..53 name, NUL-padded, at most 15 characters + NUL
//   off 54..63 unresolved                                 kept raw
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/bytes.hpp"
#include "common/result.hpp"
#include "db/database.hpp"

namespace lmcfg::db {

inline constexpr std::size_t kCtEntrySize = 64;
inline constexpr std::uint16_t kCtNoLink = 0xFFFF;
inline constexpr std::uint16_t kCtEntryVersion = 0xA701;  // DCF, entry offset 0

struct CtParam {
  int index = 0;
  int entry_offset = 0;  // from the start of the entry
  std::string name;      // catalogue name ("Target Position")
  std::uint32_t raw = 0;
  std::string text;  // formatted: "100 mm"
};

struct CtEntry {
  std::uint16_t word0 = 0;  // off 0, the entry version (kCtEntryVersion)
  // "" for version A701h; else why the entry is not decoded, e.g. "entry
  // version 1234h, expected A701h (DCF): another layout; not decoded, kept raw
  // (a restore writes its 64 bytes unchanged)". summary() is this note then.
  std::string version_note;
  std::uint16_t link = kCtNoLink;
  std::uint16_t header = 0;
  const MotionCommand* command = nullptr;  // null when the header is not in the catalogue
  std::string command_name;                // catalogue name, or "unknown motion command 0123h"
  std::vector<CtParam> params;
  std::string name;  // entry name ("Unnamed")
  Bytes raw;         // the 64 bytes as given

  bool has_link() const { return link != kCtNoLink; }
  // "VAI Go To Pos, target 100 mm, max velocity 0.5 m/s, acceleration 2 m/s2, deceleration 2 m/s2"
  std::string summary() const;
};

// Label of a parameter in the one-line summary: the catalogue name in lower
// case, "maximal"/"minimal" shortened to "max"/"min", "target position" to "target".
std::string summary_label(std::string_view catalogue_name);

// Errc::invalid_argument unless the entry is exactly 64 bytes. An unknown
// command header is not an error (command == nullptr, no parameters), nor is
// another entry version (version_note set, only word0 and raw filled in).
Result<CtEntry> decode_ct_entry(const Database& db, ByteView entry);

}  // namespace lmcfg::db
