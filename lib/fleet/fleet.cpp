#include "fleet/fleet.hpp"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <filesystem>
#include <mutex>
#include <nlohmann/json.hpp>
#include <thread>

#include "common/bytes.hpp"
#include "common/layers.hpp"
#include "common/text.hpp"
#include "config/config_io.hpp"
#include "fleet/approved.hpp"

namespace lmcfg::fleet {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// Every line read live: one thread per line (read_line never throws).
std::vector<LineRun> read_all(const Inventory& inv, const FleetOptions& opt) {
  std::vector<LineRun> per_line(inv.lines.size());
  std::vector<std::thread> workers;
  for (std::size_t l = 0; l < inv.lines.size(); ++l)
    workers.emplace_back([&, l] { per_line[l] = read_line(inv.lines[l], opt.links[l], opt); });
  for (auto& w : workers) w.join();
  return per_line;
}

Result<FleetRun> read_and_compare(const Inventory& inv, const Archive& archive,
                                  const FleetOptions& opt, std::vector<LineRun>& reads,
                                  Compare how) {
  if (opt.links.size() != inv.lines.size())
    return Error(Errc::invalid_argument, "fleet: one link per inventory line is needed");
  FleetRun run;
  run.against_approved = opt.rev.empty();
  LMCFG_ASSIGN_OR_RETURN(run.compared_to, archive.resolve(opt.rev.empty() ? "HEAD" : opt.rev));
  const auto start = Clock::now();
  reads = read_all(inv, opt);
  for (std::size_t l = 0; l < inv.lines.size(); ++l) {
    LMCFG_TRY(compare_line(inv.lines[l], archive, opt.rev, opt.db, reads[l], how));
    for (const auto& r : reads[l].drives) run.drives.push_back(r);
  }
  run.seconds = seconds_since(start);
  return run;
}

std::string plural(std::size_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

std::string where(const DriveResult& r) {
  return r.name + " (line " + r.line + (r.devicenet ? ", DeviceNet MAC ID " : ", MACID ") +
         hex(r.id, 2, "h") + ")";
}

constexpr std::size_t kItemsPerDrive = 20;  // in a commit message; the diff has them all

void append_items(std::string& s, const DriveResult& r, const char* indent) {
  std::size_t n = 0;
  for (const auto& it : r.diff.items) {
    if (n++ == kItemsPerDrive) {
      s += indent + std::string("... and ") + std::to_string(r.diff.items.size() - kItemsPerDrive) +
           " more\n";
      break;
    }
    s += indent + item_line(it) + "\n";
  }
}

}  // namespace

std::string counts_line(const DriveResult& r) {
  using K = ops::DiffItem::Kind;
  if (r.devicenet) {
    std::string s = plural(r.count(K::devicenet), "DeviceNet value", "DeviceNet values");
    if (auto other = r.count(K::metadata) + r.count(K::scope))
      s += ", " + plural(other, "other difference", "other differences");
    return s;
  }
  std::string s = plural(r.count(K::parameter), "parameter", "parameters") + ", " +
                  plural(r.count(K::curve), "curve", "curves") + ", " +
                  plural(r.count(K::ct_entry), "CT entry", "CT entries");
  if (auto other = r.count(K::metadata) + r.count(K::scope) + r.count(K::devicenet))
    s += ", " + plural(other, "other difference", "other differences");
  return s;
}

std::string item_line(const ops::DiffItem& it) {
  using K = ops::DiffItem::Kind;
  std::string what;
  switch (it.kind) {
    case K::parameter:
      what = std::string(layers::name(it.layer)) + " " + hex(it.key, 4, "h");
      break;
    case K::curve:
      what = "curve " + std::to_string(it.key);
      break;
    case K::ct_entry:
      what = "CT entry " + std::to_string(it.key);
      break;
    case K::metadata:
    case K::scope:
    case K::devicenet:
      what = ops::kind_name(it.kind);
      break;
  }
  if (!it.name.empty()) what += " " + it.name;
  what += ": " + it.a + " -> " + it.b;
  if (!it.detail.empty()) what += " (" + it.detail + ")";
  return what;
}

ops::LineDrive line_drive(const DriveEntry& d) {
  ops::LineDrive ld;
  ld.id = d.id;
  ld.io_modules = d.io_modules;
  ld.motors = d.devicenet_motors;
  ld.module_values = d.module_values;
  return ld;
}

LineRun read_line(const LineEntry& line, const ops::LineLink& link, const FleetOptions& opt,
                  const std::vector<std::string>& only) {
  LineRun run;
  for (const auto& d : line.drives) {
    if (!only.empty() && std::find(only.begin(), only.end(), d.name) == only.end()) continue;
    run.entries.push_back(&d);
    DriveResult r;
    r.line = line.name;
    r.name = d.name;
    r.id = d.id;
    r.devicenet = link.is_devicenet();
    run.drives.push_back(std::move(r));
  }
  run.configs.resize(run.entries.size());
  if (run.entries.empty()) return run;
  const auto line_start = Clock::now();
  try {
    auto session = ops::LineSession::open(link, run.entries.front()->id);
    std::size_t done = 0;
    for (std::size_t i = 0; i < run.entries.size(); ++i) {
      const auto& d = *run.entries[i];
      auto& r = run.drives[i];
      const auto start = Clock::now();
      if (!session.ok()) {
        r.error = Error(session.error().code,
                        "line '" + line.name + "' (" + line.port + "): " + session.error().message);
      } else {
        ops::BackupOptions bo = opt.backup;
        bo.progress = nullptr;
        bo.report = nullptr;
        if (d.family) bo.family = d.family;
        auto cfg = (*session)->backup(line_drive(d), bo, opt.db.get());
        if (!cfg.ok()) {
          r.error = cfg.error();
        } else {
          cfg->identity.labels = d.labels;
          for (const auto& l : cfg->layers) r.parameters += l.size();
          r.curves = cfg->curves.size();
          r.ct_entries = cfg->ct_entries.size();
          if (cfg->devicenet) r.devicenet_values = cfg->devicenet->values.size();
          run.configs[i] = std::move(cfg).value();
        }
      }
      r.seconds = seconds_since(start);
      if (opt.on_drive) {
        // One call at a time across the lines' workers.
        static std::mutex report_lock;
        std::lock_guard<std::mutex> lock(report_lock);
        opt.on_drive(r, ++done, run.entries.size());
      }
    }
    if (session.ok()) {
      run.stats = (*session)->stats();
      // A simulated line saves its drives here; a real one has nothing to save.
      if (auto closed = (*session)->close(); !closed.ok()) {
        for (std::size_t i = 0; i < run.drives.size(); ++i) {
          if (!run.drives[i].error) {
            run.drives[i].error = closed.error();
            run.configs[i].reset();
          }
        }
      }
    }
  } catch (const std::exception& e) {
    // A worker never takes the process down: its unread drives fail, named.
    for (std::size_t i = 0; i < run.drives.size(); ++i) {
      if (!run.configs[i] && !run.drives[i].error)
        run.drives[i].error = Error(Errc::io_error, std::string("fleet worker: ") + e.what());
    }
  }
  run.seconds = seconds_since(line_start);
  return run;
}

Result<void> compare_drive(const LineEntry& line, const DriveEntry& d, const Archive& archive,
                           const std::string& rev, const db::Database& db,
                           const std::optional<config::DriveConfig>& live, DriveResult& r,
                           Compare how) {
  r.diff.items.clear();
  r.kept.clear();
  if (!live) {
    r.status = DriveResult::Status::failed;
    return {};
  }
  LMCFG_ASSIGN_OR_RETURN(auto text, archive.read(archive_path(d), rev));
  if (!text) {
    r.status = DriveResult::Status::added;
    return {};
  }
  auto archived =
      config::read_config_text(*text, archive_path(d) + " at " + rev, config::FileFormat::json);
  if (!archived.ok()) {
    // A hand-edited or damaged archive file is a difference, not a failure
    // of the drive: backup replaces it with what the drive holds.
    ops::DiffItem it;
    it.kind = ops::DiffItem::Kind::metadata;
    it.name = "archived file";
    it.a = "unreadable (" + archived.error().message + ")";
    it.b = "read from the drive";
    r.diff.items.push_back(std::move(it));
    r.status = DriveResult::Status::changed;
    return {};
  }
  r.diff = ops::diff(*archived, *live, db, nullptr, ops::DiffOptions{});
  if (how == Compare::drift) {
    auto m = ops::match(r.diff, *live, db, match_policy(line, d));
    r.status = m.matches() ? DriveResult::Status::unchanged : DriveResult::Status::changed;
    r.diff.items = std::move(m.differences);
    r.kept = std::move(m.kept);
    return {};
  }
  // Live and volatile values the inventory names are never a difference.
  const auto ignored = ignored_upids(line, d);
  std::erase_if(r.diff.items, [&](const ops::DiffItem& it) {
    return it.kind == ops::DiffItem::Kind::parameter &&
           std::find(ignored.begin(), ignored.end(), it.key) != ignored.end();
  });
  r.status = r.diff.items.empty() ? DriveResult::Status::unchanged : DriveResult::Status::changed;
  return {};
}

ops::MatchPolicy match_policy(const LineEntry& line, const DriveEntry& d) {
  ops::MatchPolicy p;
  p.ignored = ignored_upids(line, d);
  if (!line.devicenet) {
    p.macid = d.id;
    if (line.baud && *line.baud > 0) p.baud = static_cast<unsigned>(*line.baud);
  }
  return p;
}

Result<void> compare_line(const LineEntry& line, const Archive& archive, const std::string& rev,
                          const db::Database& db, LineRun& run, Compare how) {
  for (std::size_t i = 0; i < run.entries.size(); ++i) {
    // "" = each drive against its approved configuration (fleet/approved.hpp).
    std::string against = rev;
    if (against.empty()) {
      LMCFG_ASSIGN_OR_RETURN(against, approved_rev(archive, *run.entries[i]));
    }
    LMCFG_TRY(compare_drive(line, *run.entries[i], archive, against, db, run.configs[i],
                            run.drives[i], how));
  }
  return {};
}

Result<std::vector<std::string>> write_line(Archive& archive, const db::Database& db,
                                            const LineRun& run) {
  std::optional<ops::DatabaseCtDecoder> ct_decoder;
  config::WriteOptions wo;
  if (!db.is_empty()) wo.ct_decoder = &ct_decoder.emplace(db);
  std::vector<std::string> paths;
  for (std::size_t i = 0; i < run.entries.size(); ++i) {
    using S = DriveResult::Status;
    if (run.drives[i].status != S::changed && run.drives[i].status != S::added) continue;
    const auto& d = *run.entries[i];
    LMCFG_ASSIGN_OR_RETURN(const std::string where, archive.work_path(archive_path(d)));
    const std::filesystem::path file = where;
    std::error_code ec;
    std::filesystem::create_directories(file.parent_path(), ec);
    if (ec) return Error(Errc::file_error, file.parent_path().string() + ": " + ec.message());
    LMCFG_TRY(config::write_config_file(*run.configs[i], file, config::FileFormat::json, wo));
    paths.push_back(archive_path(d));
  }
  return paths;
}

std::size_t DriveResult::count(ops::DiffItem::Kind kind) const {
  std::size_t n = 0;
  for (const auto& it : diff.items) n += it.kind == kind;
  return n;
}

const char* status_name(DriveResult::Status s) {
  switch (s) {
    case DriveResult::Status::unchanged:
      return "unchanged";
    case DriveResult::Status::changed:
      return "changed";
    case DriveResult::Status::added:
      return "new";
    case DriveResult::Status::failed:
      return "failed";
  }
  return "?";
}

std::size_t FleetRun::count(DriveResult::Status s) const {
  std::size_t n = 0;
  for (const auto& d : drives) n += d.status == s;
  return n;
}

std::string archive_path(const DriveEntry& d) { return d.name + ".json"; }

Result<FleetRun> fleet_backup(const Inventory& inv, Archive& archive, const FleetOptions& opt) {
  std::vector<LineRun> reads;
  LMCFG_ASSIGN_OR_RETURN(auto run, read_and_compare(inv, archive, opt, reads, Compare::exact));
  std::vector<std::string> paths;
  for (const auto& line : reads) {
    LMCFG_ASSIGN_OR_RETURN(auto written, write_line(archive, opt.db, line));
    paths.insert(paths.end(), written.begin(), written.end());
  }
  LMCFG_ASSIGN_OR_RETURN(run.commit, archive.commit(paths, commit_message(run)));
  // Commissioning: a position read for the first time approves itself (and
  // one from an archive older than approvals adopts the file it held).
  std::vector<const DriveEntry*> read;
  for (const auto& line : reads)
    for (std::size_t i = 0; i < line.entries.size(); ++i)
      if (line.configs[i]) read.push_back(line.entries[i]);
  const std::string before = run.compared_to ? run.compared_to->id : "";
  const std::string after = run.commit ? run.commit->id : before;
  LMCFG_TRY(commission(archive, read, before, after,
                       opt.who.empty() ? std::string("lmcfg fleet") : opt.who,
                       static_cast<std::int64_t>(std::time(nullptr))));
  return run;
}

Result<FleetRun> fleet_status(const Inventory& inv, const Archive& archive,
                              const FleetOptions& opt) {
  std::vector<LineRun> reads;
  return read_and_compare(inv, archive, opt, reads, Compare::drift);
}

std::string commit_message(const FleetRun& run) {
  using S = DriveResult::Status;
  std::string s = "fleet backup: " + std::to_string(run.count(S::changed)) + " changed, " +
                  std::to_string(run.count(S::unchanged)) + " unchanged, " +
                  std::to_string(run.count(S::added)) + " new, " +
                  std::to_string(run.count(S::failed)) + " failed\n";
  for (const auto& r : run.drives) {
    if (r.status == S::changed) {
      s += "\nchanged " + where(r) + ": " + counts_line(r) + "\n";
      append_items(s, r, "  ");
    }
  }
  for (const auto& r : run.drives) {
    if (r.status == S::added && r.devicenet) {
      s += "\nnew " + where(r) + ": " +
           plural(r.devicenet_values, "DeviceNet value", "DeviceNet values") + "\n";
    } else if (r.status == S::added) {
      s += "\nnew " + where(r) + ": " + plural(r.parameters, "parameter", "parameters") + ", " +
           plural(r.curves, "curve", "curves") + ", " +
           plural(r.ct_entries, "CT entry", "CT entries") + "\n";
    }
  }
  for (const auto& r : run.drives) {
    if (r.status == S::failed) {
      s += "\nfailed " + where(r) +
           ", previous file kept: " + (r.error ? one_line(r.error->message) : "unknown error") +
           "\n";
    }
  }
  return s;
}

std::string render_text(const FleetRun& run, bool status) {
  using S = DriveResult::Status;
  std::string s;
  for (const auto& r : run.drives) {
    if (status && !r.kept.empty()) {
      // What matches means (ops/matching.hpp): not drift, but said.
      s += "kept: " + where(r) + ": " + plural(r.kept.size(), "value", "values") +
           " the drive keeps by policy\n";
      for (const auto& k : r.kept)
        s += "    " + ops::kept_text(k) + " (" + ops::kept_reason(k.by) + ")\n";
    }
    if (r.status == S::unchanged) continue;  // counted in the summary
    const char* word = status_name(r.status);
    if (status && r.status == S::changed) word = "drift";
    if (status && r.status == S::added) word = "not in archive";
    s += std::string(word) + ": " + where(r);
    if (r.status == S::failed) s += ": " + (r.error ? r.error->message : "unknown error");
    if (r.status == S::changed) s += ": " + counts_line(r);
    s += "\n";
    if (r.status == S::changed) append_items(s, r, "    ");
  }
  char secs[32];
  std::snprintf(secs, sizeof secs, "%.1f", run.seconds);
  if (status) {
    s += std::to_string(run.drives.size()) +
         " drive(s): " + std::to_string(run.count(S::unchanged)) + " as archived, " +
         std::to_string(run.count(S::changed)) + " drifted, " +
         std::to_string(run.count(S::added)) + " not in archive, " +
         std::to_string(run.count(S::failed)) + " failed";
    if (run.against_approved)
      s += " (against the approved configurations)";
    else if (run.compared_to)
      s += " (against " + run.compared_to->id.substr(0, 12) + ")";
  } else {
    s += std::to_string(run.drives.size()) + " drive(s): " + std::to_string(run.count(S::changed)) +
         " changed, " + std::to_string(run.count(S::unchanged)) + " unchanged, " +
         std::to_string(run.count(S::added)) + " new, " + std::to_string(run.count(S::failed)) +
         " failed; ";
    s += run.commit ? "committed " + run.commit->id.substr(0, 12) : std::string("no changes");
  }
  return s + " in " + secs + " s\n";
}

std::string render_json(const FleetRun& run, bool status) {
  using S = DriveResult::Status;
  nlohmann::ordered_json j;
  j["operation"] = status ? "status" : "backup";
  j["seconds"] = run.seconds;
  j["compared_to"] = run.compared_to ? nlohmann::ordered_json(run.compared_to->id) : nullptr;
  if (!status) j["commit"] = run.commit ? nlohmann::ordered_json(run.commit->id) : nullptr;
  j["counts"] = {{"unchanged", run.count(S::unchanged)},
                 {"changed", run.count(S::changed)},
                 {"new", run.count(S::added)},
                 {"failed", run.count(S::failed)}};
  auto& drives = j["drives"] = nlohmann::ordered_json::array();
  for (const auto& r : run.drives) {
    nlohmann::ordered_json d{{"name", r.name},
                             {"line", r.line},
                             {"id", r.id},
                             {"status", status_name(r.status)},
                             {"seconds", r.seconds}};
    if (r.error) d["error"] = r.error->message;
    if (r.status != S::failed) {
      d["parameters"] = r.parameters;
      d["curves"] = r.curves;
      d["ct_entries"] = r.ct_entries;
      if (r.devicenet) d["devicenet_values"] = r.devicenet_values;
    }
    if (status && r.status != S::failed) {
      auto& kept = d["kept"] = nlohmann::ordered_json::array();
      for (const auto& k : r.kept) kept.push_back(ops::kept_json(k));
    }
    if (r.status == S::changed) {
      auto& items = d["differences"] = nlohmann::ordered_json::array();
      for (const auto& it : r.diff.items) {
        items.push_back({{"kind", ops::kind_name(it.kind)},
                         {"layer", it.layer},
                         {"key", it.key},
                         {"name", it.name},
                         {"archived", it.a},
                         {"live", it.b},
                         {"detail", it.detail},
                         {"text", item_line(it)}});
      }
    }
    drives.push_back(std::move(d));
  }
  return j.dump(2) + "\n";
}

namespace {
// The values --skip-incompatible left out, for the commit message.
std::string skipped_lines(const ops::Plan& p) {
  const std::string s = ops::render_skipped_incompatible(p);
  return s.empty() ? s : "\n" + s;
}
}  // namespace

Result<ArchivedFile> load_archived(const Inventory& inv, const Archive& archive,
                                   const std::string& drive, const std::string& rev) {
  const LineEntry* line = nullptr;
  const DriveEntry* d = inv.find_drive(drive, &line);
  if (!d) {
    return Error(Errc::not_found, inv.path + ": no drive named '" + drive + "' in the inventory");
  }
  ArchivedFile f;
  f.drive = d;
  f.line = line;
  LMCFG_ASSIGN_OR_RETURN(auto source, archive.resolve(rev));
  if (!source) return Error(Errc::not_found, "archive " + archive.dir() + " has no commit yet");
  f.source = *source;
  // The commit id, never the text asked: git's revision syntax takes any text
  // ("HEAD^{/...}" a line break too), and this goes into commit messages,
  // job records and pages.
  f.rev = source->id;
  f.path = archive_path(*d);
  LMCFG_ASSIGN_OR_RETURN(auto text, archive.read(f.path, source->id));
  if (!text) {
    return Error(Errc::not_found, "archive " + archive.dir() + " has no " + f.path + " at " + rev +
                                      " (" + source->id.substr(0, 12) + ")");
  }
  f.file_name = f.path + "@" + source->id.substr(0, 12);
  LMCFG_ASSIGN_OR_RETURN(f.config,
                         config::read_config_text(*text, f.file_name, config::FileFormat::json));
  return f;
}

std::string restore_record_message(const ArchivedFile& f, const ops::RestoreOutcome& outcome,
                                   const ops::Audit& audit, const std::string& cause) {
  const std::string at = f.source.id.substr(0, 12);
  std::string message = "fleet restore: " + f.drive->name + " <- " + f.path + " at " + at;
  // The outcome follows the commit; an automatic restore names its cause in the
  // subject and the outcome in the body. No text a user typed goes into the
  // subject (the revision asked is resolved to `at`, the commit id; the one
  // word that may follow it says it was the approved configuration).
  if (f.rev == "approved" && cause.empty()) message += " (approved)";
  message += cause.empty() ? ": " + ops::outcome_name(outcome) + "\n"
                           : " (" + cause + ")\n\n" + ops::outcome_name(outcome) + "\n";
  const std::string steps = f.line->devicenet
                                ? std::to_string(outcome.set_commands) + " Set command(s)"
                                : std::to_string(outcome.plan.steps.size()) + " step(s)";
  message += "\nline " + f.line->name + " (" + f.line->port + "), " +
             (f.line->devicenet ? "DeviceNet MAC ID " : "MACID ") + hex(f.drive->id, 2, "h") +
             ", " + steps + "\n" + skipped_lines(outcome.plan);
  // One line: an error message may quote what a peer or a user sent.
  if (outcome.error) message += "\n" + one_line(outcome.error->message) + "\n";
  const std::string tr = ops::trailers(audit);
  if (!tr.empty()) message += "\n" + tr;
  return message;
}

Result<FleetRestoreResult> fleet_restore(const Inventory& inv, Archive& archive,
                                         const FleetRestore& opt) {
  std::string rev = opt.rev;
  if (rev.empty()) {
    // No revision named: the position's approved configuration.
    const DriveEntry* d = inv.find_drive(opt.drive);
    if (!d)
      return Error(Errc::not_found,
                   inv.path + ": no drive named '" + opt.drive + "' in the inventory");
    LMCFG_ASSIGN_OR_RETURN(rev, approved_rev(archive, *d));
  }
  LMCFG_ASSIGN_OR_RETURN(auto f, load_archived(inv, archive, opt.drive, rev));
  if (opt.rev.empty() && rev != "HEAD") f.rev = "approved";  // the record says which
  FleetRestoreResult res;
  res.source = f.source;
  const DriveEntry* d = f.drive;
  // The session of the drive's protocol, the matching restore on it; the
  // connection is released (a simulated line saved) before the record.
  Result<void> closed;
  if (opt.link.is_devicenet()) {
    LMCFG_ASSIGN_OR_RETURN(auto session, ops::DevicenetSession::open(ops::devicenet_link_for(
                                             *opt.link.devicenet, line_drive(*d))));
    res.outcome = opt.restore_devicenet(*session, f.config, f.file_name);
    closed = session->close();
  } else {
    LMCFG_ASSIGN_OR_RETURN(auto session, link::open_session(opt.link.linrs.for_macid(d->id)));
    res.outcome = opt.restore(*session, f.config, f.file_name);
    closed = session->close();
  }
  if (res.outcome.written) {
    LMCFG_ASSIGN_OR_RETURN(
        res.record,
        archive.commit({}, restore_record_message(f, res.outcome, opt.audit, ""), true));
  }
  if (!closed.ok()) return closed.error();
  return res;
}

}  // namespace lmcfg::fleet
