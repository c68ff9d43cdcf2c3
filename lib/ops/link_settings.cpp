// `lmcfg link`: reading, planning and applying a change of the LinRS settings.
// Why each step is as it is: docs/link.md.
#include "ops/link_settings.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>

#include "common/bytes.hpp"
#include "link/scan.hpp"
#include "ops/backup.hpp"
#include "ops/recovery.hpp"
#include "ops/restore.hpp"

namespace lmcfg::ops {

namespace {

using S = LinkSetting;

constexpr std::array<std::string_view, kLinkSettings> kTitles = {
    "baud rate source", "baud rate", "MACID source", "MACID", "checksum", "parity", "stop bits"};
constexpr std::array<std::string_view, kLinkSettings> kKeys = {
    "baud-source", "baud", "id-source", "id", "checksum", "parity", "stop-bits"};

std::string trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return std::string(s);
}

std::optional<std::uint32_t> parse_raw(std::string_view t, bool hex_default = false) {
  return parse_number(trim(t), hex_default);
}

// A value as the map stores it: checksums by their canonical option name
// ("crc" -> "crc-ffff"), everything else as given.
Result<std::string> canonical(S s, std::string_view value) {
  const std::string v = trim(value);
  switch (s) {
    case S::checksum: {
      LMCFG_ASSIGN_OR_RETURN(auto c, link::parse_checksum(v));
      return link::checksum_name(c);
    }
    case S::parity:
      if (!transport::parity_from_name(v))
        return Error(Errc::invalid_argument, "parity '" + v + "' is not one of none, even, odd");
      return v;
    case S::stop_bits:
      if (v != "1" && v != "2")
        return Error(Errc::invalid_argument, "stop bits '" + v + "' is not 1 or 2");
      return v;
    case S::baud: {
      auto b = parse_raw(v);
      if (!b || std::find(transport::kSerialBaudRates.begin(), transport::kSerialBaudRates.end(),
                          *b) == transport::kSerialBaudRates.end())
        return Error(Errc::invalid_argument,
                     "baud rate '" + v +
                         "' is not a LinRS rate (seed 003 §3.2.1: 4800, 9600, 19200, 38400, "
                         "57600, 115200)");
      return std::to_string(*b);
    }
    case S::baud_source:
    case S::macid_source:
      if (v != "parameter")
        return Error(Errc::invalid_argument,
                     "a source select takes only 'parameter' (seed 003 gives no raw value of its "
                     "hex switch choices)");
      return v;
    case S::macid:
      return Error(Errc::invalid_argument, "the MACID's raw value is the ID itself: no codes");
  }
  return v;
}

void put_code(SettingMap& m, std::uint32_t raw, std::string value) {
  std::erase_if(m.codes, [&](const auto& c) { return c.first == raw || c.second == value; });
  m.codes.emplace_back(raw, std::move(value));
}

std::string code_list(const SettingMap& m) {
  std::string s;
  for (const auto& [raw, v] : m.codes)
    s += (s.empty() ? "" : ", ") + v + " = " + std::to_string(raw);
  return s.empty() ? "none" : s;
}

// The text of a raw value of `s`, "" when the map does not know it.
std::string text_of(const LinkMap& map, S s, std::uint32_t raw) {
  if (s == S::macid) return raw <= 0xFF ? hex(static_cast<std::uint8_t>(raw), 2, "h") : "";
  if (auto v = map[s].value_of(raw)) return *v == "parameter" ? "By Parameter" : *v;
  // LinRS §15 lists two choices for Baud Rate Source Select and three for
  // MACID Source Select; the raw value of By Parameter is stated (§10.2), so
  // any other value is a hex switch choice.
  if (s == S::baud_source) return "hex switch S1";
  if (s == S::macid_source) return "hex switches (S2, or S1 and S2)";
  return "";
}

}  // namespace

std::string_view setting_title(LinkSetting s) { return kTitles[static_cast<std::size_t>(s)]; }
std::string_view setting_key(LinkSetting s) { return kKeys[static_cast<std::size_t>(s)]; }

