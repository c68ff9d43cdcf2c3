// lmcfg convert IN OUT [--to json|xml]: lossless conversion between the JSON
// and XML configuration files (and migration of older format versions).
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include "command.hpp"
#include "config/config_io.hpp"

namespace lmcfg::cli {
namespace {

int run_convert(const std::string& in, const std::string& out, const std::string& to) {
  std::optional<config::FileFormat> out_format;
  if (!to.empty()) {
    auto f = config::format_from_name(to);
    if (!f.ok()) {
      std::fprintf(stderr, "lmcfg convert: %s\n", f.error().message.c_str());
      return kInvalidInput;
    }
    out_format = *f;
  } else {
    auto f = config::format_from_path(out);
    if (!f.ok()) {
      std::fprintf(stderr, "lmcfg convert: %s\n", f.error().message.c_str());
      return kInvalidInput;
    }
    out_format = *f;
  }
  auto cfg = config::read_config_file(in);
  if (!cfg.ok()) {
    std::fprintf(stderr, "lmcfg convert: %s\n", cfg.error().message.c_str());
    return kInvalidInput;
  }
  auto w = config::write_config_file(*cfg, out, out_format);
  if (!w.ok()) {
    std::fprintf(stderr, "lmcfg convert: %s\n", w.error().message.c_str());
    return kInvalidInput;
  }
  return kOk;
}

const Register reg(70, [](CLI::App& app, int& exit_code) {
  auto* sub = app.add_subcommand("convert", "Convert a configuration file between JSON and XML (lossless)");
  auto in = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>();
  auto to = std::make_shared<std::string>();
  sub->add_option("IN", *in, "Input file (.json or .xml; format version 1 is migrated)")->required();
  sub->add_option("OUT", *out, "Output file; replaced atomically")->required();
  sub->add_option("--to", *to, "Output format (default: from OUT's extension)")
      ->check(CLI::IsMember({"json", "xml"}));
  sub->callback([in, out, to, &exit_code] { exit_code = run_convert(*in, *out, *to); });
});

}  // namespace
}  // namespace lmcfg::cli
