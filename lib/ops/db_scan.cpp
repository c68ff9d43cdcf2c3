#include "ops/db_scan.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/bytes.hpp"
#include "common/layers.hpp"
#include "config/atomic_file.hpp"
#include "db/tsv.hpp"

namespace lmcfg::ops {

namespace {

namespace fs = std::filesystem;

constexpr const char* kPartialHeader = "# lmcfg db scan partial state, version 1";
constexpr const char* kScannedSource = "scanned from a drive";
constexpr const char* kProfilesMark = "#@profiles.tsv\t";

std::optional<std::uint32_t> parse_hex(std::string_view s, std::size_t digits) {
  if (s.size() != digits) return std::nullopt;
  std::uint32_t v = 0;
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v, 16);
  if (ec != std::errc() || p != s.data() + s.size()) return std::nullopt;
  return v;
}

using db::tsv::field;
using db::tsv::is_data_line;
using db::tsv::join;
using db::tsv::split;

bool is_scanned_source(std::string_view source) { return source.rfind(kScannedSource, 0) == 0; }

std::string limit_text(const std::optional<std::uint32_t>& v) { return v ? hex(*v, 8) : "-"; }

std::string partial_line(const ScannedUpid& u) {
  return hex(u.upid, 4) + "\t" + hex(u.address_usage, 4) + "\t" + hex(u.type, 4) + "\t" +
         limit_text(u.limits.min) + "\t" + limit_text(u.limits.max) + "\t" +
         limit_text(u.limits.def) + "\n";
}

std::optional<ScannedUpid> parse_partial_line(std::string_view line) {
  auto f = split(line);
  if (f.size() != 6) return std::nullopt;
  auto upid = parse_hex(f[0], 4), au = parse_hex(f[1], 4), type = parse_hex(f[2], 4);
  if (!upid || !au || !type) return std::nullopt;
  ScannedUpid u{static_cast<std::uint16_t>(*upid),
                static_cast<std::uint16_t>(*au),
                static_cast<std::uint16_t>(*type),
                {}};
  std::optional<std::uint32_t>* dst[3] = {&u.limits.min, &u.limits.max, &u.limits.def};
  for (int i = 0; i < 3; ++i) {
    std::string_view t = f[static_cast<std::size_t>(3 + i)];
    if (t == "-") continue;
    auto v = parse_hex(t, 8);
    if (!v) return std::nullopt;
    *dst[i] = *v;
  }
  return u;
}

}  // namespace

// ---------------------------------------------------------------- stores

std::optional<ScannedLimits> MemoryScanStore::find(std::uint16_t upid, std::uint16_t type,
                                                   std::uint16_t address_usage) const {
  auto it = std::lower_bound(entries_.begin(), entries_.end(), upid,
                             [](const ScannedUpid& e, std::uint16_t u) { return e.upid < u; });
  if (it == entries_.end() || it->upid != upid || it->type != type ||
      it->address_usage != address_usage)
    return std::nullopt;
  return it->limits;
}

Result<void> MemoryScanStore::add(const ScannedUpid& u) {
  auto it = std::lower_bound(entries_.begin(), entries_.end(), u.upid,
                             [](const ScannedUpid& e, std::uint16_t x) { return e.upid < x; });
  if (it != entries_.end() && it->upid == u.upid)
    *it = u;
  else
    entries_.insert(it, u);
  return {};
}