std::optional<std::uint32_t> SettingMap::raw_of(std::string_view value) const {
  for (const auto& [raw, v] : codes)
    if (v == value) return raw;
  return std::nullopt;
}
std::optional<std::string> SettingMap::value_of(std::uint32_t raw) const {
  for (const auto& [r, v] : codes)
    if (r == raw) return v;
  return std::nullopt;
}

namespace {
constexpr const char* kChecksumSource = "LinRS 3V27 §4.4";
}  // namespace

Result<LinkMap> link_map(const db::Database& db, const std::vector<std::string>& entries) {
  LinkMap m;
  // "UPID: 0x200Eh, Baud Rate Source Select, Value: 0x00000002h, By Parameter",
  // "UPID: 0x2012h, Baud Rate Parameter Def, Value: 0x00000008h, 38400 Baud",
  // "UPID: 0x206Ch, MACID Source Select, Value: 0x00000003h, By Parameter",
  // "UPID: 0x2076h, MACID Parameter Value, Value: 0x00000011h, MACID" (LinRS §10.2).
  m[S::baud_source] = {kBaudRateSource, {{kBaudRateByParameter, "parameter"}}, "seed 003 §10.2"};
  m[S::baud] = {kBaudRateCode, {{8, "38400"}}, "seed 003 §10.2"};
  m[S::macid_source] = {kMacidSource, {{kMacidByParameter, "parameter"}}, "seed 003 §10.2"};
  m[S::macid] = {kMacidValue, {}, "seed 003 §10.2"};
  // The checksum's UPID from a later manual; its raw values from --map only.
  // A --map with another UPID replaces it (a firmware may differ: keep it mappable).
  m[S::checksum] = {kChecksumUpid, {}, kChecksumSource};
  // The database's labels of 2012h ("8=38400 Bit/s"): what a merged firmware
  // profile adds.
  if (const db::Parameter* d = db.find(kBaudRateCode)) {
    for (const auto& l : d->spec.labels) {
      auto rate = parse_raw(l.label.substr(0, l.label.find_first_not_of("0123456789")));
      if (rate && l.raw >= 0 && canonical(S::baud, std::to_string(*rate)).ok())
        put_code(m[S::baud], static_cast<std::uint32_t>(l.raw), std::to_string(*rate));
    }
  }
  for (const auto& e : entries) {
    auto bad = [&](const std::string& why) {
      return Error(Errc::invalid_argument,
                   "--map '" + e + "': " + why +
                       "; expected SETTING[@UPID]:VALUE=RAW[,VALUE=RAW...], e.g. "
                       "checksum@20A0:none=0,add=1,crc=2 or baud:115200=32");
    };
    const auto colon = e.find(':');
    if (colon == std::string::npos) return bad("no ':'");
    std::string head = trim(std::string_view(e).substr(0, colon));
    std::optional<std::uint16_t> upid;
    if (auto at = head.find('@'); at != std::string::npos) {
      auto u = parse_raw(head.substr(at + 1), true);
      if (!u || *u > 0xFFFF) return bad("'" + head.substr(at + 1) + "' is not a UPID in hex");
      upid = static_cast<std::uint16_t>(*u);
      head = trim(head.substr(0, at));
    }
    const auto it = std::find(kKeys.begin(), kKeys.end(), head);
    if (it == kKeys.end())
      return bad("unknown setting '" + head +
                 "' (one of baud-source, baud, id-source, checksum, parity, stop-bits)");
    const auto s = static_cast<S>(it - kKeys.begin());
    if (s == S::macid) return bad("the MACID's raw value is the ID itself: nothing to map");
    SettingMap& sm = m[s];
    if (upid) {
      if (sm.upid && *sm.upid != *upid && sm.source != kChecksumSource)
        return bad("seed 003 §10.2 gives " + std::string(setting_title(s)) + " the UPID " +
                   hex(*sm.upid, 4, "h"));
      sm.upid = upid;
      sm.source = "--map";
    }
    std::string_view rest = std::string_view(e).substr(colon + 1);
    while (!rest.empty()) {
      const auto comma = rest.find(',');
      const std::string item(rest.substr(0, comma));
      rest = comma == std::string_view::npos ? std::string_view() : rest.substr(comma + 1);
      const auto eq = item.find('=');
      if (eq == std::string::npos) return bad("'" + item + "' is not VALUE=RAW");
      auto value = canonical(s, item.substr(0, eq));
      if (!value.ok()) return bad(value.error().message);
      auto raw = parse_raw(item.substr(eq + 1));
      if (!raw) return bad("'" + item.substr(eq + 1) + "' is not a number");
      put_code(sm, *raw, *value);
    }
  }
  return m;
}

