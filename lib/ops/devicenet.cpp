#include "ops/devicenet.hpp"

#include <algorithm>
#include <map>

#include "common/version.hpp"
#include "db/database.hpp"
#include "devicenet/catalogue.hpp"
#include "link/port.hpp"

namespace lmcfg::ops {
namespace {

using devicenet::Master;
using devicenet::Motor;

std::array<bool, 4> select(int motor) {
  std::array<bool, 4> s{};
  if (motor != config::kDevicenetController) s[static_cast<std::size_t>(motor)] = true;
  return s;
}

std::optional<Motor> motor_of(int motor) {
  if (motor == config::kDevicenetController) return std::nullopt;
  return static_cast<Motor>(motor);
}

bool refused(const Error& e) { return e.code == ErrorClass::drive_refusal; }

std::string command_hex(std::uint8_t id) { return hex(id, 2, "h"); }

std::string motor_label(int motor) {
  return motor == config::kDevicenetController
             ? std::string("controller")
             : std::string("motor ") + static_cast<char>('A' + motor);
}

// "Controller P": the database's name, else the capture's, without the "Get "
// every recorded command carries (the Get/Set pair is one setting).
std::string command_name(const db::DevicenetCommand* c, const config::DevicenetValue& v) {
  std::string n = c && !c->name.empty() ? c->name : v.name;
  if (n.rfind("Get ", 0) == 0) n.erase(0, 4);
  return n;
}

config::DevicenetValue value_of(int motor, std::uint8_t get, std::uint16_t raw = 0) {
  return {motor, get, raw, {}, {}, {}};
}

std::size_t read_count(const std::vector<int>& motors, bool live, bool module_values) {
  std::size_t n = 0;
  for (const auto& vc : devicenet::value_commands()) {
    if ((vc.live && !live) || (!vc.live && !vc.settable) || (vc.needs_module && !module_values))
      continue;
    n += vc.per_motor ? motors.size() : 1;
  }
  return n;
}

Result<void> check_coded_error(Master& m, bool reset, std::vector<std::string>* notes) {
  LMCFG_ASSIGN_OR_RETURN(const std::uint16_t pending, m.command({}, 0x0A, 0));
  if (pending == 0) return {};
  std::string what = "coded error " + hex(pending, 4, "h");
  if (auto t = devicenet::coded_error_text(pending); !t.empty()) what += " " + std::string(t);
  if (!reset) {
    return Error(Errc::drive_refused,
                 "the controller reports " + what +
                     " from before this run; values read now could not be told from refused "
                     "reads: clear it (the PLC, or --reset-coded-error to reset it here) and run "
                     "again");
  }
  LMCFG_TRY(m.command({}, 0x0B, 0));
  if (notes) notes->push_back("reset the controller's pending " + what);
  return {};
}

Result<std::vector<int>> configured_motors(Master& m) {
  std::vector<int> motors;
  for (Motor mo : devicenet::kMotors) {
    const int i = static_cast<int>(mo);
    auto r = m.command(select(i), 0x24, 0);
    // Taken only on the resend with the toggle flipped, the motor's Command
    // Toggle did not change: asked once more (now with the inverse of the
    // toggle it shows), a present motor's toggle follows.
    if (r.ok() && !m.last_toggle_witnessed()) r = m.command(select(i), 0x24, 0);
    if (r.ok()) {
      motors.push_back(i);
      continue;
    }
    // Absent: refused with 8111h "Drive not master" or 8110h, or not taken
    // at all (the readings of docs/devicenet.md "A motor the controller does
    // not have"), recognised by the master rather than waited for.
    const auto code = m.last_coded_error();
    if (refused(r.error()) && (code == 0x8111 || code == 0x8110 || m.last_not_taken())) continue;
    return std::move(r).error();
  }
  return motors;
}

}  // namespace

bool is_can_port(const std::string& port) { return link::is_can_port(port); }

Result<std::unique_ptr<DevicenetSession>> DevicenetSession::open(const DevicenetLinkOptions& o) {
  auto s = std::unique_ptr<DevicenetSession>(new DevicenetSession);
  s->opt_ = o;
  can::SlcanOptions so;
  so.bitrate = o.can_bitrate;
  LMCFG_ASSIGN_OR_RETURN(s->link_, link::open_can_link(o.port, so, o.holder));
  if (o.trace) {
    s->link_ = std::make_unique<can::TraceLink>(
        std::move(s->link_), o.trace, [layout = o.master.layout](const can::Frame& f, bool) {
          return devicenet::describe_frame(f, layout);
        });
  }
  s->master_ = std::make_unique<Master>(*s->link_, o.master);
  if (o.check_own_mac) LMCFG_TRY(s->master_->check_own_mac());
  LMCFG_TRY(s->master_->connect());
  return s;
}

config::LinkSettings DevicenetSession::link_settings() const {
  config::LinkSettings l;
  l.port = opt_.port;
  l.baud = std::to_string(opt_.can_bitrate);
  return l;
}

Result<void> DevicenetSession::close() {
  if (!master_ || !master_->connected()) return {};
  return master_->release();
}

Result<config::DriveConfig> capture_devicenet(const DevicenetLinkOptions& l,
                                              const DevicenetBackupOptions& opt,
                                              const db::Database& db) {
  LMCFG_ASSIGN_OR_RETURN(auto session, DevicenetSession::open(l));
  auto cfg = devicenet_backup(session->master(), opt, db);
  auto closed = session->close();
  LMCFG_TRY(cfg);
  LMCFG_TRY(closed);
  cfg->identity.macid = std::to_string(session->macid());
  cfg->identity.link = session->link_settings();
  cfg->devicenet->can_bitrate = l.can_bitrate;
  cfg->devicenet->io_modules = devicenet::module_names(l.master.layout);
  return cfg;
}

std::int64_t devicenet_word(const db::DevicenetCommand* c, std::uint16_t raw) {
  // Table 5-1 gives signed ranges ("-32256 to +32256") for positions: the
  // word is two's complement there.
  const bool is_signed =
      c && ((c->spec.min && *c->spec.min < 0) || c->range_text.rfind('-', 0) == 0);
  return is_signed ? std::int64_t{static_cast<std::int16_t>(raw)} : std::int64_t{raw};
}

std::string devicenet_value_name(const db::Database& db, const config::DevicenetValue& v) {
  const std::string name = command_name(db.devicenet_command(v.command), v);
  return motor_label(v.motor) + ": " +
         (name.empty() ? "command " + command_hex(v.command)
                       : name + " (" + command_hex(v.command) + ")");
}

std::string devicenet_value_text(const db::Database& db, const config::DevicenetValue& v) {
  const auto* c = db.devicenet_command(v.command);
  const std::string raw = std::to_string(v.raw);
  if (c && c->spec.scale) {
    std::string s = db::format_scaled(devicenet_word(c, v.raw), *c->spec.scale);
    if (!c->spec.unit.empty()) s += " " + c->spec.unit;
    return s + " (raw " + raw + ")";
  }
  if (!v.scaled.empty())
    return v.scaled + (v.unit.empty() ? "" : " " + v.unit) + " (raw " + raw + ")";
  return raw;
}

void annotate_devicenet(config::DevicenetSection& s, const db::Database& db) {
  for (auto* list : {&s.values, &s.live}) {
    for (auto& v : *list) {
      const auto* c = db.devicenet_command(v.command);
      if (!c) continue;
      v.name = c->name;
      v.unit = c->spec.unit;
      v.scaled = c->spec.scale ? db::format_scaled(devicenet_word(c, v.raw), *c->spec.scale) : "";
    }
  }
}

Result<config::DriveConfig> devicenet_backup(Master& m, const DevicenetBackupOptions& opt,
                                             const db::Database& db) {
  config::DriveConfig cfg;
  cfg.scope.layers = {false, false, false, false};
  cfg.scope.curves = false;
  cfg.scope.command_table = false;
  cfg.identity.tool_version = kToolVersion;
  cfg.identity.captured_at = utc_now();
  if (!db.is_empty()) cfg.identity.upid_db_hash = db.info().content_hash;
  if (!db.is_empty()) cfg.identity.upid_db_version = std::to_string(db.info().schema_version);
  LMCFG_TRY(check_coded_error(m, opt.reset_coded_error, opt.notes));
  const bool was_running = m.last_status().run_state();
  auto& s = cfg.devicenet.emplace();
  if (opt.motors) {
    s.motors = *opt.motors;
  } else {
    LMCFG_ASSIGN_OR_RETURN(s.motors, configured_motors(m));
  }
  const std::size_t total = read_count(s.motors, opt.live, opt.module_values);
  std::size_t done = 0;
  const std::vector<int> controller{config::kDevicenetController};
  std::vector<std::string> no_module;
  for (const auto& vc : devicenet::value_commands()) {
    if ((vc.live && !opt.live) || (!vc.live && !vc.settable)) continue;
    if (vc.needs_module && !opt.module_values) continue;
    for (int target : vc.per_motor ? s.motors : controller) {
      if (opt.progress) opt.progress("devicenet", done++, total);
      auto r = m.command(select(target), vc.get, 0);
      if (!r.ok()) {
        if (!refused(r.error())) return std::move(r).error();
        // A refused read is data about this controller (no encoder module,
        // a firmware without the command), not a failed backup.
        const auto code = m.last_coded_error();
        if (vc.needs_module && code == 0x8120) {
          no_module.push_back(devicenet_value_name(db, value_of(target, vc.get)));
        } else if (opt.notes) {
          std::string why = r.error().message;
          if (code != 0) {
            why = "refused with coded error " + hex(code, 4, "h");
            if (auto t = devicenet::coded_error_text(code); !t.empty()) why += " " + std::string(t);
          }
          opt.notes->push_back("not read: " + devicenet_value_name(db, value_of(target, vc.get)) +
                               ": " + why);
        }
        continue;
      }
      auto& list = vc.live ? s.live : s.values;
      list.push_back({target, vc.get, *r, {}, {}, {}});
    }
  }
  if (opt.progress) opt.progress("devicenet", total, total);
  if (opt.notes && !no_module.empty()) {
    std::string n =
        "no master encoder or IO module (coded error 8120h Encoder not exists), so "
        "not read: ";
    for (std::size_t i = 0; i < no_module.size(); ++i) n += (i ? ", " : "") + no_module[i];
    opt.notes->push_back(n);
  }
  if (opt.notes && was_running && !m.last_status().run_state())
    opt.notes->push_back(
        "the controller left RUN state during the backup (status " +
        hex(m.last_status().low, 4, "h") +
        "), after refusing a read; seed 000 §5.2: RUN Request must be released and set again (the "
        "PLC's Control Word). --devicenet-motors and --no-module-values avoid the probes");
  annotate_devicenet(s, db);
  return cfg;
}

DevicenetPlan plan_devicenet_restore(const config::DriveConfig& file,
                                     const config::DriveConfig& current, const db::Database& db) {
  DevicenetPlan p;
  if (!file.devicenet) {
    p.problems.push_back("the file is a LinRS drive capture, not a DeviceNet controller's");
    return p;
  }
  const auto& want = *file.devicenet;
  const std::vector<int> none;
  const auto& have_motors = current.devicenet ? current.devicenet->motors : none;
  std::map<std::pair<int, int>, std::uint16_t> have;
  if (current.devicenet)
    for (const auto& v : current.devicenet->values) have[{v.motor, v.command}] = v.raw;
  for (int motor : want.motors)
    if (std::find(have_motors.begin(), have_motors.end(), motor) == have_motors.end())
      p.problems.push_back(devicenet::target_name(motor_of(motor)) +
                           " is in the file but not configured on the controller (it refuses "
                           "commands to it)");
  for (const auto& v : want.values) {
    const std::string name = devicenet_value_name(db, v);
    const auto* vc = devicenet::value_command(v.command);
    if (!vc || !vc->settable || vc->live) {
      p.problems.push_back(name + ": Table 5-1 has no Set command for it");
      continue;
    }
    const auto* c = db.devicenet_command(static_cast<std::uint8_t>(v.command + 1));
    const auto value = devicenet_word(c, v.raw);
    if (c && ((c->spec.min && value < *c->spec.min) || (c->spec.max && value > *c->spec.max))) {
      p.problems.push_back(name + ": " + devicenet_value_text(db, v) +
                           " is outside Table 5-1's range " + c->range_text +
                           (c->unit_text.empty() || c->unit_text == "-"
                                ? std::string()
                                : " (unit " + c->unit_text + ")"));
      continue;
    }
    auto it = have.find({v.motor, v.command});
    if (it == have.end()) {
      if (std::find(have_motors.begin(), have_motors.end(), v.motor) != have_motors.end() ||
          v.motor == config::kDevicenetController)
        p.problems.push_back(name + ": the controller did not let it be read (see the notes)");
      continue;
    }
    if (it->second == v.raw) {
      ++p.unchanged;
      continue;
    }
    const std::string from = devicenet_value_text(db, value_of(v.motor, v.command, it->second));
    const std::string to = devicenet_value_text(db, v);
    p.writes.push_back(
        {v.motor, v.command, it->second, v.raw, name + ": " + from + " -> " + to, name, from, to});
  }
  return p;
}

std::string render_devicenet_plan(const DevicenetPlan& p, const std::string& file_name) {
  std::string out;
  if (p.refused()) {
    out += "restore plan for " + file_name + ": REFUSED, nothing written:\n";
    for (const auto& s : p.problems) out += "  problem: " + s + "\n";
    return out;
  }
  out += "restore plan for " + file_name + ": " + std::to_string(p.writes.size()) +
         " Set command(s), " + std::to_string(p.unchanged) + " value(s) already equal\n";
  for (const auto& w : p.writes)
    out += "  set " + command_hex(static_cast<std::uint8_t>(w.get + 1)) + " " + w.what + "\n";
  out += "note: " + std::string(kRuntimeNote) + ".\n";
  return out;
}

Result<std::vector<std::string>> execute_devicenet_plan(Master& m, const DevicenetPlan& p,
                                                        const config::DriveConfig& file,
                                                        const db::Database& db,
                                                        const Progress& progress) {
  // A refused plan, or a file that is no controller's capture, sends nothing.
  if (p.refused()) {
    std::string all;
    for (const auto& pr : p.problems) all += (all.empty() ? "" : "; ") + pr;
    return Error(Errc::plan_refused, "restore refused: " + all + "; nothing written");
  }
  if (!file.devicenet)
    return Error(
        Errc::plan_refused,
        "the file is a LinRS drive capture, not a DeviceNet controller's; nothing written");
  std::size_t done = 0;
  const std::size_t total = p.writes.size() + file.devicenet->values.size();
  for (const auto& w : p.writes) {
    if (progress) progress("write", done++, total);
    auto r = m.command(select(w.motor), static_cast<std::uint8_t>(w.get + 1), w.to);
    if (!r.ok()) {
      // The Set may have executed with its echo lost: the rerun's plan reads it.
      return Error(r.error().code,
                   r.error().message + " (writing " + w.what +
                       ", which the controller may or may not have executed; " +
                       std::to_string(&w - p.writes.data()) + " of " +
                       std::to_string(p.writes.size()) +
                       " Set command(s) done before it, the rest not sent: run the restore again)");
    }
  }
  std::vector<std::string> mismatches;
  for (const auto& v : file.devicenet->values) {
    if (progress) progress("verify", done++, total);
    LMCFG_ASSIGN_OR_RETURN(const auto now, m.command(select(v.motor), v.command, 0));
    if (now != v.raw)
      mismatches.push_back(devicenet_value_name(db, v) + ": file " + devicenet_value_text(db, v) +
                           ", controller " +
                           devicenet_value_text(db, value_of(v.motor, v.command, now)));
  }
  if (progress) progress("verify", total, total);
  return mismatches;
}

}  // namespace lmcfg::ops
