// The DeviceNet flows of backup, diff and restore.
#include "devicenet_flow.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <memory>

#include "command.hpp"
#include "devicenet/catalogue.hpp"
#include "ops/devicenet_restore.hpp"
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
  ProgressBar bar(o);
  bo.progress = bar.callback();
  auto cfg = ops::capture_devicenet(l, bo, db);
  bar.end();
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
  if (!common.quiet && !common.json)
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
  RestoreTarget t;
  t.noun = "controller";
  t.question = "Write these values to DeviceNet MAC ID " + common.devicenet_macid + " on " +
               common.port + "?";
  t.macid = session.macid();
  t.plan_with_yes = true;
  ops::DevicenetRestoreRunOptions ro;
  ro.read = std::move(read);
  ro.dry_run = f.dry_run;
  ProgressBar bar(common);
  ro.progress = bar.callback();
  t.bar = &bar;
  ro.cancel = &ops::interrupt_flag();
  // The read's notes come before the plan, so a person sees what was not read
  // before being asked.
  bool notes_shown = false;
  auto show_notes = [&](const ops::DevicenetPlan& p) {
    if (!notes_shown) print_notes(common, "restore", p.notes);
    notes_shown = true;
  };
  ro.confirm = [&](const ops::DevicenetPlan& plan) {
    bar.end();
    show_notes(plan);
    return confirm_restore(ops::render_devicenet_plan(plan, file_name), t, file_name, common, f);
  };
  out = ops::run_devicenet_restore(session, file, db, ro);
  bar.end();
  if (out.devicenet) show_notes(*out.devicenet);
  return finish_restore(out, t, file_name, common, f);
}

}  // namespace lmcfg::cli
