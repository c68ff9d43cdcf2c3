// lmcfg backup -o FILE: read a drive's configuration and write it to a file.
#include <cstdio>
#include <filesystem>

#include "command.hpp"
#include "common/families.hpp"
#include "config/config_io.hpp"
#include "devicenet_flow.hpp"
#include "link_options.hpp"
#include "report/json_reports.hpp"

namespace lmcfg::cli {
namespace {

struct BackupCli {
  CommonOptions common;
  std::string output;
  std::string format;
  std::string layers = "os,mc,intf,appl";
  bool no_curves = false;
  bool no_ct = false;
  bool full = false;
  bool no_describe = false;
  std::vector<std::string> labels;
  bool reset_coded_error = false;
  std::string family;
};

// The file (or stdout) and, for a DeviceNet controller, the summary.
int write_backup(const BackupCli& o, const config::DriveConfig& cfg,
                 std::optional<config::FileFormat> format, const db::Database& db) {
  const bool to_stdout = o.output == "-";
  config::WriteOptions wo;
  std::optional<ops::DatabaseCtDecoder> ct_decoder;
  if (!db.is_empty()) wo.ct_decoder = &ct_decoder.emplace(db);
  if (to_stdout) {
    auto text = config::write_config_text(cfg, *format, wo);
    if (!text.ok()) return fail("backup", text.error());
    if (std::fwrite(text->data(), 1, text->size(), stdout) != text->size() ||
        std::fflush(stdout) != 0)
      return fail("backup", Error(Errc::file_error, "-o -: cannot write to stdout"));
  } else {
    auto w = config::write_config_file(cfg, o.output, format, wo);
    if (!w.ok()) return fail("backup", w.error());
  }
  if (!cfg.devicenet) return kOk;
  const auto& dn = *cfg.devicenet;
  if (o.common.json) {
    std::printf("%s\n", report::devicenet_backup_json(o.output, cfg).dump().c_str());
  } else if (!o.common.quiet) {
    std::fprintf(stderr,
                 "backup: DeviceNet MAC ID %s: %zu motor(s), %zu value(s), %zu live value(s) -> "
                 "%s\nbackup: note: %s\n",
                 cfg.identity.macid.c_str(), dn.motors.size(), dn.values.size(), dn.live.size(),
                 o.output.c_str(), ops::kRuntimeNote);
  }
  return kOk;
}

int run(BackupCli& o) {
  // The output is checked before the drive is talked to.
  if (auto ok = check_output_path(o.output, "-o"); !ok.ok()) return fail("backup", ok.error());
  const bool to_stdout = o.output == "-";
  if (to_stdout && o.common.json) {
    return fail("backup", Error(Errc::invalid_argument,
                                "-o - and --json both write to stdout; use one of them"));
  }
  std::optional<config::FileFormat> format;
  if (!o.format.empty()) {
    auto f = config::format_from_name(o.format);
    if (!f.ok()) return fail("backup", f.error());
    format = *f;
  } else if (to_stdout) {
    format = config::FileFormat::json;  // -o - without --format: JSON
  } else if (auto f = config::format_from_path(o.output); !f.ok()) {
    return fail("backup", f.error());
  }
  auto layers = parse_layers(o.layers);
  if (!layers.ok()) return fail("backup", layers.error());
  std::map<std::string, std::string> labels;
  for (const auto& l : o.labels) {
    auto eq = l.find('=');
    if (eq == std::string::npos || eq == 0) {
      return fail("backup", Error(Errc::invalid_argument, "--label '" + l + "' must be KEY=VALUE"));
    }
    labels[l.substr(0, eq)] = l.substr(eq + 1);
  }
  auto family = families::parse(o.family, "--family");
  if (!family.ok()) return fail("backup", family.error());
  const db::Database db = load_database(o.common);
  if (is_devicenet(o.common)) {
    auto cfg = devicenet_capture(o.common, db, {true, o.reset_coded_error});
    if (!cfg.ok()) return fail("backup", cfg.error());
    cfg->identity.labels = labels;
    return write_backup(o, *cfg, format, db);
  }
  auto session = open_link(o.common);
  if (!session.ok()) return fail("backup", session.error());
  ops::BackupOptions bo;
  bo.layers = *layers;
  bo.curves = !o.no_curves;
  bo.command_table = !o.no_ct;
  bo.full = o.full;
  bo.ask_drive = !o.no_describe;
  bo.family = *family;
  ProgressBar bar(o.common);
  bo.progress = bar.callback();
  ops::BackupReport notes;
  bo.report = &notes;
  auto cfg = ops::backup((*session)->client(), bo, db);
  bar.end();
  auto closed = (*session)->close();
  if (!cfg.ok()) return session->fail("backup", cfg.error());
  if (!closed.ok()) return session->fail("backup", closed.error());
  cfg->identity.link = (*session)->link_settings();
  cfg->identity.labels = labels;
  if (int code = write_backup(o, *cfg, format, db); code != kOk) return code;
  std::size_t params = 0;
  for (const auto& l : cfg->layers) params += l.size();
  const auto& st = (*session)->client().stats();
  if (o.common.json) {
    std::printf("%s\n", report::backup_json(o.output, *cfg, st.requests).dump().c_str());
  } else if (!o.common.quiet) {
    std::fprintf(
        stderr,
        "backup: %zu parameter(s), %zu curve(s), %zu command table entr%s -> %s (%llu telegrams)\n",
        params, cfg->curves.size(), cfg->ct_entries.size(),
        cfg->ct_entries.size() == 1 ? "y" : "ies", o.output.c_str(),
        static_cast<unsigned long long>(st.requests));
    for (const auto& n : notes.notes) std::fprintf(stderr, "backup: %s\n", n.c_str());
  }
  return kOk;
}

}  // namespace

void add_backup(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<BackupCli>();
  auto* sub = app.add_subcommand("backup",
                                 "Read a drive's configuration and write it to a JSON or XML file");
  sub->footer(
      "Examples:\n"
      "  lmcfg backup --port /dev/ttyUSB0 --id 0x11 -o axis1.json\n"
      "  lmcfg backup --port tcp://10.0.0.5:4001 --full --label machine=press3 -o axis1.xml\n"
      "Reads the modified-parameter list of each layer, every curve and every defined command "
      "table entry,\n"
      "and records each parameter's type and factory default (asking the drive for what the UPID "
      "database\n"
      "does not know, unless --no-describe).\n"
      "Sends read telegrams only; the file is written atomically and only when the whole backup "
      "succeeded.");
  add_link_options(sub, o->common);
  add_devicenet_options(sub, o->common);
  add_output_options(sub, o->common);
  sub->add_option("-o,--output", o->output,
                  "output file (.json or .xml); - = stdout (JSON unless --format)")
      ->required();
  sub->add_option("--format", o->format, "json or xml (default: from the extension)");
  sub->add_option("--layers", o->layers, "layers to read: os,mc,intf,appl")->capture_default_str();
  sub->add_flag("--no-curves", o->no_curves, "do not read curves");
  sub->add_flag("--no-ct", o->no_ct, "do not read the command table");
  sub->add_flag("--full", o->full, "read every ROM-writable UPID (audit-grade snapshot)");
  sub->add_flag(
      "--no-describe", o->no_describe,
      "do not ask the drive for types and defaults the UPID database lacks (fewer telegrams)");
  sub->add_option("--family", o->family,
                  "drive family: E1100 (default), B1100, C1100, E1200, E1400 (docs/families.md)");
  sub->add_option("--label", o->labels, "KEY=VALUE stored in the file (machine, axis, ...)");
  sub->add_flag("--reset-coded-error", o->reset_coded_error,
                "DeviceNet: reset a coded error the controller reports from before the backup "
                "instead of refusing to read");
  sub->callback([o, &exit_code] { exit_code = run(*o); });
}
}  // namespace lmcfg::cli
