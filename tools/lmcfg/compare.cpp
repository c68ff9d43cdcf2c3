#include "compare.hpp"

#include <map>

#include "command.hpp"
#include "config/config_io.hpp"
#include "devicenet_flow.hpp"

namespace lmcfg::cli {

int load_and_compare(const char* command, const CompareOptions& o, const db::Database& db,
                     Compared& out) {
  SessionHandle session;
  const bool two = !o.b.empty();
  const bool needs_drive = o.a == "drive" || o.b == "drive";
  const bool devicenet = is_devicenet(o.common);
  if (!devicenet && (needs_drive || !o.common.port.empty())) {
    auto s = open_link(o.common);
    if (!s.ok()) return fail(command, s.error());
    session = std::move(*s);
  }
  if (o.a == "-" && o.b == "-")
    return session.fail(command,
                        Error(Errc::invalid_argument,
                              "A and B are both standard input ('-'); at most one side can be"));
  auto load = [&](const std::string& what) -> Result<config::DriveConfig> {
    if (what == "defaults") return ops::factory_defaults_config();
    if (what == "drive" && devicenet) return devicenet_capture(o.common, db, {});
    if (what == "drive") {
      ops::BackupOptions bo;
      bo.full = o.full;
      ProgressBar bar(o.common);
      bo.progress = bar.callback();
      auto r = ops::backup(session->client(), bo, db);
      bar.end();
      return r;
    }
    return config::read_config_file(what);
  };
  auto a = load(o.a);
  if (!a.ok()) return session.fail(command, a.error());
  out.a_name = o.a == "-" ? "(stdin)" : o.a;
  if (!two) {
    out.a = std::move(*a);
    if (session)
      if (auto c = session->close(); !c.ok()) return session.fail(command, c.error());
    return kOk;
  }
  auto b = load(o.b);
  if (!b.ok()) return session.fail(command, b.error());
  out.b_name = o.b == "-" ? "(stdin)" : o.b;
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
  opt.include_live = o.live;
  opt.a_is_defaults = o.a == "defaults";
  opt.b_is_defaults = o.b == "defaults";
  out.result = ops::diff(*a, *b, db, defaults, opt);
  if (session) {
    if (auto c = session->close(); !c.ok()) return session.fail(command, c.error());
  }
  if (link_error) return session.fail(command, *link_error);
  out.a = std::move(*a);
  out.b = std::move(*b);
  return kOk;
}

void add_compare_options(CLI::App* sub, CompareOptions& o, bool b_required, bool json) {
  sub->add_option("A", o.a, "file, -, defaults or drive")->required();
  auto* b = sub->add_option("B", o.b, "file, -, defaults or drive");
  if (b_required) b->required();
  add_link_options(sub, o.common);
  add_devicenet_options(sub, o.common);
  sub->get_option("--port")->required(false);
  add_output_options(sub, o.common);
  if (!json) sub->remove_option(sub->get_option("--json"));
  sub->add_flag("--ignore-metadata", o.ignore_metadata,
                "do not compare identity fields (MACID, firmware, labels)");
  sub->add_flag("--ignore-unit", o.ignore_unit,
                "do not compare per-unit data (communication parameters, MACID)");
  sub->add_flag("--full", o.full, "when reading a drive, read every ROM-writable UPID");
  sub->add_flag("--live", o.live,
                "DeviceNet captures: also compare the informational live values (status words, "
                "actual position, ...)");
}

}  // namespace lmcfg::cli