Result<void> learn_from_drive(link::Session& session, LinkMap& map) {
  SettingMap& baud = map[S::baud];
  if (!baud.upid || baud.raw_of("57600")) return {};
  auto def = session.client().get_default(*baud.upid);
  if (!def.ok()) {
    if (def.error().code == ErrorClass::drive_refusal) return {};
    return std::move(def).error();
  }
  if (!baud.value_of(*def)) baud.codes.emplace_back(*def, "57600");
  return {};
}

Result<LinkState> read_link_settings(link::Session& session, const LinkMap& map) {
  auto& c = session.client();
  LinkState st;
  st.in_use = {session.line(), c.options().id, c.options().checksum};
  for (std::size_t i = 0; i < kLinkSettings; ++i) {
    const auto s = static_cast<S>(i);
    LinkValue& v = st.values[i];
    v.upid = map[s].upid;
    if (!v.upid) {
      // LinRS §15 names these settings with their choices, no UPID.
      v.note =
          "UPID unknown: seed 003 §15 names the setting but not its UPID; give it with "
          "--map " +
          std::string(setting_key(s)) + "@UPID:VALUE=RAW,...";
      continue;
    }
    auto r = c.read_rom(*v.upid);
    if (!r.ok()) {
      if (r.error().code != ErrorClass::drive_refusal) return std::move(r).error();
      v.note = "the drive refused to read " + hex(*v.upid, 4, "h") + ": " + r.error().message;
      continue;
    }
    v.rom = *r;
    v.text = text_of(map, s, *r);
    v.note = map[s].source;
    if (v.text.empty()) v.note = "raw value " + std::to_string(*r) + " not in the map";
  }
  return st;
}

namespace {

Error refuse(const std::string& option, const std::string& why) {
  return Error(Errc::invalid_argument, option + ": " + why + "; nothing written");
}

// The raw value of `value` for setting `s`, or why the map cannot say.
Result<std::uint32_t> raw_for(const LinkMap& map, S s, const std::string& option,
                              const std::string& value) {
  const SettingMap& m = map[s];
  if (!m.upid)
    return refuse(option, "seed 003 §15 names the " + std::string(setting_title(s)) +
                              " setting but gives neither its UPID nor its raw values; give "
                              "them with --map " +
                              std::string(setting_key(s)) + "@UPID:VALUE=RAW,...");
  auto raw = m.raw_of(value);
  if (!raw && m.codes.empty() && m.source == kChecksumSource)
    return refuse(option,
                  "LinRS 3V27 §4.4 gives the checksum's UPID, 2080h, but no source its "
                  "raw values; give them with --map checksum:VALUE=RAW,...");
  if (!raw)
    return refuse(
        option, "no raw value of " + hex(*m.upid, 4, "h") + " " + std::string(setting_title(s)) +
                    " is known for " + value + " (known: " + code_list(m) +
                    (s == S::baud ? "; seed 003 states only 8 = 38400 Baud, §10.2" : "") +
                    "); give it with --map " + std::string(setting_key(s)) + ":" + value + "=RAW");
  return *raw;
}

std::string checksum_value(const codec::ChecksumConfig& c) {
  return link::checksum_name(codec::ChecksumConfig{c.mode, c.crc_init, {}});
}

}  // namespace

