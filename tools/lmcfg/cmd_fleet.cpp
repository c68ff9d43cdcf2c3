// lmcfg fleet check|backup|status|restore INVENTORY: every drive of a plant,
// lines in parallel, into a git archive (docs/fleet.md).
#include <unistd.h>

#include <cstdio>
#include <ctime>

#include "command.hpp"
#include "devicenet_flow.hpp"
#include "fleet/approved.hpp"
#include "fleet/fleet.hpp"
#include "fleet/history.hpp"
#include "fleet_cli.hpp"
#include "link_options.hpp"
#include "ops/interrupt.hpp"
#include "restore_flow.hpp"

namespace lmcfg::cli {
namespace {

struct FleetCli {
  CommonOptions common;  // --db, --json, --quiet, --trace; link settings come per line
  // since, rev: "" = each position's approved configuration (docs/fleet.md).
  std::string inventory, archive, since, push, drive, rev;
  std::string position;             // fleet log NAME, fleet approve NAME
  std::string reason, ticket, who;  // fleet approve
  bool no_curves = false, no_ct = false, full = false;
  RestoreFlags flags;
};

Result<fleet::Inventory> load_checked(const FleetCli& o) {
  return load_checked_inventory(o.inventory, o.common);
}

int run_check(const FleetCli& o) {
  auto inv = load_checked(o);
  if (!inv.ok()) return fail("fleet check", inv.error());
  if (!o.common.quiet)
    std::printf("%s: %zu line(s), %zu drive(s): ok\n", o.inventory.c_str(), inv->lines.size(),
                inv->drive_count());
  return kOk;
}

// 0: every drive read; else the exit code of the first failure (4 link, 5 drive refused).
int failure_code(const fleet::FleetRun& run) {
  for (const auto& d : run.drives)
    if (d.status == fleet::DriveResult::Status::failed && d.error) return exit_code_for(*d.error);
  return kOk;
}

int run_fleet(const FleetCli& o, bool status) {
  const char* name = status ? "fleet status" : "fleet backup";
  auto inv = load_checked(o);
  if (!inv.ok()) return fail(name, inv.error());
  auto archive = fleet::Archive::open(o.archive, !status);
  if (!archive.ok()) return fail(name, archive.error());
  const db::Database db = load_database(o.common);
  fleet::FleetOptions fo;
  fo.db = db;
  fo.links = *line_links(*inv, o.common);
  fo.rev = status ? o.since : "HEAD";
  fo.who = ops::current_user();
  fo.backup.curves = !o.no_curves;
  fo.backup.command_table = !o.no_ct;
  fo.backup.full = o.full;
  if (!o.common.quiet) {
    fo.on_drive = [](const fleet::DriveResult& r, std::size_t done, std::size_t total) {
      if (r.error) {
        std::fprintf(stderr, "[%s %zu/%zu] %s: failed: %s\n", r.line.c_str(), done, total,
                     r.name.c_str(), r.error->message.c_str());
      } else if (r.devicenet) {
        std::fprintf(stderr, "[%s %zu/%zu] %s: read %zu DeviceNet value(s) in %.1f s\n",
                     r.line.c_str(), done, total, r.name.c_str(), r.devicenet_values, r.seconds);
      } else {
        std::fprintf(stderr,
                     "[%s %zu/%zu] %s: read %zu parameter(s), %zu curve(s), %zu CT "
                     "entr%s in %.1f s\n",
                     r.line.c_str(), done, total, r.name.c_str(), r.parameters, r.curves,
                     r.ct_entries, r.ct_entries == 1 ? "y" : "ies", r.seconds);
      }
    };
  }
  auto run =
      status ? fleet::fleet_status(*inv, *archive, fo) : fleet::fleet_backup(*inv, *archive, fo);
  if (!run.ok()) return fail(name, run.error());
  if (o.common.json)
    std::fputs(fleet::render_json(*run, status).c_str(), stdout);
  else if (!o.common.quiet || status)
    std::fputs(fleet::render_text(*run, status).c_str(), stdout);
  if (!status && !o.push.empty() && run->commit) {
    if (auto pushed = archive->push(o.push); !pushed.ok()) return fail(name, pushed.error());
  }
  if (int code = failure_code(*run); code != kOk) return code;
  using S = fleet::DriveResult::Status;
  if (status && (run->count(S::changed) || run->count(S::added))) return kDifferent;
  return kOk;
}

int run_restore(const FleetCli& o) {
  ops::install_interrupt_handlers();
  auto inv = load_checked(o);
  if (!inv.ok()) return fail("fleet restore", inv.error());
  const fleet::LineEntry* line = nullptr;
  const fleet::DriveEntry* d = inv->find_drive(o.drive, &line);
  if (!d) {
    return fail("fleet restore", Error(Errc::not_found, o.inventory + ": no drive named '" +
                                                            o.drive + "' in the inventory"));
  }
  // Checked before the archive or the link is touched: nothing is written.
  if (inv->require_reason && o.flags.audit.reason.empty() && !o.flags.dry_run)
    return fail(
        "fleet restore",
        Error(Errc::invalid_argument,
              o.inventory + ": require_reason = true: a restore needs --reason TEXT (why this "
                            "drive is written; recorded in the archive and the journal); nothing "
                            "written"));
  auto overrides = relink_overrides(o.flags.reconnect);
  if (!overrides.ok()) return fail("fleet restore", overrides.error());
  auto archive = fleet::Archive::open(o.archive, false);
  if (!archive.ok()) return fail("fleet restore", archive.error());
  const db::Database db = load_database(o.common);
  fleet::FleetRestore fr;
  fr.drive = o.drive;
  fr.rev = o.rev;
  fr.db = db;
  fr.audit = audit_of(o.flags.audit);
  // The restore lets the telegram in flight complete on SIGINT/SIGTERM.
  const auto links = *line_links(*inv, o.common, &ops::interrupt_flag());
  fr.link = links[static_cast<std::size_t>(line - inv->lines.data())];
  CommonOptions common = o.common;  // the plan's prompt names the drive's port and MACID
  common.port = line->port;
  common.id = hex(d->id, 2, "h");
  common.devicenet_macid = std::to_string(d->id);
  RestoreFlags flags = o.flags;
  flags.undo_name = "fleet-restore";
  flags.position = o.drive;
  if (line->devicenet) {
    if (auto dn = check_devicenet_restore_flags(flags); !dn.ok())
      return fail("fleet restore", dn.error());
  }
  int code = kOk;
  fr.restore = [&](link::Session& s, const config::DriveConfig& file,
                   const std::string& file_name) {
    ops::RestoreOutcome out;
    code = restore_on_session(s, file, file_name, common, flags, *overrides, fr.db, out);
    return out;
  };
  fr.restore_devicenet = [&](ops::DevicenetSession& s, const config::DriveConfig& file,
                             const std::string& file_name) {
    ops::RestoreOutcome out;
    code = restore_devicenet_on(s, file, file_name, common, flags,
                                ops::devicenet_read_for(fleet::line_drive(*d)), fr.db, out);
    return out;
  };
  auto res = fleet::fleet_restore(*inv, *archive, fr);
  if (!res.ok()) return fail("fleet restore", res.error());
  if (line->devicenet && res->outcome.stage == ops::RestoreOutcome::Stage::restored &&
      !o.common.quiet)
    std::fprintf(stderr,
                 "restore: %zu Set command(s) sent, verified: the controller matches %s@%s\n"
                 "restore: note: %s\n",
                 res->outcome.set_commands, fleet::archive_path(*d).c_str(),
                 res->source.id.substr(0, 12).c_str(), ops::kRuntimeNote);
  if (res->record && !o.common.quiet && !o.common.json)
    std::fprintf(stderr, "fleet restore: recorded as %s in %s\n",
                 res->record->id.substr(0, 12).c_str(), o.archive.c_str());
  return code;
}

// The position NAME of fleet log and fleet approve: with --inventory one of
// its drives; without, any valid position name.
Result<fleet::DriveEntry> position_of(const FleetCli& o) {
  fleet::DriveEntry d;
  d.name = o.position;
  if (!o.inventory.empty()) {
    LMCFG_ASSIGN_OR_RETURN(auto inv, fleet::load_inventory(o.inventory));
    const auto* found = inv.find_drive(o.position);
    if (!found)
      return Error(Errc::not_found,
                   o.inventory + ": no drive named '" + o.position + "' in the inventory");
    return *found;
  }
  LMCFG_TRY(fleet::check_position_name(o.position));
  return d;
}

// fleet log NAME: the position's history from the archive.
int run_log(const FleetCli& o) {
  auto d = position_of(o);
  if (!d.ok()) return fail("fleet log", d.error());
  auto archive = fleet::Archive::open(o.archive, false);
  if (!archive.ok()) return fail("fleet log", archive.error());
  auto events = fleet::position_history(*archive, *d);
  if (!events.ok()) return fail("fleet log", events.error());
  if (o.common.json)
    std::printf("%s\n", fleet::history_json(*events).dump(2).c_str());
  else
    std::fputs(fleet::render_history(*events, o.position).c_str(), stdout);
  return kOk;
}

// fleet approve NAME: the position's approved configuration (docs/fleet.md
// "Approved configurations").
int run_approve(const FleetCli& o) {
  auto d = position_of(o);
  if (!d.ok()) return fail("fleet approve", d.error());
  auto archive = fleet::Archive::open(o.archive, false);
  if (!archive.ok()) return fail("fleet approve", archive.error());
  fleet::ApproveRequest req;
  req.rev = o.rev.empty() ? "HEAD" : o.rev;
  req.who = o.who.empty() ? ops::current_user() : o.who;
  req.reason = o.reason;
  req.ticket = o.ticket;
  req.time = static_cast<std::int64_t>(std::time(nullptr));
  auto a = fleet::approve(*archive, *d, req);
  if (!a.ok()) return fail("fleet approve", a.error());
  if (o.common.json)
    std::printf("%s\n", fleet::approval_json(*a).dump(2).c_str());
  else if (!o.common.quiet)
    std::printf("fleet approve: %s <- %s at %s (%s), approved by %s: %s%s\n", d->name.c_str(),
                fleet::archive_path(*d).c_str(), a->commit.substr(0, 12).c_str(), req.rev.c_str(),
                a->who.c_str(), a->reason.c_str(),
                a->ticket.empty() ? "" : (" (ticket " + a->ticket + ")").c_str());
  return kOk;
}

CLI::App* add_part(CLI::App* fleet, const char* name, const char* help, FleetCli& o) {
  auto* sub = fleet->add_subcommand(name, help);
  sub->add_option("INVENTORY", o.inventory, "inventory file (TOML, docs/fleet.md)")->required();
  add_output_options(sub, o.common);
  return sub;
}

}  // namespace

// The line's link settings, checked as the command-line options are; a bad
// value is reported at the line's position in the inventory.
Result<std::vector<ops::LineLink>> line_links(const fleet::Inventory& inv,
                                              const CommonOptions& base,
                                              const std::atomic<bool>* cancel, bool check_only) {
  std::vector<ops::LineLink> links;
  for (const auto& l : inv.lines) {
    CommonOptions c = base;
    c.port = l.port;
    auto set_int = [&](const std::optional<std::int64_t>& v, auto& field) {
      if (v)
        field = static_cast<std::remove_reference_t<decltype(field)>>(
            std::clamp<std::int64_t>(*v, -1, 100'000'000));
    };
    auto at_line = [&](const Error& e) {
      return Error(e.code, l.at.str() + ": line '" + l.name + "': " + e.message);
    };
    if (l.devicenet) {
      // The DeviceNet options' own checks, once per controller (this tool's
      // MAC ID must differ from each).
      set_int(l.can_bitrate, c.can_bitrate);
      set_int(l.devicenet_own_macid, c.devicenet_own_macid);
      set_int(l.devicenet_listen_ms, c.devicenet_listen_ms);
      set_int(l.timeout_ms, c.timeout_ms);
      set_int(l.retries, c.retries);
      ops::LineLink link;
      for (const auto& d : l.drives) {
        c.devicenet_macid = std::to_string(d.id);
        auto dn = devicenet_link_options(c);
        if (!dn.ok()) return at_line(dn.error());
        link.devicenet = std::move(dn).value();
      }
      links.push_back(std::move(link));
      continue;
    }
    // Lines run in parallel: no shared progress line for long waits.
    link::LinkInput in = c;  // the link part of the options, as typed
    in.cancel = cancel;
    if (check_only) {
      if (auto ok = fleet::check_line_link(l, std::move(in)); !ok.ok()) return ok.error();
      links.emplace_back();
      continue;
    }
    auto spec = fleet::line_link_spec(l, std::move(in));
    if (!spec.ok()) return std::move(spec).error();
    links.push_back(std::move(spec).value());
  }
  return links;
}

Result<fleet::Inventory> load_checked_inventory(const std::string& path,
                                                const CommonOptions& base) {
  LMCFG_ASSIGN_OR_RETURN(auto inv, fleet::load_inventory(path));
  // Every line's settings first, then every port (all of their problems at once).
  LMCFG_TRY(line_links(inv, base, nullptr, true));
  LMCFG_TRY(fleet::check_ports(inv));
  return inv;
}

void add_fleet(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<FleetCli>();
  auto* fleet = app.add_subcommand(
      "fleet", "Back up, watch and restore every drive of a plant (inventory + git archive)");
  fleet->require_subcommand(1);
  fleet->footer(
      "Examples:\n"
      "  lmcfg fleet check plant.toml\n"
      "  lmcfg fleet backup plant.toml --archive /srv/lmcfg-archive\n"
      "  lmcfg fleet status plant.toml --archive /srv/lmcfg-archive --since HEAD~7\n"
      "  lmcfg fleet restore plant.toml --archive /srv/lmcfg-archive --drive press3/z-axis \\\n"
      "      --reason \"replaced the motor\" --ticket T-17\n"
      "  lmcfg fleet log press3/z-axis --archive /srv/lmcfg-archive\n"
      "Lines are read in parallel, the drives of a line one after another. docs/fleet.md has the\n"
      "inventory format and the archive workflow.");
  add_part(fleet, "check", "Validate an inventory: keys, names, MACIDs, ports", *o)
      ->callback([o, &exit_code] { exit_code = run_check(*o); });
  for (bool status : {false, true}) {
    auto* sub = add_part(fleet, status ? "status" : "backup",
                         status ? "Read every drive and report drift from the archive "
                                  "(exit 0 none, 1 drift, 4/5 failures)"
                                : "Back up every drive into the archive: one git commit per run",
                         *o);
    sub->add_option("--archive", o->archive, "the archive: a git repository (backup creates it)")
        ->required();
    sub->add_flag("--no-curves", o->no_curves, "do not read curves");
    sub->add_flag("--no-ct", o->no_ct, "do not read the command table");
    sub->add_flag("--full", o->full, "read every ROM-writable UPID");
    if (status)
      sub->add_option("--since", o->since,
                      "compare against this archive revision (git syntax) instead of each "
                      "position's approved configuration");
    else
      sub->add_option("--push", o->push, "push the commit to this remote (name, URL or path)");
    sub->callback([o, &exit_code, status] { exit_code = run_fleet(*o, status); });
  }
  auto* restore =
      add_part(fleet, "restore", "Restore a position's archived file onto the drive now there", *o);
  restore->add_option("--archive", o->archive, "the archive (a git repository)")->required();
  restore->add_option("--drive", o->drive, "the position's name in the inventory")->required();
  restore->add_option("--rev", o->rev,
                      "archive revision to restore from (git syntax); default: the position's "
                      "approved configuration");
  add_restore_flags(restore, o->flags);
  restore->callback([o, &exit_code] { exit_code = run_restore(*o); });

  auto* log = fleet->add_subcommand(
      "log", "A position's history from the archive: backups and restores, who and why");
  log->add_option("NAME", o->position, "the position's name (its file is NAME.json)")->required();
  log->add_option("--archive", o->archive, "the archive (a git repository)")->required();
  log->add_option("--inventory", o->inventory,
                  "the inventory: NAME must be one of its drives (docs/fleet.md)");
  add_output_options(log, o->common);
  log->footer(
      "Newest first: the commits that changed NAME.json (fleet backup) and the records of fleet\n"
      "restore onto NAME, with the time, who (the Operator: trailer, else the commit's author),\n"
      "why (Reason:, Ticket:) and the subject. --json: the array GET "
      "/api/v1/drives/NAME/history\n"
      "returns.");
  log->callback([o, &exit_code] { exit_code = run_log(*o); });

  auto* approve = fleet->add_subcommand(
      "approve", "Record a revision of a position's file as its approved configuration");
  approve->add_option("NAME", o->position, "the position's name (its file is NAME.json)")
      ->required();
  approve->add_option("--archive", o->archive, "the archive (a git repository)")->required();
  approve->add_option("--rev", o->rev,
                      "the archive revision to approve (git syntax; default HEAD)");
  approve->add_option("--reason", o->reason, "why this configuration is approved (required)");
  approve->add_option("--ticket", o->ticket, "a ticket id, recorded with the approval");
  approve->add_option("--who", o->who, "who approves (default: the OS user)");
  approve->add_option("--inventory", o->inventory,
                      "the inventory: NAME must be one of its drives (docs/fleet.md)");
  add_output_options(approve, o->common);
  approve->footer(
      "fleet status, fleet restore and lmcfg serve compare with and restore the approved\n"
      "configuration; backups record every state but never approve one, except a position's\n"
      "first backup (commissioning). Kept as refs/lmcfg/approved/NAME in the archive.");
  approve->callback([o, &exit_code] { exit_code = run_approve(*o); });
}

}  // namespace lmcfg::cli
