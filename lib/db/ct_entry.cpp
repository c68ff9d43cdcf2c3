#include "db/ct_entry.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>

namespace lmcfg::db {

std::string summary_label(std::string_view catalogue_name) {
  std::string s(catalogue_name);
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  auto replace_word = [&s](std::string_view from, std::string_view to) {
    std::size_t pos = 0;
    while ((pos = s.find(from, pos)) != std::string::npos) {
      bool start_ok = pos == 0 || s[pos - 1] == ' ';
      bool end_ok = pos + from.size() == s.size() || s[pos + from.size()] == ' ';
      if (start_ok && end_ok) {
        s.replace(pos, from.size(), to);
        pos += to.size();
      } else {
        pos += from.size();
      }
    }
  };
  replace_word("target position", "target");
  replace_word("maximal", "max");
  replace_word("minimal", "min");
  return s;
}

std::string CtEntry::summary() const {
  if (!version_note.empty()) return version_note;
  std::string s = command_name;
  for (const auto& p : params)
    s += ", " + (p.name.empty() ? "parameter " + std::to_string(p.index) : summary_label(p.name)) +
         " " + p.text;
  return s;
}

Result<CtEntry> decode_ct_entry(const Database& db, ByteView entry) {
  if (entry.size() != kCtEntrySize)
    return Error(Errc::invalid_argument, "command table entry has " + std::to_string(entry.size()) +
                                             " bytes, expected " + std::to_string(kCtEntrySize));
  CtEntry e;
  e.raw.assign(entry.begin(), entry.end());
  e.word0 = get_u16le(entry, 0);
  if (e.word0 != kCtEntryVersion) {
    // The offsets below are those of version A701h (DCF): under another
    // version they would decode whatever sits there as a command.
    char b[160];
    std::snprintf(b, sizeof b,
                  "entry version %04Xh, expected A701h (DCF): another layout; not decoded, kept "
                  "raw (a restore writes its 64 bytes unchanged)",
                  static_cast<unsigned>(e.word0));
    e.version_note = b;
    e.command_name = b;
    return e;
  }
  e.link = get_u16le(entry, 2);
  e.header = get_u16le(entry, 4);
  for (std::size_t i = 38; i < 54 && entry[i] != 0; ++i)
    e.name.push_back(static_cast<char>(entry[i]));
  e.command = db.motion_command(e.header);
  if (!e.command) {
    char b[48];
    std::snprintf(b, sizeof b, "unknown motion command %04Xh",
                  static_cast<unsigned>(e.header & 0xFFF0u));
    e.command_name = b;
    return e;
  }
  e.command_name = e.command->name;
  for (const auto& p : e.command->params) {
    CtParam cp;
    cp.index = p.index;
    cp.entry_offset = 4 + p.offset;
    cp.name = p.name;
    auto off = static_cast<std::size_t>(cp.entry_offset);
    // Unknown type: up to 4 bytes, shown as hex.
    unsigned size =
        p.spec.type
            ? type_size(*p.spec.type)
            : static_cast<unsigned>(std::min<std::size_t>(4, 38 - std::min<std::size_t>(off, 38)));
    if (off + size > 38 || size == 0)
      return Error(Errc::validation_failed,
                   "motion command " + e.command->name + " parameter " + p.name + " at offset " +
                       std::to_string(p.offset) +
                       " runs past the parameter area (entry bytes 6..37)");
    for (unsigned i = 0; i < size; ++i)
      cp.raw |= static_cast<std::uint32_t>(entry[off + i]) << (8 * i);
    cp.text = format_value(p.spec, cp.raw);
    e.params.push_back(std::move(cp));
  }
  return e;
}

}  // namespace lmcfg::db
