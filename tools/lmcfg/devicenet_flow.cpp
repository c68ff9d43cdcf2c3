// The DeviceNet flows of backup, diff and restore.
#include "devicenet_flow.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <memory>

#include "command.hpp"
#include "confirm.hpp"
#include "devicenet/catalogue.hpp"
#include "ops/interrupt.hpp"

namespace lmcfg::cli {
namespace {

can::TraceLink::Sink file_trace(const std::string& path) {
  auto out = std::make_shared<std::ofstream>(path, std::ios::trunc);
  if (!*out) return nullptr;
  const auto start = std::chrono::steady_clock::now();
  return [out, start](const std::string& line) {
    const std::chrono::duration<double> t = std::chrono::steady_clock::now() - start;
    char stamp[32];
    std::snprintf(stamp, sizeof stamp, "%.6f ", t.count());
    *out << stamp << line << '\n' << std::flush;
  };
}

void print_notes(const CommonOptions& o, const char* command,
                 const std::vector<std::string>& notes) {
  if (o.quiet) return;
  for (const auto& n : notes) std::fprintf(stderr, "%s: %s\n", command, n.c_str());
}

// Every command polls until its echo shows up: a signal stops between two.
Result<void> interrupted_check() {
  if (ops::interrupt_flag().load())
    return Error(Errc::interrupted, "interrupted: the connection was released");
  return {};
}

}  // namespace

Result<ops::DevicenetLinkOptions> devicenet_link_options(const CommonOptions& o) {
  if (!ops::is_can_port(o.port)) {
    return Error(Errc::invalid_argument,
                 "--devicenet-macid needs a CAN port: --port can0 (SocketCAN) or --port "
                 "slcan:/dev/ttyACM0 (serial CAN adapter), not '" +
                     o.port + "'");
  }
  if (o.devicenet_macid.empty())
    return Error(Errc::invalid_argument,
                 "--port " + o.port + " is a CAN link: give the controller's --devicenet-macid");
  LMCFG_ASSIGN_OR_RETURN(const auto mac,
                         devicenet::parse_mac_id("--devicenet-macid", o.devicenet_macid));
  if (o.devicenet_own_macid > 63 || o.devicenet_own_macid == mac)
    return Error(Errc::invalid_argument,
                 "--devicenet-own-macid " + std::to_string(o.devicenet_own_macid) +
                     " must be 0..63 and differ from the controller's MAC ID");
  if (o.can_bitrate != 125000 && o.can_bitrate != 250000 && o.can_bitrate != 500000)
    return Error(Errc::invalid_argument, "--can-bitrate " + std::to_string(o.can_bitrate) +
                                             " is not a DeviceNet bit rate (125000, 250000, "
                                             "500000)");
  ops::DevicenetLinkOptions l;
  l.port = o.port;
  l.holder = o.holder;
  l.can_bitrate = o.can_bitrate;
  l.master.slave_mac = mac;
  l.master.own_mac = static_cast<std::uint8_t>(o.devicenet_own_macid);
  l.master.timeout = transport::Millis(o.timeout_ms);
  l.master.retries = o.retries;
  l.master.duplicate_check_wait = transport::Millis(std::max(o.devicenet_listen_ms, 0));
  // Ctrl-C stops between two polls; the session then releases the connection.
  ops::install_interrupt_handlers();
  l.master.cancel = &ops::interrupt_flag();
  if (!o.io_modules.empty()) {
    LMCFG_ASSIGN_OR_RETURN(l.master.layout, devicenet::parse_modules(o.io_modules));
  }
  if (!o.trace.empty()) {
    l.trace = file_trace(o.trace);
    if (!l.trace) return Error(Errc::file_error, "cannot open trace file '" + o.trace + "'");
  }
  return l;
}

Result<ops::DevicenetBackupOptions> devicenet_read_options(const CommonOptions& o) {
  ops::DevicenetBackupOptions bo;
  bo.module_values = !o.no_module_values;
  if (o.devicenet_motors.empty()) return bo;
  LMCFG_ASSIGN_OR_RETURN(const auto selected,
                         devicenet::parse_motor_list("--devicenet-motors", o.devicenet_motors));
  std::vector<int> motors;
  for (int m = 0; m < 4; ++m)
    if (selected[static_cast<std::size_t>(m)]) motors.push_back(m);
  bo.motors = motors;
  return bo;
}

Result<config::DriveConfig> devicenet_capture(const CommonOptions& o, const db::Database& db,
                                              const DevicenetCapture& c) {
  LMCFG_ASSIGN_OR_RETURN(auto l, devicenet_link_options(o));
  LMCFG_ASSIGN_OR_RETURN(auto bo, devicenet_read_options(o));
  std::vector<std::string> notes;
  bo.live = c.live;
  bo.reset_coded_error = c.reset_coded_error;
  bo.notes = &notes;
  bo.progress = make_progress(o);
  auto cfg = ops::capture_devicenet(l, bo, db);
  end_progress(o);
  print_notes(o, "devicenet", notes);
  return cfg;
}

Result<void> check_devicenet_restore_flags(const RestoreFlags& f) {
  if (f.include_comm || f.no_default || f.no_reset || !f.reconnect.baud.empty() ||
      !f.reconnect.id.empty() || !f.reconnect.checksum.empty())
    return Error(Errc::invalid_argument,
                 "--include-comm, --no-default, --no-reset and --reconnect-* are LinRS options; a "
                 "DeviceNet restore writes only the values that differ");
  if (f.skip_incompatible)
    return Error(Errc::invalid_argument,
                 "--skip-incompatible is a LinRS option; a DeviceNet restore plans against Table "
                 "5-1's ranges and refuses any value outside");
  return {};
}

int restore_devicenet(const config::DriveConfig& file, const std::string& file_name,
                      const CommonOptions& common, const RestoreFlags& f, const db::Database& db) {
  if (auto flags = check_devicenet_restore_flags(f); !flags.ok())
    return fail("restore", flags.error());
  auto l = devicenet_link_options(common);
  if (!l.ok()) return fail("restore", l.error());
  auto read = devicenet_read_options(common);
  if (!read.ok()) return fail("restore", read.error());
  auto session = ops::DevicenetSession::open(*l);
  if (!session.ok()) return fail("restore", session.error());
  ops::RestoreOutcome out;
  const int code = restore_devicenet_on(**session, file, file_name, common, f, *read, db, out);
  if (code != kOk || !out.written) return code;
  if (auto c = (*session)->close(); !c.ok()) return fail("restore", c.error());
  if (!common.quiet)
    std::fprintf(stderr,
                 "restore: %zu Set command(s) sent, verified: the controller matches %s\n"
                 "restore: note: %s\n",
                 out.set_commands, file_name.c_str(), ops::kRuntimeNote);
  return kOk;
}

int restore_devicenet_on(ops::DevicenetSession& session, const config::DriveConfig& file,
                         const std::string& file_name, const CommonOptions& common,
                         const RestoreFlags& f, ops::DevicenetBackupOptions read,
                         const db::Database& db, ops::RestoreOutcome& out) {
  using S = ops::RestoreOutcome::Stage;
  auto failed = [&](const Error& e) {
    out.stage = S::failed;
    out.error = e;
    return fail("restore", e);
  };
  auto& m = session.master();
  std::vector<std::string> notes;
  read.live = false;
  read.notes = &notes;
  auto current = ops::devicenet_backup(m, read, db);
  print_notes(common, "restore", notes);
  if (!current.ok()) return failed(current.error());
  if (auto i = interrupted_check(); !i.ok()) return failed(i.error());
  const auto plan = ops::plan_devicenet_restore(file, *current, db);
  out.set_commands = plan.writes.size();
  const std::string text = ops::render_devicenet_plan(plan, file_name);
  if (plan.refused()) {
    out.stage = S::plan_refused;
    std::fputs(text.c_str(), stderr);
    return kPlanRefused;
  }
  if (f.dry_run || plan.writes.empty()) {
    out.stage = f.dry_run ? S::dry_run : S::nothing_to_do;
    if (!common.quiet || f.dry_run) std::fputs(text.c_str(), stdout);
    if (plan.writes.empty() && !common.quiet)
      std::printf("nothing to do: the controller already matches %s\n", file_name.c_str());
    return kOk;
  }
  // Printed with --yes too: the Set commands are few, and a log of a scripted
  // restore should say what was written.
  if (!common.quiet) std::fputs(text.c_str(), stdout);
  std::fflush(stdout);
  auto consent = confirm("Write these values to DeviceNet MAC ID " + common.devicenet_macid +
                             " on " + common.port + "?",
                         "restore " + file_name + " onto a controller", f.yes);
  if (!consent.ok()) return failed(consent.error());
  if (*consent == ops::Consent::declined) {
    out.stage = S::declined;
    std::fprintf(stderr, "cancelled; nothing written\n");
    return kOk;
  }
  if (auto i = interrupted_check(); !i.ok()) return failed(i.error());
  out.written = true;
  auto mismatches = ops::execute_devicenet_plan(m, plan, file, db, make_progress(common));
  end_progress(common);
  {
    // Recorded once the Set commands went out; the caller closes the session.
    ops::JournalEntry e;
    e.audit = audit_of(f.audit);
    e.command = "restore";
    e.port = common.port;
    e.macid = session.macid();
    e.file = file_name;
    for (const auto& w : plan.writes)
      e.steps.push_back({{"step", e.steps.size() + 1},
                         {"action", "devicenet_set"},
                         {"motor", w.motor == config::kDevicenetController
                                       ? std::string("controller")
                                       : std::string(1, static_cast<char>('A' + w.motor))},
                         {"command", hex(w.get + 1u, 2, "h")},
                         {"old", w.from},
                         {"new", w.to},
                         {"text", w.what}});
    const Error* error = !mismatches.ok() ? &mismatches.error() : nullptr;
    if (error) {
      e.outcome = "failed";
      e.exit_code = exit_code_for(*error);
      e.error = error->message;
    } else if (!mismatches->empty()) {
      e.outcome = "verify mismatch";
      e.exit_code = kVerifyMismatch;
      for (const auto& s : *mismatches) e.error += (e.error.empty() ? "" : "; ") + s;
    } else {
      e.outcome = "restored and verified";
    }
    record_in_journal("restore", std::move(e));
  }
  if (!mismatches.ok()) {
    out.stage = S::failed;
    out.error = mismatches.error();
    std::fprintf(stderr, "lmcfg restore: the controller is partially restored: %s\n",
                 mismatches.error().message.c_str());
    return exit_code_for(mismatches.error());
  }
  out.mismatches = *mismatches;
  if (!mismatches->empty()) {
    out.stage = S::verify_mismatch;
    std::fprintf(stderr, "lmcfg restore: verification found %zu mismatch(es):\n",
                 mismatches->size());
    for (const auto& s : *mismatches) std::fprintf(stderr, "  %s\n", s.c_str());
    return kVerifyMismatch;
  }
  out.stage = S::restored;
  return kOk;
}

}  // namespace lmcfg::cli