Result<std::unique_ptr<PartialFileStore>> PartialFileStore::open(const std::string& path,
                                                                 const std::string& profile) {
  std::unique_ptr<PartialFileStore> s(new PartialFileStore());
  s->path_ = path;
  std::error_code ec;
  const bool exists = fs::exists(path, ec);
  if (exists) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return Error(Errc::file_error, path + ": cannot read the partial scan state");
    std::stringstream ss;
    ss << in.rdbuf();
    const std::string text = ss.str();
    bool have_profile = false, any = false;
    for (std::string_view line : db::tsv::lines(text)) {
      if (line.empty() || line[0] == '#') continue;
      any = true;
      if (line.rfind("profile\t", 0) == 0) {
        std::string p(line.substr(8));
        if (p != profile) {
          return Error(Errc::invalid_argument,
                       path + ": partial scan state of profile '" + p + "', not '" + profile +
                           "'; rerun with --profile " + p + " or delete the file to start over");
        }
        have_profile = true;
      } else if (auto u = parse_partial_line(line)) {
        (void)s->mem_.add(*u);
      }
    }
    if (any && !have_profile)
      return Error(Errc::invalid_argument, path + ": not a partial scan state of lmcfg db scan");
    s->loaded_ = s->mem_.size();
    s->f_ = std::fopen(path.c_str(), "ab");
    if (!s->f_) return Error(Errc::file_error, path + ": cannot append to the partial scan state");
    // A torn last line (no newline) must not glue onto the next record.
    if (!text.empty() && text.back() != '\n') std::fputc('\n', s->f_);
    if (!have_profile) std::fprintf(s->f_, "%s\nprofile\t%s\n", kPartialHeader, profile.c_str());
  } else {
    s->f_ = std::fopen(path.c_str(), "wb");
    if (!s->f_) return Error(Errc::file_error, path + ": cannot create the partial scan state");
    std::fprintf(s->f_, "%s\nprofile\t%s\n", kPartialHeader, profile.c_str());
  }
  if (std::fflush(s->f_) != 0)
    return Error(Errc::file_error, path + ": cannot write the partial scan state");
  return s;
}

PartialFileStore::~PartialFileStore() {
  if (f_) std::fclose(f_);
}

std::optional<ScannedLimits> PartialFileStore::find(std::uint16_t upid, std::uint16_t type,
                                                    std::uint16_t address_usage) const {
  return mem_.find(upid, type, address_usage);
}

Result<void> PartialFileStore::add(const ScannedUpid& u) {
  (void)mem_.add(u);
  if (!f_) return Error(Errc::file_error, path_ + ": partial scan state is closed");
  const std::string line = partial_line(u);
  if (std::fwrite(line.data(), 1, line.size(), f_) != line.size() || std::fflush(f_) != 0)
    return Error(Errc::file_error, path_ + ": cannot append to the partial scan state");
  return {};
}

Result<void> PartialFileStore::remove() {
  if (f_) std::fclose(f_);
  f_ = nullptr;
  std::error_code ec;
  fs::remove(path_, ec);
  if (ec) return Error(Errc::file_error, path_ + ": cannot delete: " + ec.message());
  return {};
}

// ---------------------------------------------------------------- scan

