// lmcfg get UPID / lmcfg set UPID VALUE [--ram|--rom]: one parameter, with names and units.
#include <unistd.h>

#include <cstdio>
#include <iostream>

#include "command.hpp"
#include "link_options.hpp"
#include "ops/drive_info.hpp"
#include "ops/param_info.hpp"
#include "ops/restore.hpp"
#include "ops/undo.hpp"
#include "report/json_reports.hpp"
#include "restore_flow.hpp"

namespace lmcfg::cli {
namespace {

struct ParamCli {
  CommonOptions common;
  std::string upid_text;
  std::string value_text;
  bool ram = false;
  bool rom = false;
  bool stop_mc = false;
  bool yes = false;  // --yes: for --rom, what --stop-mc means
  bool include_comm = false;
  bool no_undo = false;
  AuditFlags audit;  // set: --reason, --ticket
};

Result<std::uint16_t> parse_upid(const std::string& t) { return db::parse_upid(t); }

// The database's description, completed from the drive; says so unless --quiet.
Result<db::ValueSpec> describe(client::Client& c, const ParamCli& o, const char* cmd,
                               std::uint16_t upid, const db::Parameter* d, bool with_range) {
  LMCFG_ASSIGN_OR_RETURN(auto desc, ops::describe_parameter(c, upid, d, with_range));
  if (!desc.asked.empty() && !o.common.quiet) {
    std::fprintf(stderr, "lmcfg %s: %04X %s; asked the drive: %s\n", cmd, upid,
                 d ? "is only partly described by the database" : "is not in the database",
                 desc.asked.c_str());
  }
  return desc.spec;
}

void print_value(const ParamCli& o, std::uint16_t upid, const db::Parameter* d,
                 const db::ValueSpec& spec, const char* where, std::uint32_t v,
                 const std::optional<ops::UndoSaved>& undo = std::nullopt) {
  const bool known = spec.type || !spec.labels.empty();
  const std::string text = known ? db::format_value(spec, v) : std::to_string(v);
  if (o.common.json) {
    const auto j = report::param_json(upid, d, spec, where, v, text, undo);
    std::printf("%s\n", j.dump().c_str());
  } else {
    const char* name = !d                ? "(not in database)"
                       : d->name.empty() ? "(no name in database)"
                                         : d->name.c_str();
    std::printf("%04X %s [%s] = %s%s\n", upid, name, where, text.c_str(), known ? "" : " (raw)");
  }
}

// After the drive refused a request: its error state, with the error text
// (a refusal can put MC into its error state, LinRS §15), as a line for
// stderr; "" for other errors.
std::string refusal_state(client::Client& c, const char* cmd, const Error& e) {
  if (e.code != ErrorClass::drive_refusal) return "";
  auto st = ops::read_error_state(c);
  return "lmcfg " + std::string(cmd) + ": after the refusal: " +
         (st.ok() ? ops::render_error_state(*st)
                  : "the drive's error state could not be read: " + st.error().message) +
         "\n";
}

// The session's fail() (with the link advice), then the drive's state after a
// refusal.
int fail_with_state(const SessionHandle& session, const char* cmd, const Error& e,
                    const std::string& state) {
  const int rc = session.fail(cmd, e);
  std::fputs(state.c_str(), stderr);
  return rc;
}

int run_get(ParamCli& o) {
  auto upid = parse_upid(o.upid_text);
  if (!upid.ok()) return fail("get", upid.error());
  const db::Database db = load_database(o.common);
  const db::Parameter* d = db.find(*upid);
  auto session = open_link(o.common);
  if (!session.ok()) return fail("get", session.error());
  auto& c = (*session)->client();
  auto v = o.rom ? c.read_rom(*upid) : c.read_ram(*upid);
  const std::string state = v.ok() ? "" : refusal_state(c, "get", v.error());
  auto spec =
      v.ok() ? describe(c, o, "get", *upid, d, false) : Result<db::ValueSpec>(db::ValueSpec{});
  auto closed = (*session)->close();
  if (!v.ok()) return fail_with_state(*session, "get", v.error(), state);
  if (!spec.ok()) return session->fail("get", spec.error());
  if (!closed.ok()) return session->fail("get", closed.error());
  print_value(o, *upid, d, *spec, o.rom ? "ROM" : "RAM", *v);
  return kOk;
}

// The manual requires the MC software stopped for configuration (seed 003
// §10; ROM values act after its restart, §9.2), and LinRS has no message that
// tells whether it runs: `set --rom` stops it (--stop-mc, or asked on a
// terminal), writes, and starts it again; otherwise it refuses with that advice.
Result<bool> confirm_stop_mc(const ParamCli& o, std::uint16_t upid) {
  if (!o.rom || o.stop_mc || o.yes) return o.rom;
  if (!::isatty(STDIN_FILENO))
    return Error(Errc::invalid_argument,
                 "writing ROM needs the MC software stopped (seed 003 §10); add --stop-mc to stop "
                 "it, write and start it again (the axis stops meanwhile), or write RAM only "
                 "without --rom; nothing written");
  char hex[8];
  std::snprintf(hex, sizeof hex, "%04X", upid);
  std::fprintf(stderr,
               "Writing ROM needs the MC software stopped (seed 003 §10). Stop MC of drive %s on "
               "%s, write %s and start MC again? [y/N] ",
               o.common.id.c_str(), o.common.port.c_str(), hex);
  std::string answer;
  std::getline(std::cin, answer);
  if (answer != "y" && answer != "Y" && answer != "yes")
    return Error(Errc::cancelled, "cancelled; nothing written");
  return true;
}

// The undo record of `set --rom`: the parameter's layer as it is now.
Result<void> save_set_undo(const ParamCli& o, client::Client& c, std::uint16_t upid,
                           const db::Database& db, std::optional<ops::UndoSaved>& undo,
                           std::optional<std::uint32_t>& old) {
  LMCFG_ASSIGN_OR_RETURN(auto dir, ops::undo_dir());
  LMCFG_ASSIGN_OR_RETURN(auto cfg, ops::undo_config_for_parameter(c, upid, db));
  if (const auto* p = cfg.find_param(upid)) old = p->value;
  LMCFG_ASSIGN_OR_RETURN(
      undo, ops::save_undo(
                ops::UndoOptions{true, dir, o.common.port, c.options().id, "set", ops::kUndoKeep},
                cfg, db));
  return {};
}

// The journal's record of a `set` (`error`: the first failure, or none).
void journal_set(const ParamCli& o, std::uint8_t macid, std::uint16_t upid, const db::Parameter* d,
                 const db::ValueSpec& spec, std::uint32_t value,
                 const std::optional<std::uint32_t>& old, const std::optional<ops::UndoSaved>& undo,
                 const Error* error) {
  ops::JournalEntry e;
  e.audit = audit_of(o.audit);
  e.command = "set";
  e.port = o.common.port;
  e.macid = macid;
  e.steps.push_back(report::param_write_step_json(o.rom && o.ram ? "write_ram_rom"
                                                  : o.rom        ? "write_rom"
                                                                 : "write_ram",
                                                  upid, d, spec, old, value));
  e.outcome = error ? "failed" : "written";
  e.exit_code = error ? exit_code_for(*error) : kOk;
  if (error) e.error = error->message;
  if (undo) e.undo = undo->path.string();
  record_in_journal("set", std::move(e));
}

int run_set(ParamCli& o) {
  auto upid = parse_upid(o.upid_text);
  if (!upid.ok()) return fail("set", upid.error());
  const db::Database db = load_database(o.common);
  const db::Parameter* d = db.find(*upid);
  const bool comm = ops::is_comm_parameter(db, *upid);
  if (comm && !o.include_comm) {
    char hex[8];
    std::snprintf(hex, sizeof hex, "%04X", *upid);
    return fail("set", Error(Errc::invalid_argument,
                             std::string(hex) + (d && !d->name.empty() ? " " + d->name : "") +
                                 " is a communication parameter (baud rate, MACID, checksum or "
                                 "parity): writing it changes the link the drive answers on; "
                                 "add --include-comm to write it anyway; nothing written"));
  }
  auto stop = confirm_stop_mc(o, *upid);
  if (!stop.ok() && stop.error().code == make_error_code(Errc::cancelled)) {
    std::fprintf(stderr, "%s\n", stop.error().message.c_str());  // as `default` does
    return kOk;
  }
  if (!stop.ok()) return fail("set", stop.error());
  auto session = open_link(o.common);
  if (!session.ok()) return fail("set", session.error());
  auto& c = (*session)->client();
  auto spec = describe(c, o, "set", *upid, d, true);
  if (!spec.ok()) return session->fail("set", spec.error());
  auto value = db::parse_value(*spec, o.value_text);
  if (!value.ok()) return session->fail("set", value.error());
  // A ROM value is what the drive starts with, so its old value is saved first.
  // A RAM value gets no undo record: "This change will affect the position
  // controller behavior only after a restart of the MC-SW" (LinRS §9.2, of a
  // ROM write whose RAM value differs): a restart brings the ROM value back.
  std::optional<ops::UndoSaved> undo;
  // The ROM value before the write, for the journal: the layer's modified
  // list (read for the undo record) holds it when it is not the default.
  std::optional<std::uint32_t> old;
  if (o.rom && !o.no_undo) {
    if (auto saved = save_set_undo(o, c, *upid, db, undo, old); !saved.ok())
      return session->fail("set", saved.error());
  }
  if (*stop) {
    if (auto r = c.stop_mc(); !r.ok())
      return fail_with_state(*session, "set", r.error(), refusal_state(c, "set", r.error()));
  }
  Result<void> w = o.rom && o.ram ? c.write_ram_rom(*upid, *value)
                   : o.rom        ? c.write_rom(*upid, *value)
                                  : c.write_ram(*upid, *value);
  const std::string state = w.ok() ? "" : refusal_state(c, "set", w.error());
  Result<void> started{};
  if (*stop) started = c.start_mc();  // also after a failed write: leave MC as found
  auto closed = (*session)->close();
  if (undo) print_undo_saved(*undo, o.common);
  const Error* error = !w.ok()         ? &w.error()
                       : !started.ok() ? &started.error()
                       : !closed.ok()  ? &closed.error()
                                       : nullptr;
  journal_set(o, c.options().id, *upid, d, *spec, *value, old, undo, error);
  if (!w.ok()) return fail_with_state(*session, "set", w.error(), state);
  if (!started.ok()) return session->fail("set", started.error());
  if (!closed.ok()) return session->fail("set", closed.error());
  if (comm && !o.common.quiet)
    std::fprintf(stderr,
                 "lmcfg set: warning: %04X is a communication parameter: the link changes when "
                 "the value takes effect; reach the drive with the new settings\n",
                 *upid);
  if (*stop && !o.common.quiet)
    std::fprintf(stderr, "lmcfg set: MC was stopped for the ROM write and started again\n");
  print_value(o, *upid, d, *spec, o.rom && o.ram ? "RAM+ROM" : o.rom ? "ROM" : "RAM", *value, undo);
  return kOk;
}

}  // namespace

void add_get(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<ParamCli>();
  auto* sub =
      app.add_subcommand("get", "Read one parameter (RAM by default, --rom for the stored value)");
  sub->footer("Example: lmcfg get 13A2 --port /dev/ttyUSB0 --rom");
  sub->add_option("UPID", o->upid_text, "UPID in hex (13A2, 0x13A2, 13A2h)")->required();
  add_link_options(sub, o->common);
  add_output_options(sub, o->common);
  sub->add_flag("--rom", o->rom, "read the ROM value (§10 05h 00h) instead of RAM (§9 03h 00h)");
  sub->callback([o, &exit_code] { exit_code = run_get(*o); });
}

void add_set(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<ParamCli>();
  auto* sub = app.add_subcommand(
      "set", "Write one parameter (RAM by default; --rom, or --ram --rom for both)");
  sub->footer(
      "VALUE: raw number (16, 0x10), scaled value with unit (100 mm) or enum label (By "
      "Parameter).\n"
      "Examples:\n"
      "  lmcfg set 13A2 16 --port /dev/ttyUSB0\n"
      "  lmcfg set 13A2 16 --port /dev/ttyUSB0 --rom --stop-mc");
  sub->add_option("UPID", o->upid_text, "UPID in hex (13A2, 0x13A2, 13a2h)")->required();
  sub->add_option("VALUE", o->value_text, "value")->required();
  add_link_options(sub, o->common);
  add_output_options(sub, o->common);
  sub->add_flag("--ram", o->ram, "write RAM (live value)");
  sub->add_flag("--rom", o->rom,
                "write ROM (acts after a restart, §9.2); needs MC stopped (§10): asks on a "
                "terminal, else needs --stop-mc");
  sub->add_flag("--stop-mc", o->stop_mc,
                "with --rom: stop MC before the write and start it again after (§13.3, §13.4)");
  sub->add_flag("--yes,-y", o->yes,
                "do not ask for confirmation; with --rom: stop MC, write and start it again "
                "(as --stop-mc)");
  sub->add_flag("--include-comm", o->include_comm,
                "allow writing a communication parameter (baud rate, MACID, checksum, parity)");
  sub->add_flag("--no-undo", o->no_undo,
                "with --rom: do not save the layer's previous values as an undo record first "
                "(lmcfg undo); a RAM write gets none, a reset brings the ROM value back");
  add_audit_options(sub, o->audit);
  sub->callback([o, &exit_code] { exit_code = run_set(*o); });
}
}  // namespace lmcfg::cli
