#include "ops/backup.hpp"

#include <algorithm>
#include <ctime>
#include <set>

#include "common/layers.hpp"
#include "common/utc_time.hpp"
#include "common/version.hpp"
#include "db/database.hpp"

namespace lmcfg::ops {

std::string utc_now() {
  std::time_t t = std::time(nullptr);
  const std::tm tm = utc_tm(t);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

std::string display_value(const db::Database& db, std::uint16_t upid, std::uint32_t value,
                          std::optional<std::uint8_t> type, std::string_view profile) {
  const db::Parameter* d = db.find(upid, profile);
  db::ValueSpec spec = d ? d->spec : db::ValueSpec{};
  if (!spec.type && type) spec.type = db::type_from_code(*type);
  const bool labelled = std::any_of(
      spec.labels.begin(), spec.labels.end(),
      [&](const db::EnumLabel& l) { return l.raw == static_cast<std::int64_t>(value); });
  if (spec.type || labelled) return db::format_value(spec, value);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%u (%04Xh)", value, value);
  return buf;
}

void annotate(config::DriveConfig& cfg, const db::Database& db) {
  const families::Family* fam = families::find(cfg.identity.product);
  const std::string_view profile = fam ? fam->profile : std::string_view();
  for (auto& layer : cfg.layers) {
    for (auto& p : layer) {
      const db::Parameter* d = db.find(p.upid, profile);
      if (!d) {
        if (p.type) p.scaled = display_value(db, p.upid, p.value, p.type, profile);
        continue;
      }
      p.name = d->name;
      p.unit = d->spec.unit;
      if (!p.type && d->spec.type) p.type = static_cast<std::uint8_t>(*d->spec.type);
      if (!p.default_value && d->default_value)
        p.default_value = static_cast<std::uint32_t>(*d->default_value);
      p.scaled = display_value(db, p.upid, p.value, p.type, profile);
    }
  }
}

namespace {

// FNV-1a 64 over (UPID, address usage, type) of every listed UPID: identifies
// the drive's UPID set (firmware) without listing it.
std::string fingerprint(const std::vector<client::UpidInfo>& all) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  auto mix = [&](std::uint16_t v) {
    for (int i = 0; i < 2; ++i) {
      h ^= static_cast<std::uint8_t>(v >> (8 * i));
      h *= 0x100000001b3ull;
    }
  };
  for (const auto& u : all) {
    mix(u.upid);
    mix(u.address_usage);
    mix(u.type);
  }
  char buf[40];
  std::snprintf(buf, sizeof buf, "fnv1a64:%016llx", static_cast<unsigned long long>(h));
  return buf;
}

std::string form_name(std::uint8_t state) {
  if (state == 0) return "state 00h and size 0";
  char buf[48];
  std::snprintf(buf, sizeof buf, "error state %02Xh", state);
  return buf;
}

void report(const Progress& p, const std::string& phase, std::size_t done, std::size_t total) {
  if (p) p(phase, done, total);
}

std::optional<std::uint8_t> file_type_code(std::uint16_t drive_type) {
  if (!db::type_from_code(drive_type)) return std::nullopt;  // not a §10 type code: stays unknown
  return static_cast<std::uint8_t>(drive_type);
}

// Types and defaults of the captured parameters that the database does not
// know, from the drive (§10 05h 04h / 07h). In a full capture the type came
// with the UPID list and a UPID outside the modified list holds its default.
Result<void> describe_from_drive(client::Client& c, const db::Database& db, int layer,
                                 std::vector<config::Parameter>& params,
                                 const std::set<std::uint16_t>* modified,
                                 const BackupOptions& opt) {
  const Progress& progress = opt.progress;
  // DCF p8: a B1100 stores no defaults, so none is asked.
  const bool defaults = !opt.family || opt.family->stored_defaults;
  const std::string phase = "types and defaults " + std::string(lmcfg::layers::name(layer));
  std::size_t n = 0;
  for (auto& p : params) {
    report(progress, phase, ++n, params.size());
    const db::Parameter* d = db.find(p.upid);
    if (!p.type && !(d && d->spec.type)) {
      LMCFG_ASSIGN_OR_RETURN(auto t, unless_refused(c.get_type(p.upid)));
      if (t) p.type = file_type_code(*t);
    }
    if (defaults && !p.default_value && !(d && d->default_value)) {
      if (modified && !modified->count(p.upid)) {
        p.default_value = p.value;
      } else {
        LMCFG_ASSIGN_OR_RETURN(p.default_value, unless_refused(c.get_default(p.upid)));
      }
    }
  }
  return {};
}

// One layer's parameters: the modified list (and what the drive says of
// their types and defaults), or with `full` every ROM-writable UPID of the
// UPID list (collected into `all_upids` for the fingerprint).
Result<void> read_layer(client::Client& c, const BackupOptions& opt, const db::Database& db,
                        int layer, config::DriveConfig& cfg,
                        std::vector<client::UpidInfo>& all_upids) {
  const std::string phase = "parameters " + std::string(lmcfg::layers::name(layer));
  auto& out = cfg.layer(layer);
  if (!opt.full) {
    LMCFG_ASSIGN_OR_RETURN(auto mods, c.modified_list(layer));
    for (const auto& m : mods)
      out.push_back(config::Parameter{m.upid, m.value, std::nullopt, std::nullopt, {}, {}, {}});
    report(opt.progress, phase, mods.size(), mods.size());
    if (opt.ask_drive) LMCFG_TRY(describe_from_drive(c, db, layer, out, nullptr, opt));
    return {};
  }
  LMCFG_ASSIGN_OR_RETURN(auto list, c.upid_list(layer, [&](std::size_t n) {
    report(opt.progress, phase + " list", n, 0);
  }));
  all_upids.insert(all_upids.end(), list.begin(), list.end());
  auto rom_write = [](const client::UpidInfo& u) {
    return db::AddressUsage{u.address_usage}.rom_write();
  };
  const auto rom_writable =
      static_cast<std::size_t>(std::count_if(list.begin(), list.end(), rom_write));
  for (const auto& u : list) {
    if (!rom_write(u)) continue;  // bit 3 ROM write (§10.3: only those form a configuration)
    LMCFG_ASSIGN_OR_RETURN(auto v, c.read_rom(u.upid));
    out.push_back(config::Parameter{u.upid, v, file_type_code(u.type), std::nullopt, {}, {}, {}});
    report(opt.progress, phase, out.size(), rom_writable);
  }
  if (opt.ask_drive) {
    LMCFG_ASSIGN_OR_RETURN(auto mods, c.modified_list(layer));
    std::set<std::uint16_t> modified;
    for (const auto& m : mods) modified.insert(m.upid);
    LMCFG_TRY(describe_from_drive(c, db, layer, out, &modified, opt));
  }
  return {};
}

// The sentence for people on how far a value read from this link can be
// trusted: whether the link detects a flipped bit, and how many agreeing reads
// each value took. Empty: nothing to say.
std::string reads_note(const client::Client& c, int reads_per_value) {
  const bool detects_flips =
      c.options().checksum.mode != codec::ChecksumMode::none || c.options().link_has_parity;
  const bool fixed = c.options().agreeing_reads > 0;
  const std::string n = std::to_string(reads_per_value);
  if (detects_flips) {
    if (reads_per_value > 1)
      return "each value read until " + n + " reads agreed (--agreeing-reads " + n + ")";
    return "";
  }
  if (reads_per_value == 1) {
    return "no checksum on this link and --agreeing-reads 1: a flipped bit in a value goes into "
           "the file undetected; enable CRC on the drive (§15)";
  }
  if (fixed) {
    return "no checksum on this link: each value read until " + n +
           " reads agreed (--agreeing-reads " + n + ")" +
           (c.noise_seen() && reads_per_value == 2
                ? "; the line corrupted answers, and the same flipped bit in two answers goes "
                  "unnoticed (auto reads 3 here)"
                : "");
  }
  if (reads_per_value == 2) {
    return "no checksum on this link: each value read twice; enable CRC on the drive (§15) to "
           "halve backup time";
  }
  return "no checksum on this link, and it corrupted answers: each value read until " + n +
         " reads agreed; enable CRC on the drive (§15) to read each value once";
}

// BackupOptions::report: how the values were read, and the notes for people.
void fill_report(const client::Client& c, const std::vector<std::string>& notes, BackupReport& r) {
  r.reads_per_value = c.agreeing_reads();
  r.empty_curve_form = c.probe_forms().empty_curve;
  r.empty_ct_form = c.probe_forms().empty_ct_entry;
  if (auto note = reads_note(c, r.reads_per_value); !note.empty()) r.notes.push_back(note);
  if (r.empty_curve_form && *r.empty_curve_form != 0) {
    r.notes.push_back("this drive answers a probe of an empty curve ID with " +
                      form_name(*r.empty_curve_form) + " (taken as: no curve there)");
  }
  r.notes.insert(r.notes.end(), notes.begin(), notes.end());
}

}  // namespace

bool no_such_group(const Error& e) { return e.code == make_comm_state_error(0xC3); }

Result<std::vector<config::Curve>> read_curves(client::Client& c, std::uint16_t max_curve_id,
                                               const Progress& progress, const std::string& phase,
                                               bool* no_group) {
  std::vector<config::Curve> out;
  for (std::uint16_t id = 1; id <= max_curve_id; ++id) {
    report(progress, phase, id, max_curve_id);
    auto read = c.read_curve(id);
    if (!read.ok() && id == 1 && no_group && no_such_group(read.error())) {
      *no_group = true;  // the group's first request answered C3h
      return out;
    }
    if (!read.ok()) return std::move(read).error();
    if (*read) out.push_back(config::Curve{id, std::move((*read)->info), std::move((*read)->data)});
  }
  return out;
}

Result<std::vector<config::CtEntry>> read_command_table(client::Client& c, const Progress& progress,
                                                        const std::string& phase,
                                                        std::vector<std::string>& notes,
                                                        bool* no_group) {
  std::vector<config::CtEntry> out;
  auto listed = c.ct_defined_entries();  // the group's first request: the list's first block
  if (!listed.ok() && no_group && no_such_group(listed.error())) {
    *no_group = true;
    return out;
  }
  LMCFG_ASSIGN_OR_RETURN(auto entries, std::move(listed));
  std::size_t n = 0;
  for (auto e : entries) {
    report(progress, phase, ++n, entries.size());
    LMCFG_ASSIGN_OR_RETURN(auto raw, c.probe_ct_entry(e));
    if (!raw) {
      // Listed as defined, but the entry query says nothing is there.
      notes.push_back("command table entry " + std::to_string(e) +
                      ": listed as defined, but the drive answers its query with " +
                      form_name(*c.probe_forms().empty_ct_entry) + ": left out");
      continue;
    }
    out.push_back(config::CtEntry{e, std::move(*raw)});
  }
  return out;
}

config::DriveConfig new_capture(const client::Client& c, const db::Database& db) {
  config::DriveConfig cfg;
  char macid[8];
  std::snprintf(macid, sizeof macid, "0x%02X", c.options().id);
  cfg.identity.macid = macid;
  cfg.identity.tool_version = kToolVersion;
  cfg.identity.captured_at = utc_now();
  if (!db.is_empty()) cfg.identity.upid_db_hash = db.info().content_hash;
  if (!db.is_empty()) cfg.identity.upid_db_version = std::to_string(db.info().schema_version);
  cfg.scope.layers = {false, false, false, false};
  cfg.scope.parameters = config::ParamSet::modified;
  cfg.scope.curves = false;
  cfg.scope.command_table = false;
  return cfg;
}

namespace {
// What the family leaves out, said (LinRS 3V27 §11-§12, p32; DCF p8; C1250 notes).
std::vector<std::string> family_notes(const BackupOptions& opt, const families::Family& f) {
  std::vector<std::string> n;
  const std::string name(f.name);
  if (opt.curves && !f.curves)
    n.push_back(name + " has no curve group (LinRS 3V27 §11): curves not asked, not in the file");
  if (opt.command_table && !f.command_table)
    n.push_back(name +
                " has no command table group (LinRS 3V27 §12): command table not asked, not in "
                "the file");
  if (opt.ask_drive && !f.stored_defaults)
    n.push_back(name + " stores no default values (DCF p8): defaults not asked");
  return n;
}

// "--family B1100": the families without the group, for the note.
std::string family_options_without(bool families::Family::*group) {
  std::string out;
  for (const auto& f : families::all())
    if (!(f.*group)) out += (out.empty() ? "--family " : " or ") + std::string(f.name);
  return out.empty() ? "--family" : out;
}

// A group the drive answered C3h for: out of scope, recorded, said.
void lacks_group(config::DriveConfig& cfg, std::vector<std::string>& notes, bool curves) {
  const std::string what = curves ? "curve" : "command table";
  const std::string option =
      family_options_without(curves ? &families::Family::curves : &families::Family::command_table);
  (curves ? cfg.scope.curves : cfg.scope.command_table) = false;
  cfg.scope.drive_lacks.push_back(curves ? "curves" : "command_table");
  notes.push_back("the drive has no " + what +
                  " group (it answers C3h undefined message main ID, LinRS §16.1): " +
                  (curves ? "curves" : "the command table") + " not in the file; " + option +
                  " says so up front");
}
}  // namespace

Result<config::DriveConfig> backup(client::Client& c, const BackupOptions& opt,
                                   const db::Database& db) {
  config::DriveConfig cfg = new_capture(c, db);
  const families::Family& fam = opt.family ? *opt.family : families::reference();
  const bool curves = opt.curves && fam.curves;
  const bool command_table = opt.command_table && fam.command_table;
  cfg.scope.layers = opt.layers;
  cfg.scope.parameters = opt.full ? config::ParamSet::full : config::ParamSet::modified;
  cfg.scope.curves = curves;
  cfg.scope.command_table = command_table;
  if (opt.family) cfg.identity.product = std::string(fam.name);
  if (opt.curves && !fam.curves) cfg.scope.drive_lacks.push_back("curves");
  if (opt.command_table && !fam.command_table) cfg.scope.drive_lacks.push_back("command_table");

  std::vector<client::UpidInfo> all_upids;
  std::vector<std::string> notes = family_notes(opt, fam);
  for (int layer = 1; layer <= 4; ++layer) {
    if (!opt.layers[static_cast<std::size_t>(layer - 1)]) continue;
    LMCFG_TRY(read_layer(c, opt, db, layer, cfg, all_upids));
  }
  if (opt.full) cfg.identity.upid_fingerprint = fingerprint(all_upids);
  if (curves) {
    const auto limit =
        static_cast<std::uint16_t>(std::min<unsigned>(opt.max_curve_id, fam.curve_limit));
    bool none = false;
    LMCFG_ASSIGN_OR_RETURN(cfg.curves, read_curves(c, limit, opt.progress, "curves", &none));
    if (none) lacks_group(cfg, notes, true);
  }
  if (command_table) {
    bool none = false;
    LMCFG_ASSIGN_OR_RETURN(cfg.ct_entries,
                           read_command_table(c, opt.progress, "command table", notes, &none));
    if (none) lacks_group(cfg, notes, false);
  }
  if (opt.report) fill_report(c, notes, *opt.report);
  if (!db.is_empty()) annotate(cfg, db);
  config::canonicalize(cfg);
  return cfg;
}

}  // namespace lmcfg::ops

#include "db/ct_entry.hpp"

namespace lmcfg::ops {

std::optional<config::CtEntryView> DatabaseCtDecoder::decode(std::uint32_t, ByteView raw) const {
  auto e = db::decode_ct_entry(db_, raw);
  if (e.ok() && !e->version_note.empty()) {
    config::CtEntryView v;
    v.summary = e->version_note;  // said, not decoded with the wrong layout
    return v;
  }
  if (!e.ok() || !e->command) return std::nullopt;
  config::CtEntryView v;
  v.summary = e->summary();
  for (const auto& p : e->params) {
    const auto space = p.text.find(' ');
    v.params.push_back(
        config::CtParam{p.name, p.text.substr(0, space),
                        space == std::string::npos ? std::string() : p.text.substr(space + 1)});
  }
  return v;
}

}  // namespace lmcfg::ops
