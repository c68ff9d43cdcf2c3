// lmcfg diff A B: compare two configurations; each side is a file, `defaults`
// or `drive` (read live through the link options). Exit 0 identical, 1
// different, 2 or more on error, like diff(1).
#include <cstdio>
#include <map>

#include "command.hpp"
#include "config/config_io.hpp"
#include "link_options.hpp"
#include "ops/diff.hpp"

namespace lmcfg::cli {
namespace {

struct DiffCli {
  CommonOptions common;
  std::string a, b;
  bool ignore_metadata = false;
  bool ignore_unit = false;
  bool full = false;
};

int run(DiffCli& o) {
  std::optional<db::Database> holder;
  const db::Database* db = load_database(o.common, holder);
  std::unique_ptr<ops::Session> session;
  const bool needs_drive = o.a == "drive" || o.b == "drive";
  if (needs_drive || !o.common.port.empty()) {
    auto s = open_link(o.common);
    if (!s.ok()) return fail("diff", s.error());
    session = std::move(*s);
  }
  if (o.a == "-" && o.b == "-")
    return fail("diff", Error(Errc::invalid_argument,
                              "A and B are both standard input ('-'); at most one side can be"));
  auto load = [&](const std::string& what) -> Result<config::DriveConfig> {
    if (what == "defaults") return ops::factory_defaults_config();
    if (what == "drive") {
      ops::BackupOptions bo;
      bo.full = o.full;
      bo.progress = make_progress(o.common);
      auto r = ops::backup(session->client(), bo, db);
      end_progress(o.common);
      return r;
    }
    return config::read_config_file(what);
  };
  auto a = load(o.a);
  if (!a.ok()) return fail("diff", a.error());
  auto b = load(o.b);
  if (!b.ok()) return fail("diff", b.error());
  // Factory defaults are known for everything: compared within the other
  // side's scope, so a partial capture is not reported as lacking the rest.
  if (o.a == "defaults" && o.b != "defaults") a = ops::factory_defaults_config(b->scope);
  if (o.b == "defaults" && o.a != "defaults") b = ops::factory_defaults_config(a->scope);

  std::map<std::uint16_t, std::optional<std::uint32_t>> asked;
  std::optional<Error> link_error;
  ops::DefaultLookup defaults = [&](std::uint16_t upid) -> std::optional<std::uint32_t> {
    if (!session) return std::nullopt;
    auto it = asked.find(upid);
    if (it != asked.end()) return it->second;
    // The drive's own default value (05h 07h); a refusal leaves it unknown.
    auto r = unless_refused(session->client().get_default(upid));
    if (!r.ok()) link_error = r.error();
    return asked[upid] = r.ok() ? *r : std::nullopt;
  };
  ops::DiffOptions opt;
  opt.ignore_metadata = o.ignore_metadata || o.a == "defaults" || o.b == "defaults" ||
                        o.a == "drive" || o.b == "drive";
  opt.ignore_unit = o.ignore_unit;
  auto result = ops::diff(*a, *b, db, defaults, opt);
  if (session) {
    if (auto c = session->close(); !c.ok()) return fail("diff", c.error());
  }
  if (link_error) return fail("diff", *link_error);
  const std::string an = o.a == "-" ? "(stdin)" : o.a, bn = o.b == "-" ? "(stdin)" : o.b;
  std::fputs(
      (o.common.json ? ops::render_json(result, an, bn) : ops::render_text(result, an, bn)).c_str(),
      stdout);
  return result.identical() ? kOk : kDifferent;
}

const Register reg(20, [](CLI::App& app, int& exit_code) {
  auto o = std::make_shared<DiffCli>();
  auto* sub = app.add_subcommand(
      "diff", "Compare two configurations (files, factory defaults or a live drive)");
  sub->footer(
      "A and B are each a file (.json/.xml; '-' reads standard input, format from the "
      "content), 'defaults' (factory defaults, within the other side's scope) or 'drive' (read "
      "live).\n"
      "A side that captured a layer, the curves or the command table the other did not is a "
      "difference\n"
      "(scope); values that do not fit their type or range are flagged INVALID on their side.\n"
      "Examples:\n"
      "  lmcfg diff axis1.json axis2.json\n"
      "  lmcfg diff defaults axis1.json\n"
      "  lmcfg diff axis1.json drive --port /dev/ttyUSB0 --id 0x11\n"
      "  ssh host cat axis1.xml | lmcfg diff - axis1.json\n"
      "Exit status: 0 identical, 1 different, 2 or more on error.");
  sub->add_option("A", o->a, "file, -, defaults or drive")->required();
  sub->add_option("B", o->b, "file, -, defaults or drive")->required();
  add_link_options(sub, o->common);
  sub->get_option("--port")->required(false);
  add_output_options(sub, o->common);
  sub->add_flag("--ignore-metadata", o->ignore_metadata,
                "do not compare identity fields (MACID, firmware, labels)");
  sub->add_flag("--ignore-unit", o->ignore_unit,
                "do not compare per-unit data (communication parameters, MACID)");
  sub->add_flag("--full", o->full, "when reading a drive, read every ROM-writable UPID");
  sub->callback([o, &exit_code] { exit_code = run(*o); });
});

}  // namespace
}  // namespace lmcfg::cli
