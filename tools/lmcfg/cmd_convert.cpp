// lmcfg convert IN OUT [--to json|xml]: lossless conversion between the JSON
// and XML configuration files (and migration of older format versions). The
// decoded views (curves; command table entries with their names and, through
// the UPID database, their commands) are regenerated on every write, so a
// round trip JSON -> XML -> JSON is byte-identical.
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include "command.hpp"
#include "config/atomic_file.hpp"
#include "config/config_io.hpp"
#include "link_options.hpp"
#include "report/json_reports.hpp"

namespace lmcfg::cli {
namespace {

struct ConvertCli {
  CommonOptions common;
  std::string in, out, to;
};

Result<config::FileFormat> output_format(const ConvertCli& o) {
  if (!o.to.empty()) return config::format_from_name(o.to);
  if (o.out == "-")
    return Error(Errc::invalid_argument,
                 "OUT is standard output ('-'): give the format with --to json|xml");
  return config::format_from_path(o.out);
}

int run(const ConvertCli& o) {
  auto format = output_format(o);
  if (!format.ok()) return fail("convert", format.error());
  auto cfg = config::read_config_file(o.in);
  if (!cfg.ok()) return fail("convert", cfg.error());
  const db::Database db = load_database(o.common);
  config::WriteOptions wo;
  std::optional<ops::DatabaseCtDecoder> ct_decoder;
  if (!db.is_empty()) wo.ct_decoder = &ct_decoder.emplace(db);
  auto text = config::write_config_text(*cfg, *format, wo);
  if (!text.ok()) return fail("convert", text.error());
  if (o.out == "-") {
    if (o.common.json)
      return fail("convert", Error(Errc::invalid_argument,
                                   "--json and OUT '-' both write to standard output; choose one"));
    std::fwrite(text->data(), 1, text->size(), stdout);
    return kOk;
  }
  auto w = config::write_config_file(*cfg, o.out, *format, wo);
  if (!w.ok()) return fail("convert", w.error());
  if (o.common.json) {
    const auto j = report::convert_json(config::input_name(o.in), o.out, *format, text->size(),
                                        *cfg, !db.is_empty());
    std::printf("%s\n", j.dump().c_str());
  }
  return kOk;
}

}  // namespace

void add_convert(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<ConvertCli>();
  auto* sub =
      app.add_subcommand("convert", "Convert a configuration file between JSON and XML (lossless)");
  sub->footer(
      "IN '-' reads standard input (format from the content); OUT '-' writes standard output "
      "(with --to).\n"
      "Examples:\n"
      "  lmcfg convert axis1.json axis1.xml\n"
      "  ssh host cat axis1.xml | lmcfg convert - axis1.json");
  sub->add_option("IN", o->in, "Input file (.json or .xml; format version 1 is migrated), or -")
      ->required();
  sub->add_option("OUT", o->out, "Output file; replaced atomically; or - (needs --to)")->required();
  sub->add_option("--to", o->to, "Output format (default: from OUT's extension)")
      ->check(CLI::IsMember({"json", "xml"}));
  add_output_options(sub, o->common);
  sub->callback([o, &exit_code] { exit_code = run(*o); });
}
}  // namespace lmcfg::cli