Result<void> check_link_change(const LinkMap& map, const LinkChange& change) {
  if (change.baud) {
    const std::string opt = "--set-baud " + std::to_string(*change.baud);
    auto v = canonical(S::baud, std::to_string(*change.baud));
    if (!v.ok()) return refuse(opt, v.error().message);
    // 57600 is 2012h's default (LinRS §15): learn_from_drive asks the drive.
    if (*v != "57600" || map[S::baud].raw_of(*v)) LMCFG_TRY(raw_for(map, S::baud, opt, *v));
    LMCFG_TRY(raw_for(map, S::baud_source, opt, "parameter"));
  }
  if (change.macid)
    LMCFG_TRY(raw_for(map, S::macid_source, "--set-id " + hex(*change.macid, 2, "h"), "parameter"));
  if (change.checksum) {
    const std::string name = checksum_value(*change.checksum);
    LMCFG_TRY(raw_for(map, S::checksum, "--set-checksum " + name, name));
  }
  if (change.parity) {
    const std::string name(transport::parity_name(*change.parity));
    LMCFG_TRY(raw_for(map, S::parity, "--set-parity " + name, name));
  }
  if (change.stop_bits) {
    const std::string name = std::to_string(*change.stop_bits);
    if (*change.stop_bits != 1 && *change.stop_bits != 2)
      return refuse("--set-stop-bits " + name, "not 1 or 2");
    LMCFG_TRY(raw_for(map, S::stop_bits, "--set-stop-bits " + name, name));
  }
  return {};
}

Result<LinkPlan> plan_link_change(link::Session& session, const LinkMap& map, const LinkState& now,
                                  const LinkChange& change) {
  LinkPlan plan;
  plan.after = now.in_use;
  // One write of setting `s` to `value` (a name of the map, or the MACID).
  auto want = [&](S s, std::uint32_t raw, const std::string& text) {
    const LinkValue& v = now[s];
    if (v.rom && *v.rom == raw) return;
    std::string t = hex(*map[s].upid, 4, "h") + " " + std::string(setting_title(s)) + ": ";
    t += v.rom ? std::to_string(*v.rom) + (v.text.empty() ? "" : " (" + v.text + ")")
               : std::string("?");
    t += " -> " + std::to_string(raw) + " (" + text + ")";
    plan.writes.push_back({s, *map[s].upid, v.rom, raw, std::move(t)});
  };
  auto mapped = [&](S s, const std::string& option,
                    const std::string& value) -> Result<std::uint32_t> {
    LMCFG_ASSIGN_OR_RETURN(auto raw, raw_for(map, s, option, value));
    if (!now[s].rom)
      return refuse(
          option, "the drive did not read " + hex(*map[s].upid, 4, "h") + " (" + now[s].note + ")");
    return raw;
  };
  LMCFG_TRY(check_link_change(map, change));
  // Pairs: the value before its source select, so a power loss between the two
  // writes never activates a half-written pair (as restore --include-comm).
  if (change.baud) {
    const std::string opt = "--set-baud " + std::to_string(*change.baud);
    auto v = canonical(S::baud, std::to_string(*change.baud));
    if (!v.ok()) return refuse(opt, v.error().message);
    LMCFG_ASSIGN_OR_RETURN(auto raw, mapped(S::baud, opt, *v));
    LMCFG_ASSIGN_OR_RETURN(auto src, mapped(S::baud_source, opt, "parameter"));
    want(S::baud, raw, *v);
    want(S::baud_source, src, "By Parameter");
    plan.after.line.baud = *change.baud;
  }
  if (change.macid) {
    const std::string opt = "--set-id " + hex(*change.macid, 2, "h");
    LMCFG_ASSIGN_OR_RETURN(auto src, mapped(S::macid_source, opt, "parameter"));
    if (!now[S::macid].rom)
      return refuse(opt, "the drive did not read 2076h (" + now[S::macid].note + ")");
    if (*change.macid != now.in_use.macid) {
      // "With the RS485 topology also several Slaves can be accessed" (LinRS
      // §3.3): two drives with one MACID would both answer.
      auto& c = session.client();
      auto co = c.options();
      const auto saved = co;
      co.id = *change.macid;
      co.read_retries = 0;
      c.set_options(co);
      auto answer = c.default_response();
      c.set_options(saved);
      if (answer.ok() || answer.error().code == ErrorClass::drive_refusal)
        return refuse(opt, "a drive already answers as MACID " + hex(*change.macid, 2, "h") +
                               " on this line");
    }
    want(S::macid, *change.macid, hex(*change.macid, 2, "h"));
    want(S::macid_source, src, "By Parameter");
    plan.after.macid = *change.macid;
  }
  if (change.checksum) {
    const std::string name = link::checksum_name(
        codec::ChecksumConfig{change.checksum->mode, change.checksum->crc_init, {}});
    const std::string opt = "--set-checksum " + name;
    LMCFG_ASSIGN_OR_RETURN(auto raw, mapped(S::checksum, opt, name));
    want(S::checksum, raw, name);
    plan.after.checksum = *change.checksum;
    plan.after.checksum.coverage = now.in_use.checksum.coverage;
  }
  if (change.parity) {
    const std::string name(transport::parity_name(*change.parity));
    const std::string opt = "--set-parity " + name;
    LMCFG_ASSIGN_OR_RETURN(auto raw, mapped(S::parity, opt, name));
    want(S::parity, raw, name);
    plan.after.line.parity = *change.parity;
  }
  if (change.stop_bits) {
    const std::string name = std::to_string(*change.stop_bits);
    const std::string opt = "--set-stop-bits " + name;
    if (*change.stop_bits != 1 && *change.stop_bits != 2) return refuse(opt, "not 1 or 2");
    LMCFG_ASSIGN_OR_RETURN(auto raw, mapped(S::stop_bits, opt, name));
    want(S::stop_bits, raw, name);
    plan.after.line.stop_bits = *change.stop_bits;
  }
  return plan;
}