Result<void> check_scan_profile_id(const std::string& id, const db::Database& db) {
  if (id.empty())
    return Error(Errc::invalid_argument, "a profile id is required (e.g. e1100-fw-x)");
  for (char ch : id) {
    const bool ok = (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') ||
                    (ch >= '0' && ch <= '9') || ch == '-' || ch == '_' || ch == '.';
    if (!ok) {
      return Error(Errc::invalid_argument,
                   "profile id '" + id +
                       "' may only contain letters, digits, '-', '_' and '.' (e.g. e1100-fw-x)");
    }
  }
  if (!db.is_empty()) {
    if (const auto* p = db.profile(id); p && !is_scanned_source(p->prov.source)) {
      return Error(Errc::invalid_argument,
                   "profile '" + id + "' is already defined in the UPID database (" + p->prov.file +
                       ":" + std::to_string(p->prov.line) + ", source \"" + p->prov.source +
                       "\"); choose a new id for the scanned profile");
    }
  }
  return {};
}

namespace {

bool is_refusal(const Error& e) { return e.code == ErrorClass::drive_refusal; }

ScanRow make_row(const ScannedUpid& s, const db::Database& db, const std::string& names_from) {
  ScanRow row;
  row.scanned = s;
  if (db.is_empty()) return row;
  const db::Parameter* p = db.find(s.upid, names_from);
  if (!p) return row;
  row.known = true;
  row.name = p->name;
  row.path = p->path;
  row.unit = p->spec.unit;
  row.scale = p->spec.scale;
  row.labels = p->spec.labels;
  row.comm = p->comm;
  return row;
}

// Raw field -> the decimal FORMAT.md wants: integer types decoded (masked,
// sign-extended), the others as the unsigned field.
std::int64_t value_of(std::uint16_t type, std::uint32_t raw) {
  auto t = db::type_from_code(type);
  if (t && db::type_range(*t)) return db::decode_value(*t, raw).integer;
  return static_cast<std::int64_t>(raw);
}

std::string scale_text(double v) {
  char b[64];
  auto [p, ec] = std::to_chars(b, b + sizeof b, v, std::chars_format::fixed);
  if (ec != std::errc()) {
    std::snprintf(b, sizeof b, "%.17g", v);
    return b;
  }
  return std::string(b, p);
}

}  // namespace

Result<DbScanResult> scan_drive_profile(client::Client& c, const db::Database& db,
                                        const DbScanOptions& opt) {
  LMCFG_TRY(check_scan_profile_id(opt.profile.id, db));
  DbScanResult r;
  r.profile = opt.profile;
  if (!opt.names_from.empty() && !db.is_empty()) {
    const auto* known = db.profile(opt.names_from);
    if (!known) {
      return Error(Errc::invalid_argument,
                   "--names-from: profile '" + opt.names_from + "' is not in the UPID database");
    }
    if (r.profile.family.empty()) r.profile.family = known->family;
    if (r.profile.software.empty()) r.profile.software = known->software;
  }
  const std::string date = opt.date.empty() ? utc_now().substr(0, 10) : opt.date;
  r.source = std::string(kScannedSource) + ": " + opt.profile.id + " " + date + " MACID " +
             hex(c.options().id, 2) + "h";

  // 1. The UPID list of each layer (§10.3). Always walked: the cursor is on the drive.
  std::vector<client::UpidInfo> all;
  for (int layer = lmcfg::layers::kOS; layer <= lmcfg::layers::kAppl; ++layer) {
    if (!opt.layers[static_cast<std::size_t>(layer - 1)]) continue;
    const std::string phase = "UPID list " + std::string(lmcfg::layers::name(layer));
    auto list = c.upid_list(layer, [&](std::size_t n) {
      if (opt.progress) opt.progress(phase, n, 0);
    });
    if (!list.ok()) return std::move(list).error();
    r.per_layer[static_cast<std::size_t>(layer - 1)] = list->size();
    all.insert(all.end(), list->begin(), list->end());
  }
  std::sort(all.begin(), all.end(),
            [](const client::UpidInfo& a, const client::UpidInfo& b) { return a.upid < b.upid; });
  all.erase(std::unique(all.begin(), all.end(),
                        [](const client::UpidInfo& a, const client::UpidInfo& b) {
                          return a.upid == b.upid;
                        }),
            all.end());

  // 2. min, max, default of each UPID (05h/06h/07h), unless the store has them.
  const std::string phase = "min/max/default";
  if (opt.progress) opt.progress(phase, 0, all.size());
  std::size_t done = 0;
  for (const auto& u : all) {
    ScannedUpid s{u.upid, u.address_usage, u.type, {}};
    std::optional<ScannedLimits> stored;
    if (opt.store) stored = opt.store->find(u.upid, u.type, u.address_usage);
    if (stored) {
      s.limits = *stored;
      ++r.resumed;
    } else {
      using Getter = Result<std::uint32_t> (client::Client::*)(std::uint16_t);
      const std::pair<Getter, std::optional<std::uint32_t>*> asks[3] = {
          {&client::Client::get_min, &s.limits.min},
          {&client::Client::get_max, &s.limits.max},
          {&client::Client::get_default, &s.limits.def}};
      for (const auto& [get, dst] : asks) {
        auto v = (c.*get)(u.upid);
        if (v.ok()) {
          *dst = *v;
        } else if (is_refusal(v.error())) {
          ++r.refused;
        } else {
          return std::move(v).error();
        }
      }
      if (opt.store) LMCFG_TRY(opt.store->add(s));
      ++r.asked;
    }
    ScanRow row = make_row(s, db, opt.names_from);
    if (row.known) ++r.named;
    r.rows.push_back(std::move(row));
    if (opt.progress) opt.progress(phase, ++done, all.size());
  }
  return r;
}

// ---------------------------------------------------------------- fragment

std::string scan_fragment_tsv(const DbScanResult& r) {
  const std::string& id = r.profile.id;
  std::string desc = r.profile.description;
  if (desc.empty()) {
    desc =
        "Parameter set scanned from a drive with lmcfg db scan: " + std::to_string(r.rows.size()) +
        " UPIDs (OS " + std::to_string(r.per_layer[0]) + ", MC " + std::to_string(r.per_layer[1]) +
        ", Intf " + std::to_string(r.per_layer[2]) + ", Appl " + std::to_string(r.per_layer[3]) +
        "); type, address usage, min, max and default as the drive reports them; names, paths, "
        "units, scales, "
        "enum labels and comm flags copied from the UPID database for " +
        std::to_string(r.named) + " known UPIDs.";
  }
  std::string out;
  out +=
      "# upid-db fragment written by `lmcfg db scan` (format: upid-db/FORMAT.md; merging: "
      "docs/upid-db.md).\n";
  out += "# " + field(r.source) + "\n";
  out +=
      "# The #@profiles.tsv lines are the header and the row for profiles.tsv; the table below is "
      "in\n";
  out += "# parameters.tsv format. Merge both with: lmcfg db merge <this file> --into upid-db\n";
  out += kProfilesMark + join(db::tsv::profile_columns()) + "\n";
  out += kProfilesMark +
         join({field(id), field(r.profile.family), field(r.profile.software),
               field(r.profile.version), field(desc), field(r.source)}) +
         "\n";
  out += join(db::tsv::parameter_columns()) + "\n";
  for (const auto& row : r.rows) {
    const auto& s = row.scanned;
    auto layer = db::layer_of_upid(s.upid);
    auto type = db::type_from_code(s.type);
    std::string note;
    if (!type)
      note = "type code " + hex(s.type, 2) +
             "h is not a seed 003 §10 type; min/max/default left raw. ";
    std::optional<std::int64_t> mn, mx, df;
    if (s.limits.min) mn = value_of(s.type, *s.limits.min);
    if (s.limits.max) mx = value_of(s.type, *s.limits.max);
    if (s.limits.def) df = value_of(s.type, *s.limits.def);
    if (mn && mx && *mn > *mx) {
      note += "The drive reports min " + std::to_string(*mn) + " above max " + std::to_string(*mx) +
              " (raw " + hex(*s.limits.min, 8) + "h, " + hex(*s.limits.max, 8) +
              "h); neither is stored. ";
      mn.reset();
      mx.reset();
    }
    if (!s.limits.min || !s.limits.max || !s.limits.def) {
      std::string which;
      if (!s.limits.min) which += "min";
      if (!s.limits.max) which += std::string(which.empty() ? "" : ", ") + "max";
      if (!s.limits.def) which += std::string(which.empty() ? "" : ", ") + "default";
      note += "The drive refused to report " + which + ". ";
    }
    while (!note.empty() && note.back() == ' ') note.pop_back();
    auto num = [](const std::optional<std::int64_t>& v) {
      return v ? std::to_string(*v) : std::string();
    };
    std::string labels;
    for (const auto& l : row.labels)
      labels += (labels.empty() ? "" : "|") + std::to_string(l.raw) + "=" + field(l.label);
    out += join({hex(s.upid, 4), field(id),
                 layer ? std::string(db::layer_name(*layer)) : std::string(), field(row.name),
                 field(row.path), type ? std::string(db::type_name(*type)) : std::string(),
                 hex(s.address_usage, 4), num(mn), num(mx), num(df), field(row.unit),
                 row.scale ? scale_text(*row.scale) : std::string(), labels, row.comm ? "1" : "",
                 field(note), field(r.source)}) +
           "\n";
  }
  return out;
}

// ---------------------------------------------------------------- merge

namespace {

struct TsvFile {
  std::vector<std::string> lines;
  std::ptrdiff_t header = -1;  // index of the header line
  std::vector<std::string> columns;
  int column(std::string_view name) const {
    for (std::size_t i = 0; i < columns.size(); ++i)
      if (columns[i] == name) return static_cast<int>(i);
    return -1;
  }
};

Result<TsvFile> read_tsv(const fs::path& path, const std::vector<std::string>& default_columns) {
  TsvFile t;
  std::error_code ec;
  if (fs::exists(path, ec)) {
    LMCFG_ASSIGN_OR_RETURN(auto text, config::read_text_file(path));
    for (std::string_view l : db::tsv::lines(db::tsv::strip_bom(text))) t.lines.emplace_back(l);
  }
  for (std::size_t i = 0; i < t.lines.size(); ++i) {
    if (!is_data_line(t.lines[i])) continue;
    t.header = static_cast<std::ptrdiff_t>(i);
    for (auto f : split(t.lines[i])) t.columns.emplace_back(f);
    break;
  }
  if (t.header < 0) {
    t.lines.push_back(join(default_columns));
    t.header = static_cast<std::ptrdiff_t>(t.lines.size() - 1);
    t.columns = default_columns;
  }
  for (const auto& c : default_columns)
    if (t.column(c) < 0)
      return Error(Errc::validation_failed, path.string() + ": header lacks column \"" + c + "\"");
  return t;
}

// Row given in `from` column order -> the target's column order.
std::string remap(const std::vector<std::string>& from, std::string_view row, const TsvFile& to) {
  auto f = split(row);
  std::vector<std::string> out(to.columns.size());
  for (std::size_t i = 0; i < from.size() && i < f.size(); ++i) {
    int j = to.column(from[i]);
    if (j >= 0) out[static_cast<std::size_t>(j)] = std::string(f[i]);
  }
  return join(out);
}

std::string text_of(const std::vector<std::string>& lines) {
  std::string s;
  for (const auto& l : lines) s += l + "\n";
  return s;
}

// A fragment `lmcfg db scan` wrote: its #@profiles.tsv header and row, and
// its parameters header and rows.
struct Fragment {
  std::vector<std::string> prof_cols, param_cols;
  std::string prof_row;
  std::vector<std::string> param_rows;
  std::string profile;
};

Result<Fragment> parse_fragment(const std::string& fragment_text) {
  Fragment fr;
  for (std::string_view l : db::tsv::lines(fragment_text)) {
    if (l.rfind(kProfilesMark, 0) == 0) {
      std::string_view body = l.substr(std::string_view(kProfilesMark).size());
      if (fr.prof_cols.empty()) {
        for (auto f : split(body)) fr.prof_cols.emplace_back(f);
      } else if (fr.prof_row.empty()) {
        fr.prof_row = std::string(body);
      } else {
        return Error(Errc::parse_error, "fragment: more than one #@profiles.tsv row");
      }
      continue;
    }
    if (!is_data_line(l)) continue;
    if (fr.param_cols.empty()) {
      for (auto f : split(l)) fr.param_cols.emplace_back(f);
    } else {
      fr.param_rows.emplace_back(l);
    }
  }
  if (fr.prof_row.empty() || fr.param_cols.empty())
    return Error(Errc::parse_error,
                 "not a lmcfg db scan fragment: no #@profiles.tsv row or no parameters header");
  return fr;
}

// The fragment holds one scanned profile, and parameters of that profile only.
Result<void> check_fragment(Fragment& fr) {
  const auto& prof_cols = fr.prof_cols;
  auto pi = std::find(prof_cols.begin(), prof_cols.end(), "profile");
  auto ps = std::find(prof_cols.begin(), prof_cols.end(), "source");
  if (pi == prof_cols.end() || ps == prof_cols.end())
    return Error(Errc::parse_error, "fragment: the #@profiles.tsv header lacks profile or source");
  auto pf = split(fr.prof_row);
  const auto id_col = static_cast<std::size_t>(pi - prof_cols.begin());
  const auto src_col = static_cast<std::size_t>(ps - prof_cols.begin());
  if (pf.size() != prof_cols.size())
    return Error(Errc::parse_error, "fragment: the #@profiles.tsv row has the wrong field count");
  fr.profile = std::string(pf[id_col]);
  if (!is_scanned_source(pf[src_col]))
    return Error(Errc::parse_error,
                 "fragment: the profile's source is not \"scanned from a drive: ...\"");
  auto upc = std::find(fr.param_cols.begin(), fr.param_cols.end(), "profiles");
  if (upc == fr.param_cols.end())
    return Error(Errc::parse_error, "fragment: the parameters header lacks column profiles");
  for (const auto& row : fr.param_rows) {
    auto f = split(row);
    auto k = static_cast<std::size_t>(upc - fr.param_cols.begin());
    if (f.size() != fr.param_cols.size() || f[k] != fr.profile) {
      return Error(Errc::parse_error,
                   "fragment: a parameters row is not of profile " + fr.profile + ": " + row);
    }
  }
  return {};
}

// profiles.tsv: replace an earlier scan's row, refuse any other definition.
Result<void> merge_profile(const fs::path& path, TsvFile& profiles, const Fragment& fr,
                           MergeReport& rep) {
  const int c_id = profiles.column("profile"), c_src = profiles.column("source");
  std::vector<std::string> kept;
  for (std::size_t i = 0; i < profiles.lines.size(); ++i) {
    const auto& l = profiles.lines[i];
    if (static_cast<std::ptrdiff_t>(i) > profiles.header && is_data_line(l)) {
      auto f = split(l);
      if (f.size() > static_cast<std::size_t>(std::max(c_id, c_src)) &&
          f[static_cast<std::size_t>(c_id)] == rep.profile) {
        if (!is_scanned_source(f[static_cast<std::size_t>(c_src)])) {
          return Error(Errc::validation_failed,
                       path.string() + ":" + std::to_string(i + 1) + ": profile '" + rep.profile +
                           "' is defined there other than by a scan; not replaced");
        }
        rep.profile_replaced = true;
        continue;
      }
    }
    kept.push_back(l);
  }
  kept.push_back(remap(fr.prof_cols, fr.prof_row, profiles));
  profiles.lines = std::move(kept);
  return {};
}

// parameters.tsv: drop the earlier scan's rows of this profile, append ours.
void merge_parameters(TsvFile& params, const Fragment& fr, MergeReport& rep) {
  const int c_prof = params.column("profiles");
  std::vector<std::string> kept;
  for (std::size_t i = 0; i < params.lines.size(); ++i) {
    const auto& l = params.lines[i];
    if (static_cast<std::ptrdiff_t>(i) > params.header && is_data_line(l)) {
      auto f = split(l);
      if (f.size() > static_cast<std::size_t>(c_prof) &&
          f[static_cast<std::size_t>(c_prof)] == rep.profile) {
        ++rep.parameters_replaced;
        continue;
      }
    }
    kept.push_back(l);
  }
  for (const auto& row : fr.param_rows) kept.push_back(remap(fr.param_cols, row, params));
  rep.parameters_added = fr.param_rows.size();
  params.lines = std::move(kept);
}

}  // namespace

Result<MergeReport> merge_scan_fragment(const std::string& source_dir,
                                        const std::string& fragment_text) {
  LMCFG_ASSIGN_OR_RETURN(auto fr, parse_fragment(fragment_text));
  LMCFG_TRY(check_fragment(fr));
  MergeReport rep;
  rep.profile = fr.profile;

  const fs::path dir(source_dir);
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return Error(Errc::file_error, source_dir + ": not a directory");
  LMCFG_ASSIGN_OR_RETURN(auto profiles, read_tsv(dir / "profiles.tsv", db::tsv::profile_columns()));
  LMCFG_TRY(merge_profile(dir / "profiles.tsv", profiles, fr, rep));
  LMCFG_ASSIGN_OR_RETURN(auto params,
                         read_tsv(dir / "parameters.tsv", db::tsv::parameter_columns()));
  merge_parameters(params, fr, rep);
  // Profile first: a parameters.tsv naming an unknown profile would not compile.
  LMCFG_TRY(config::write_file_atomic(dir / "profiles.tsv", text_of(profiles.lines)));
  LMCFG_TRY(config::write_file_atomic(dir / "parameters.tsv", text_of(params.lines)));
  return rep;
}

}  // namespace lmcfg::ops
