// lmcfg db: query the compiled UPID database (no drive needed); `db scan`
// learns a new firmware profile from a drive, `db merge` adds a scan's fragment
// to the upid-db sources.
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include "command.hpp"
#include "common/bytes.hpp"
#include "config/atomic_file.hpp"
#include "db/database.hpp"
#include "link_options.hpp"
#include "ops/db_scan.hpp"
#include "report/json_reports.hpp"

namespace lmcfg::cli {
namespace {

using lmcfg::db::Database;

struct DbOptions {
  std::string db_path;
  bool json = false;
  std::string upid;
  std::string profile;
  std::string needle;
  std::string domain;
  bool devicenet_params = false;
};

std::optional<Database> open_db(const DbOptions& o, int& exit_code) {
  auto r = o.db_path.empty() ? Database::open_default() : Database::open(o.db_path);
  if (!r) {
    std::fprintf(stderr, "lmcfg db: %s\n", r.error().message.c_str());
    exit_code = kInvalidInput;
    return std::nullopt;
  }
  return std::move(r).value();
}

std::string prov_text(const db::Provenance& p) {
  return p.source + " (" + p.file + ":" + std::to_string(p.line) + ")";
}

std::string profiles_text(const db::Parameter& p) {
  if (p.profiles.empty()) return "*";
  std::string s;
  for (const auto& x : p.profiles) s += (s.empty() ? "" : ",") + x;
  return s;
}

std::string usage_text(const db::AddressUsage& a) {
  std::string s;
  auto add = [&s](bool on, const char* what) {
    if (on) s += (s.empty() ? "" : ", ") + std::string(what);
  };
  add(a.ram_read(), "RAM read");
  add(a.ram_write(), "RAM write");
  add(a.rom_read(), "ROM read");
  add(a.rom_write(), "ROM write");
  add(a.no_hash(), "not in hash");
  return s;
}

// Limits/default shown raw and, when they differ, formatted.
std::string raw_and_text(const db::Parameter& p, std::int64_t raw) {
  std::string r = std::to_string(raw);
  std::string t =
      p.format(static_cast<std::uint32_t>(static_cast<std::uint64_t>(raw) & 0xFFFFFFFFull));
  return t == r ? r : r + " = " + t;
}

void print_param(const db::Parameter& p) {
  auto row = [](const char* k, const std::string& v) {
    if (!v.empty()) std::printf("  %-13s %s\n", k, v.c_str());
  };
  std::printf("%s  %s\n", hex(p.upid, 4).c_str(),
              p.name.empty() ? "(name not given in the seeds)" : p.name.c_str());
  row("layer", std::string(db::layer_name(p.layer)));
  row("path", p.path);
  row("profiles", profiles_text(p));
  row("type", p.spec.type ? std::string(db::type_name(*p.spec.type)) : "(unknown)");
  if (p.address_usage)
    row("address usage", hex(p.address_usage->raw, 4) + " (" + usage_text(*p.address_usage) + ")");
  if (p.spec.min) row("min", raw_and_text(p, *p.spec.min));
  if (p.spec.max) row("max", raw_and_text(p, *p.spec.max));
  if (p.default_value) row("default", raw_and_text(p, *p.default_value));
  if (p.spec.scale)
    row("scale", db::format_scaled(1, *p.spec.scale) + " " + p.spec.unit + " per raw step");
  else
    row("unit", p.spec.unit);
  std::string labels;
  for (const auto& l : p.spec.labels)
    labels += (labels.empty() ? "" : ", ") + std::to_string(l.raw) + "=" + l.label;
  row("values", labels);
  if (p.comm) row("comm", "yes: changing it changes how the drive talks on the line");
  row("description", p.description);
  row("source", prov_text(p.prov));
}

void print_param_list(const std::vector<const db::Parameter*>& v) {
  std::printf("%-5s %-4s %-13s %-40s %s\n", "UPID", "LAYR", "TYPE", "NAME", "PATH");
  for (const auto* p : v)
    std::printf("%-5s %-4s %-13s %-40s %s\n", hex(p->upid, 4).c_str(),
                std::string(db::layer_name(p->layer)).c_str(),
                p->spec.type ? std::string(db::type_name(*p->spec.type)).c_str() : "-",
                p->name.c_str(), p->path.c_str());
}

int run_show(const DbOptions& o) {
  auto v = db::parse_upid(o.upid);
  if (!v.ok()) {
    std::fprintf(stderr, "lmcfg db show: %s\n", v.error().message.c_str());
    return kInvalidInput;
  }
  int rc = kOk;
  auto d = open_db(o, rc);
  if (!d) return rc;
  auto upid = static_cast<std::uint16_t>(*v);
  std::vector<const db::Parameter*> found;
  for (const auto* p : d->find_all(upid))
    if (p->applies_to(o.profile)) found.push_back(p);
  if (o.json) {
    std::cout << report::db_show_json(upid, found).dump(2) << "\n";
    return kOk;
  }
  if (found.empty()) {
    std::printf(
        "UPID %s is unknown to the database%s; the drive can be asked for its type and limits.\n",
        hex(upid, 4).c_str(), o.profile.empty() ? "" : (" for profile " + o.profile).c_str());
    return kOk;
  }
  for (std::size_t i = 0; i < found.size(); ++i) {
    if (i) std::printf("\n");
    print_param(*found[i]);
  }
  return kOk;
}

int run_find(const DbOptions& o) {
  int rc = kOk;
  auto d = open_db(o, rc);
  if (!d) return rc;
  auto v = d->search(o.needle);
  if (o.json) {
    std::cout << report::db_parameters_json(v).dump(2) << "\n";
    return kOk;
  }
  if (v.empty()) {
    std::printf("no parameter name or path contains \"%s\"\n", o.needle.c_str());
    return kOk;
  }
  print_param_list(v);
  return kOk;
}

int run_errors(const DbOptions& o) {
  int rc = kOk;
  auto d = open_db(o, rc);
  if (!d) return rc;
  auto v = d->errors(o.domain);
  if (o.json) {
    std::cout << report::db_errors_json(v).dump(2) << "\n";
    return kOk;
  }
  std::printf("%-9s %-8s %s\n", "DOMAIN", "CODE", "TEXT");
  for (const auto* e : v)
    std::printf("%-9s %-8s %s\n", e->domain.c_str(), e->code_text.c_str(), e->text.c_str());
  return kOk;
}

int run_commands(const DbOptions& o) {
  int rc = kOk;
  auto d = open_db(o, rc);
  if (!d) return rc;
  const auto& v = d->motion_commands();
  if (o.json) {
    std::cout << report::db_commands_json(v).dump(2) << "\n";
    return kOk;
  }
  std::printf("%-6s %-45s %s\n", "HEADER", "NAME", "PARAMETERS");
  for (const auto& c : v) {
    std::string ps;
    for (const auto& p : c.params) {
      std::string what = p.spec.unit;
      if (p.scaled) what = "scaled";
      if (!p.range_text.empty()) what += (what.empty() ? "" : ", ") + p.range_text;
      ps += (ps.empty() ? "" : ", ") + p.name + (what.empty() ? "" : " [" + what + "]");
    }
    std::printf("%-6s %-45s %s\n", (hex(c.header() >> 4, 3) + "x").c_str(), c.name.c_str(),
                ps.c_str());
  }
  return kOk;
}

std::string range_text(const db::ValueSpec& s) {
  if (!s.min && !s.max) return "";
  return (s.min ? std::to_string(*s.min) : std::string("?")) + ".." +
         (s.max ? std::to_string(*s.max) : std::string("?"));
}

// Seed 000: the general-purpose command set (7-bit IDs) or the DeviceNet parameter tree.
int run_devicenet(const DbOptions& o) {
  int rc = kOk;
  auto d = open_db(o, rc);
  if (!d) return rc;
  if (o.devicenet_params) {
    if (o.json) {
      std::cout << report::db_devicenet_parameters_json(d->devicenet_parameters()).dump(2) << "\n";
      return kOk;
    }
    std::printf("%-55s %-8s %s\n", "PATH (OR NAME)", "RANGE", "NOTES");
    for (const auto& p : d->devicenet_parameters())
      std::printf("%-55s %-8s %s\n", p.id.c_str(), range_text(p.spec).c_str(),
                  p.comm ? "communication" : "");
    return kOk;
  }
  if (!o.needle.empty()) {
    auto id = parse_number(o.needle, true);
    if (!id || *id > 0x7F) {
      std::fprintf(stderr,
                   "lmcfg db devicenet: '%s' is not a command ID 00..7F (hex: 11, 0x11, 11h)\n",
                   o.needle.c_str());
      return kInvalidInput;
    }
    const auto* c = d->devicenet_command(static_cast<std::uint8_t>(*id));
    if (!c) {
      std::printf(
          "DeviceNet command %02Xh: not in the database (seed 000 §5.2 Table 5-1 does not define "
          "it)\n",
          static_cast<unsigned>(*id));
      return kOk;
    }
    if (o.json) {
      std::cout << report::db_devicenet_command_json(*c).dump(2) << "\n";
      return kOk;
    }
    std::printf("%s %s\n", c->id_text.c_str(), c->name.c_str());
    std::printf("  Table 5-1:   %s\n", c->table_name.c_str());
    std::printf("  direction:   %s\n",
                c->direction.empty() ? "action (neither get nor set)" : c->direction.c_str());
    std::printf("  value:       %s%s%s\n", c->range_text.c_str(),
                range_text(c->spec).empty() ? "" : (" (raw " + range_text(c->spec) + ")").c_str(),
                c->spec.unit.empty()
                    ? ""
                    : ("; " + c->spec.unit +
                       (c->spec.scale ? " x " + db::format_scaled(1, *c->spec.scale) : ""))
                          .c_str());
    std::printf("  unit text:   %s\n", c->unit_text.c_str());
    for (const auto& l : c->spec.labels)
      std::printf("  label:       %lld = %s\n", static_cast<long long>(l.raw), l.label.c_str());
    std::printf("  modules:     %s%s\n", c->addressed ? "Addressed In/Out " : "",
                c->direct ? "Direct In/Out" : "");
    std::printf("  %s\n  source:      %s\n", c->description.c_str(), prov_text(c->prov).c_str());
    return kOk;
  }
  if (o.json) {
    std::cout << report::db_devicenet_commands_json(d->devicenet_commands()).dump(2) << "\n";
    return kOk;
  }
  std::printf("%-5s %-4s %-45s %-22s %s\n", "ID", "DIR", "NAME", "RANGE", "UNIT");
  for (const auto& c : d->devicenet_commands())
    std::printf("%-5s %-4s %-45s %-22s %s\n", c.id_text.c_str(), c.direction.c_str(),
                c.name.c_str(), c.range_text.c_str(), c.spec.unit.c_str());
  return kOk;
}

int run_info(const DbOptions& o) {
  int rc = kOk;
  auto d = open_db(o, rc);
  if (!d) return rc;
  const auto& i = d->info();
  if (o.json) {
    std::cout << report::db_info_json(i).dump(2) << "\n";
    return kOk;
  }
  std::printf("database        %s\nschema version  %d\ncontent hash    %s\nbuilt from      %s\n",
              i.path.c_str(), i.schema_version, i.content_hash.c_str(),
              i.built_from.empty() ? "(no source files)" : i.built_from.c_str());
  for (const auto& [k, n] : i.counts) std::printf("  %-22s %zu\n", k.c_str(), n);
  return kOk;
}

// ---------------------------------------------------------------- db scan / db merge

struct DbScanCli {
  CommonOptions common;
  std::string profile;
  std::string output;
  std::string family, software, version, description;
  std::string names_from;
  std::string layers = "os,mc,intf,appl";
  std::string date;
  std::string merge_into;
  bool restart = false;
};

void print_merge(const CommonOptions& c, const ops::MergeReport& m, const std::string& dir) {
  if (c.quiet || c.json) return;
  std::fprintf(stderr, "merged profile %s into %s: %zu parameter row(s)%s%s\n", m.profile.c_str(),
               dir.c_str(), m.parameters_added,
               m.parameters_replaced ? (" (replacing " + std::to_string(m.parameters_replaced) +
                                        " of an earlier scan)")
                                           .c_str()
                                     : "",
               m.profile_replaced ? ", profile row replaced" : "");
}

int run_scan(DbScanCli& o) {
  auto layers = parse_layers(o.layers);
  if (!layers.ok()) return fail("db scan", layers.error());
  std::error_code ec;
  if (std::filesystem::is_directory(o.output, ec)) {
    return fail("db scan", Error(Errc::invalid_argument,
                                 "output '" + o.output + "' is a directory; name a .tsv file"));
  }
  if (auto ok = check_output_path(o.output, "-o"); !ok.ok()) return fail("db scan", ok.error());
  if (!o.merge_into.empty() && !std::filesystem::is_directory(o.merge_into, ec)) {
    return fail("db scan", Error(Errc::invalid_argument,
                                 "--merge-into '" + o.merge_into + "' is not a directory"));
  }
  const db::Database d = load_database(o.common);
  if (auto ok = ops::check_scan_profile_id(o.profile, d); !ok.ok())
    return fail("db scan", ok.error());
  const std::string partial = o.output + ".partial";
  if (o.restart) std::filesystem::remove(partial, ec);
  auto store = ops::PartialFileStore::open(partial, o.profile);
  if (!store.ok()) return fail("db scan", store.error());
  if ((*store)->loaded() > 0 && !o.common.quiet && !o.common.json) {
    std::fprintf(stderr, "db scan: resuming: %zu UPID(s) already read (%s)\n", (*store)->loaded(),
                 partial.c_str());
  }
  auto session = open_link(o.common);
  if (!session.ok()) return fail("db scan", session.error());
  ops::DbScanOptions so;
  so.profile = {o.profile, o.family, o.software, o.version, o.description};
  so.layers = *layers;
  so.names_from = o.names_from;
  so.date = o.date;
  ProgressBar bar(o.common);
  so.progress = bar.callback();
  so.store = store->get();
  auto r = ops::scan_drive_profile((*session)->client(), d, so);
  bar.end();
  auto closed = (*session)->close();
  if (!r.ok()) {
    if ((*store)->size() > 0)
      std::fprintf(stderr,
                   "lmcfg db scan: %zu UPID(s) kept in %s; rerun the same command to continue\n",
                   (*store)->size(), partial.c_str());
    return session->fail("db scan", r.error());
  }
  if (!closed.ok()) return session->fail("db scan", closed.error());
  const std::string text = ops::scan_fragment_tsv(*r);
  if (auto w = config::write_file_atomic(o.output, text); !w.ok())
    return session->fail("db scan", w.error());
  if (auto rm = (*store)->remove(); !rm.ok() && !o.common.quiet)
    std::fprintf(stderr, "lmcfg db scan: warning: %s\n", rm.error().message.c_str());
  std::optional<ops::MergeReport> merged;
  if (!o.merge_into.empty()) {
    auto m = ops::merge_scan_fragment(o.merge_into, text);
    if (!m.ok()) return session->fail("db scan", m.error());
    merged = *m;
  }
  const auto& st = (*session)->client().stats();
  if (o.common.json) {
    std::cout << report::db_scan_json(o.output, *r, st.requests, merged ? o.merge_into : "").dump(2)
              << "\n";
  } else if (!o.common.quiet) {
    std::fprintf(stderr,
                 "db scan: %zu UPID(s) (OS %zu, MC %zu, Intf %zu, Appl %zu), %zu named from the "
                 "database, %zu resumed, "
                 "%zu limit(s) refused -> %s (%llu telegrams)\n",
                 r->rows.size(), r->per_layer[0], r->per_layer[1], r->per_layer[2], r->per_layer[3],
                 r->named, r->resumed, r->refused, o.output.c_str(),
                 static_cast<unsigned long long>(st.requests));
    if (merged)
      print_merge(o.common, *merged, o.merge_into);
    else
      std::fprintf(stderr,
                   "db scan: add it to the database with: lmcfg db merge %s --into upid-db\n",
                   o.output.c_str());
  }
  return kOk;
}

struct MergeCli {
  CommonOptions common;
  std::string fragment;
  std::string into = "upid-db";
};

int run_merge(MergeCli& o) {
  auto text = config::read_text_file(o.fragment);
  if (!text.ok()) return fail("db merge", text.error());
  auto m = ops::merge_scan_fragment(o.into, *text);
  if (!m.ok()) return fail("db merge", m.error());
  if (o.common.json) {
    std::cout << report::db_merge_json(o.into, *m).dump(2) << "\n";
  }
  print_merge(o.common, *m, o.into);
  return kOk;
}

// lmcfg db scan: a profile learnt from a drive.
void add_db_scan(CLI::App* db, int& exit_code) {
  auto so = std::make_shared<DbScanCli>();
  auto* scan = db->add_subcommand(
      "scan", "Learn a new firmware profile from a drive: UPID list, min/max/default");
  scan->footer(
      "Examples:\n"
      "  lmcfg db scan --port /dev/ttyUSB0 --profile e1100-fw-x --names-from e1100-mc-linrs -o "
      "scan-e1100-fw-x.tsv\n"
      "  lmcfg db scan --port sim:drive.json --profile e1100-fw-x -o scan.tsv --merge-into "
      "upid-db\n"
      "Walks the UPID list of each layer (address usage, type) and asks min, max and default of "
      "every UPID;\n"
      "names, paths, units, scales, enum labels and the comm flag come from the database row of "
      "the same UPID.\n"
      "Writes a upid-db fragment (upid-db/FORMAT.md; docs/upid-db.md \"Scanning a drive\") "
      "atomically. Progress is\n"
      "kept in OUTPUT.partial: an interrupted scan continues when the same command is run again "
      "(--restart: start\n"
      "over). Sends read telegrams only. Exit codes as for backup: 2 bad input, 4 link failure, 5 "
      "drive refused.");
  add_link_options(scan, so->common);
  add_output_options(scan, so->common);
  scan->add_option("--profile", so->profile, "id of the new profile, e.g. e1100-fw-x")->required();
  scan->add_option("-o,--output", so->output, "fragment file to write (.tsv)")->required();
  scan->add_option("--family", so->family, "profile family (default: that of --names-from)");
  scan->add_option("--software", so->software,
                   "firmware / interface software (default: that of --names-from)");
  scan->add_option("--version", so->version, "firmware version text");
  scan->add_option("--description", so->description,
                   "profile description (default: a summary of the scan)");
  scan->add_option("--names-from", so->names_from,
                   "known profile whose rows give names (default: any row of the UPID)");
  scan->add_option("--layers", so->layers, "layers to scan: os,mc,intf,appl")
      ->capture_default_str();
  scan->add_option("--date", so->date, "date in the provenance (default: today, UTC)");
  scan->add_option("--merge-into", so->merge_into,
                   "also merge the fragment into this upid-db source directory");
  scan->add_flag("--restart", so->restart, "ignore OUTPUT.partial and scan from the start");
  scan->callback([so, &exit_code] { exit_code = run_scan(*so); });
}

// lmcfg db merge: a scan's fragment into the upid-db sources.
void add_db_merge(CLI::App* db, int& exit_code) {
  auto mo = std::make_shared<MergeCli>();
  auto* merge = db->add_subcommand(
      "merge",
      "Merge a `db scan` fragment into the upid-db sources (profiles.tsv, parameters.tsv)");
  merge->add_option("fragment", mo->fragment, "fragment written by lmcfg db scan")->required();
  merge->add_option("--into", mo->into, "upid-db source directory")->capture_default_str();
  merge->add_flag("--quiet,-q", mo->common.quiet, "no summary");
  merge->add_flag("--json", mo->common.json, "machine-readable report on stdout");
  merge->callback([mo, &exit_code] { exit_code = run_merge(*mo); });
}

void setup(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<DbOptions>();
  auto* db = app.add_subcommand(
      "db", "Query the UPID database (parameters, errors, motion commands); no drive needed");
  db->require_subcommand(1);
  db->footer(
      "Exit codes: 0 = answered (also when a UPID or text is not in the database: that is a note, "
      "not an error;\n"
      "the drive itself can be asked); 2 = malformed input (a UPID that is not hex) or the "
      "database file is missing\n"
      "or unreadable. The database is --db PATH, else $LMCFG_UPID_DB, else lmcfg-upid.sqlite "
      "next to the lmcfg binary, else in ../share/lmcfg/ relative to it.");
  auto common = [&](CLI::App* sub) {
    sub->fallthrough();
    sub->add_option(
        "--db", o->db_path,
        "UPID database file (default: $LMCFG_UPID_DB, else next to lmcfg, else ../share/lmcfg/)");
    sub->add_flag("--json", o->json, "Machine-readable JSON on stdout");
  };
  common(db);

  auto* show = db->add_subcommand("show", "Show everything the database knows about one UPID");
  show->add_option("upid", o->upid, "UPID in hex: 13A2, 13a2h, 0x13A2")->required();
  show->add_option("--profile", o->profile,
                   "Only the definition for this profile id (see upid-db/profiles.tsv)");
  show->callback([o, &exit_code] { exit_code = run_show(*o); });

  auto* find = db->add_subcommand(
      "find", "Find parameters whose name or tree path contains TEXT (case-insensitive)");
  find->add_option("text", o->needle, "Substring to look for")->required();
  find->callback([o, &exit_code] { exit_code = run_find(*o); });

  auto* errors = db->add_subcommand("errors", "List error codes");
  errors->add_option("--domain", o->domain, "mc, linrs or devicenet");
  errors->callback([o, &exit_code] { exit_code = run_errors(*o); });

  auto* commands = db->add_subcommand("commands", "List motion commands and their parameters");
  commands->callback([o, &exit_code] { exit_code = run_commands(*o); });

  auto* devicenet =
      db->add_subcommand("devicenet",
                         "Older DeviceNet controllers (seed 000): the general-purpose command set, "
                         "or --params the parameter tree");
  devicenet->add_option("id", o->needle, "One command ID in hex (11, 0x11, 11h): show it in full");
  devicenet->add_flag("--params", o->devicenet_params,
                      "List the DeviceNet parameter tree instead of the commands");
  devicenet->callback([o, &exit_code] { exit_code = run_devicenet(*o); });

  auto* info = db->add_subcommand("info", "Schema version, content hash and row counts");
  info->callback([o, &exit_code] { exit_code = run_info(*o); });
  for (auto* s : {show, find, errors, commands, devicenet, info}) common(s);

  add_db_scan(db, exit_code);
  add_db_merge(db, exit_code);
}
}  // namespace

void add_db(CLI::App& app, int& exit_code) { setup(app, exit_code); }
}  // namespace lmcfg::cli
