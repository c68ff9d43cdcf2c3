// What each job of the desk does on its thread (ui/desk.hpp): the same
// library calls as `lmcfg scan`, `info`, `backup`, `diff`, `restore` and
// `undo`, with the CLI's recovery record, undo record and journal.
#include <map>

#include "config/config_io.hpp"
#include "link/scan.hpp"
#include "ops/backup.hpp"
#include "ops/diff.hpp"
#include "ops/drive_info.hpp"
#include "ops/recovery.hpp"
#include "ops/undo.hpp"
#include "report/report.hpp"
#include "ui/desk_impl.hpp"

namespace lmcfg::ui {

namespace fs = std::filesystem;

namespace {

std::string checksum_mode(const codec::ChecksumConfig& c) {
  const std::string n = link::checksum_name(c);
  return n.substr(0, n.find(' '));
}

// "20261129T001500Z" from "2026-11-29T00:15:00Z": a file name's date.
std::string compact_time(std::string iso) {
  std::string out;
  for (char c : iso)
    if (c != '-' && c != ':') out += c;
  return out;
}

}  // namespace

void Desk::Impl::run_find(const std::string& job, const FindRequest& req) {
  DriveLink probe;
  probe.port = req.port;
  auto session = open(probe, true);
  if (!session.ok()) return fail(job, session.error());
  link::ScanOptions so;
  so.bauds = req.bauds;
  so.first_id = req.first_id;
  so.last_id = req.last_id;
  so.progress = progress_of(job);
  auto scanned = link::scan(**session, so);
  auto closed = (*session)->close();
  // The port and its lock let go before each drive found is opened again to
  // read its state (a serial port stays open and locked while its session lives).
  session->reset();
  if (!scanned.ok()) return fail(job, scanned.error());
  if (!closed.ok()) return fail(job, closed.error());
  Json found = Json::array();
  for (const auto& f : scanned->found) {
    DeskDrive d;
    d.link.port = req.port;
    d.link.baud = f.line.baud;
    d.link.parity = std::string(transport::parity_name(f.line.parity));
    d.link.stop_bits = f.line.stop_bits;
    d.link.checksum = checksum_mode(f.checksum);
    d.link.coverage = std::string(link::coverage_name(f.checksum.coverage));
    d.link.id = f.id;
    d.found = f.how;
    update(job, [&](DeskJob& j) { j.step = "reading the state of ID " + std::to_string(f.id); });
    if (auto s = open(d.link); s.ok()) {
      auto info = ops::read_drive_info((*s)->client(), opt.db.get(), 0);
      if (info.ok()) d.info = Json::parse(ops::render_info_json(*info), nullptr, false);
      (void)(*s)->close();
    }
    remember(d);
    found.push_back(drive_key(d.link));
  }
  Json notes = Json::array();
  for (const auto& n : scanned->notes) notes.push_back(n);
  update(job, [&](DeskJob& j) {
    j.result = Json{{"found", found},
                    {"notes", notes},
                    {"passes", scanned->passes.size()},
                    {"seconds", scanned->seconds}};
  });
}

void Desk::Impl::run_connect(const std::string& job, const DriveLink& l) {
  auto session = open(l);
  if (!session.ok()) return fail(job, session.error());
  update(job, [](DeskJob& j) { j.step = "reading the drive's state"; });
  auto info = ops::read_drive_info((*session)->client(), opt.db.get(), 8);
  auto closed = (*session)->close();
  if (!info.ok()) return fail(job, info.error());
  if (!closed.ok()) return fail(job, closed.error());
  DeskDrive d;
  d.link = l;
  d.found = "connected";
  d.info = Json::parse(ops::render_info_json(*info), nullptr, false);
  remember(d);
  update(job, [&](DeskJob& j) { j.result = Json{{"found", Json::array({drive_key(l)})}}; });
}

void Desk::Impl::run_backup(const std::string& job, const DeskDrive& d) {
  auto session = open(d.link);
  if (!session.ok()) return fail(job, session.error());
  ops::BackupOptions bo;
  bo.progress = progress_of(job);
  auto cfg = ops::backup((*session)->client(), bo, opt.db.get());
  auto closed = (*session)->close();
  if (!cfg.ok()) return fail(job, cfg.error());
  if (!closed.ok()) return fail(job, closed.error());
  cfg->identity.link = (*session)->link_settings();
  const std::string key = drive_key(d.link);
  const std::string name = key + "-" + compact_time(iso_now()) + ".json";
  if (auto w = config::write_config_file(*cfg, opt.folder / name); !w.ok())
    return fail(job, w.error());
  update(job, [&](DeskJob& j) {
    j.result = Json{{"file", name}, {"path", (opt.folder / name).string()}};
  });
}

Result<std::optional<config::DriveConfig>> Desk::Impl::compare_side(
    const std::string& job, const std::string& against, const std::optional<DeskDrive>& other) {
  if (against == "defaults") return std::optional<config::DriveConfig>();
  if (!other) {
    LMCFG_ASSIGN_OR_RETURN(auto f, config::read_config_file(opt.folder / against));
    return std::optional<config::DriveConfig>(std::move(f));
  }
  // The other drive, read as `lmcfg backup` reads it; its port is this job's too.
  update(job, [](DeskJob& j) { j.step = "reading the other drive"; });
  LMCFG_ASSIGN_OR_RETURN(auto session, open(other->link));
  ops::BackupOptions bo;
  bo.progress = progress_of(job);
  auto cfg = ops::backup(session->client(), bo, opt.db.get());
  auto closed = session->close();
  if (!cfg.ok()) return cfg.error();
  LMCFG_TRY(closed);
  cfg->identity.link = session->link_settings();
  return std::optional<config::DriveConfig>(std::move(cfg).value());
}

void Desk::Impl::run_compare(const std::string& job, const DeskDrive& d, const std::string& against,
                             const std::optional<DeskDrive>& other) {
  auto side = compare_side(job, against, other);
  if (!side.ok()) return fail(job, side.error());
  config::DriveConfig file = side->value_or(config::DriveConfig{});
  auto session = open(d.link);
  if (!session.ok()) return fail(job, session.error());
  ops::BackupOptions bo;
  bo.progress = progress_of(job);
  if (against != "defaults") {  // the file's scope, as `lmcfg diff FILE drive` reads it
    bo.layers = file.scope.layers;
    bo.curves = file.scope.curves;
    bo.command_table = file.scope.command_table;
    bo.full = file.scope.parameters == config::ParamSet::full;
  }
  auto live = ops::backup((*session)->client(), bo, opt.db.get());
  if (!live.ok()) {
    (void)(*session)->close();
    return fail(job, live.error());
  }
  if (against == "defaults") file = ops::factory_defaults_config(live->scope);
  auto& client = (*session)->client();
  std::map<std::uint16_t, std::optional<std::uint32_t>> asked;
  ops::DefaultLookup defaults = [&](std::uint16_t upid) -> std::optional<std::uint32_t> {
    if (auto it = asked.find(upid); it != asked.end()) return it->second;
    auto r = unless_refused(client.get_default(upid));
    return asked[upid] = r.ok() ? *r : std::nullopt;
  };
  ops::DiffOptions o;
  o.ignore_metadata = against == "defaults";
  // A file compared with a drive: the drive's own communication values and
  // MACID are not the file's business (a restore keeps them: `lmcfg diff
  // --ignore-unit`), so a spare restored from a file reads identical.
  o.ignore_unit = against != "defaults";
  o.a_is_defaults = against == "defaults";
  const auto r = ops::diff(file, *live, opt.db.get(), defaults, o);
  auto closed = (*session)->close();
  if (!closed.ok()) return fail(job, closed.error());
  const std::string a_name = against == "defaults" ? "factory defaults"
                             : other               ? "drive " + drive_key(other->link)
                                                   : against;
  report::ReportOptions ro;
  ro.generated_at = iso_now();
  std::string html = report::render_diff_report(file, a_name, *live, "drive", r, opt.db.get(), ro);
  update(job, [&](DeskJob& j) {
    j.html = std::move(html);
    j.result = Json{{"against", against},
                    {"identical", r.identical()},
                    {"differences", r.items.size()},
                    {"text", ops::render_text(r, a_name, "drive")}};
  });
}

void Desk::Impl::run_plan(const std::string& job, const DeskDrive& d, const std::string& path,
                          bool undo) {
  StoredPlan sp;
  sp.drive = drive_key(d.link);
  sp.undo = undo;
  std::string file = path;
  if (undo) {
    auto dir = ops::undo_dir();
    if (!dir.ok()) return fail(job, dir.error());
    auto records = ops::list_undo(*dir, sp.drive);
    if (!records.ok()) return fail(job, records.error());
    if (records->empty())
      return fail(job, Error(Errc::not_found,
                             "no undo record of this drive in " + (*dir / sp.drive).string() +
                                 ": nothing was written to it from this computer"));
    file = records->front().path.string();
  }
  auto cfg = config::read_config_file(file);
  if (!cfg.ok()) return fail(job, cfg.error());
  sp.file = std::move(cfg).value();
  sp.file_name = fs::path(file).filename().string();
  auto session = open(d.link);
  if (!session.ok()) return fail(job, session.error());
  ops::RestoreOptions ro;
  auto rec = ops::recovery_path("restore", d.link.port, static_cast<std::uint8_t>(d.link.id));
  if (!rec.ok()) return fail(job, rec.error());
  ro.recovery_path = *rec;
  ro.port = d.link.port;
  ro.skip_incompatible = true;  // listed on the plan page; the write needs the box ticked
  ro.progress = progress_of(job);
  auto plan = ops::plan_restore((*session)->client(), sp.file, opt.db.get(), ro);
  auto closed = (*session)->close();
  if (!plan.ok()) return fail(job, plan.error());
  sp.plan = std::move(plan).value();
  sp.expires = std::chrono::system_clock::now() + opt.plan_lifetime;
  std::lock_guard<std::mutex> lock(mu);
  sp.id = "p" + std::to_string(next_plan++);
  jobs.at(job).result = Json{{"plan_id", sp.id}, {"file", sp.file_name}};
  plans[sp.id] = std::move(sp);
}

Result<std::string> Desk::report_html(const std::string& name) const {
  LMCFG_ASSIGN_OR_RETURN(const auto path, file(name));
  LMCFG_ASSIGN_OR_RETURN(const auto cfg, config::read_config_file(path));
  report::ReportOptions ro;
  ro.generated_at = iso_now();
  return report::render_report(cfg, name, impl_->opt.db.get(), ro);
}

}  // namespace lmcfg::ui