namespace {

// The recovery record of a link change (the values before it), saved before
// the first write; returns the sentence that names it in every error.
Result<std::string> save_link_record(const LinkPlan& plan, const std::string& port,
                                     const std::filesystem::path& recovery,
                                     const link::RelinkCandidate& before) {
  RecoveryRecord rec;
  rec.command = "link";
  rec.port = port;
  rec.macid = before.macid;
  rec.created = utc_now();
  rec.expect = link::link_options_of(plan.after);
  for (const auto& w : plan.writes)
    if (w.old_value) rec.keep.push_back({w.upid, *w.old_value});
  LMCFG_TRY(save_recovery(recovery, rec));
  return "the recovery record " + recovery.string() + " holds the previous values (" +
         link::link_options_of(before) + ")";
}

// MC stopped, the ROM values written, the drive reset.
Result<void> write_and_reset(client::Client& c, const LinkPlan& plan,
                             const link::RelinkCandidate& before, const std::string& kept) {
  // "For configuring it is needed to stop the MC-SW of the servo controller
  // first" (LinRS §10). "The configuration parameters affects the behavior of
  // its SW instance only after a restart of it. A Reset command or Power cycle
  // restarts all SW instances" (LinRS §9): only ROM is written, and the reset
  // makes it the drive's settings.
  if (auto r = c.stop_mc(); !r.ok()) {
    Error e = std::move(r).error();
    e.message = "stopping MC failed, nothing written: " + e.message + "; " + kept;
    return e;
  }
  for (std::size_t i = 0; i < plan.writes.size(); ++i) {
    const auto& w = plan.writes[i];
    if (auto r = c.write_rom_confirmed(w.upid, w.value); !r.ok()) {
      Error e = std::move(r).error();
      (void)c.start_mc();  // leave MC as found; the written values act only after a reset
      e.message = "write " + std::to_string(i + 1) + " of " + std::to_string(plan.writes.size()) +
                  " (" + w.text + ") failed: " + e.message + ". The drive still talks at " +
                  link::link_options_of(before) + " until its next reset, with " +
                  std::to_string(i) + " value(s) written to ROM; " + kept +
                  ": run the same command again";
      return e;
    }
  }
  // "Reset Servo Controller Completely (restart of all SW instances) with
  // response after reset completion" (LinRS §13): the answer comes after the
  // restart, already at the new settings, so a lost answer is expected.
  if (auto r = c.reset(std::min(c.options().reset_timeout, c.options().relink_reset_timeout));
      !r.ok() && r.error().code != ErrorClass::link_failure) {
    Error e = std::move(r).error();
    e.message = "reset refused after writing every value: " + e.message + "; " + kept;
    return e;
  }
  return {};
}

// The drive after its reset: at the planned settings, else found by scanning
// its MACID; not found: the link goes back to the settings before.
Result<void> find_again(link::Session& session, const LinkPlan& plan,
                        const link::RelinkCandidate& before, const std::string& port,
                        const std::string& kept, LinkApplyReport& rep) {
  link::ExpectedLink expected;
  expected.baud = plan.after.line.baud;
  expected.macid = plan.after.macid;
  link::RelinkOverrides o;
  o.checksum = plan.after.checksum;
  o.parity = plan.after.line.parity;
  o.stop_bits = plan.after.line.stop_bits;
  // A drive silent for a while after its reset (field reports, C1250 notes) is
  // looked for again until recover_timeout, before the scan.
  auto found =
      link::reconnect_within(session, expected, o, session.client().options().recover_timeout);
  if (found.ok()) {
    rep.relink = std::move(found).value();
    return {};
  }
  if (found.error().code != ErrorClass::link_failure) return std::move(found).error();
  // Scanning if it must: the drive's MACID at every rate, checksum variant and
  // parity, in case the firmware reads a raw value otherwise than the map.
  link::ScanOptions so;
  so.first_id = so.last_id = plan.after.macid;
  so.checksum = plan.after.checksum;
  auto sc = link::scan(session, so);
  if (sc.ok() && !sc->found.empty()) {
    const link::FoundDrive& d = sc->found.front();
    if (auto r = session.relink(d.line, d.id, d.checksum); !r.ok()) return std::move(r).error();
    rep.scanned = true;
    rep.relink.changed = true;
    rep.relink.used = {d.line, d.id, d.checksum};
    rep.relink.summary = "the drive answers at " + link::link_options_of(rep.relink.used) +
                         " (found by scanning MACID " + hex(d.id, 2, "h") + ")";
    return {};
  }
  (void)session.relink(before.line, before.macid, before.checksum);
  std::string written;
  for (const auto& w : plan.writes)
    written +=
        (written.empty() ? "" : ", ") + hex(w.upid, 4, "h") + " = " + std::to_string(w.value);
  return Error(
      Errc::timeout,
      "written and reset, but the drive was not found again: " + found.error().message +
          "; a scan of MACID " + hex(plan.after.macid, 2, "h") +
          " at every rate, checksum and parity found nothing. The drive holds " + written +
          " in ROM and restarted with them (expected: " + link::link_options_of(plan.after) +
          "); " + kept + ". Find it with: lmcfg scan --port " + port);
}

// Verify: the ROM values the drive now holds.
Result<void> read_back(link::Session& session, const LinkMap& map, const LinkPlan& plan,
                       const std::string& kept, LinkApplyReport& rep) {
  auto after = read_link_settings(session, map);
  if (!after.ok()) {
    Error e = std::move(after).error();
    e.message = "the drive answers at " + link::link_options_of(rep.relink.used) +
                " but reading its settings back failed: " + e.message + "; " + kept;
    return e;
  }
  rep.after = std::move(after).value();
  for (const auto& w : plan.writes) {
    const LinkValue& v = rep.after[w.setting];
    if (!v.rom || *v.rom != w.value)
      return Error(Errc::verify_mismatch,
                   "the drive answers at " + link::link_options_of(rep.relink.used) + " but " +
                       hex(w.upid, 4, "h") + " reads back " +
                       (v.rom ? std::to_string(*v.rom) : std::string("nothing")) + ", not " +
                       std::to_string(w.value) + "; " + kept);
  }
  return {};
}

}  // namespace

Result<LinkApplyReport> apply_link_change(link::Session& session, const LinkMap& map,
                                          const LinkPlan& plan, const std::string& port,
                                          const std::filesystem::path& recovery) {
  auto& c = session.client();
  const link::RelinkCandidate before{session.line(), c.options().id, c.options().checksum};
  LMCFG_ASSIGN_OR_RETURN(const std::string kept, save_link_record(plan, port, recovery, before));
  LMCFG_TRY(write_and_reset(c, plan, before, kept));
  LinkApplyReport rep;
  LMCFG_TRY(find_again(session, plan, before, port, kept, rep));
  LMCFG_TRY(read_back(session, map, plan, kept, rep));
  LMCFG_TRY(remove_recovery(recovery));
  return rep;
}

}  // namespace lmcfg::ops
