// lmcfg get UPID / lmcfg set UPID VALUE [--ram|--rom]: one parameter, with names and units.
#include <cstdio>
#include <nlohmann/json.hpp>

#include "command.hpp"
#include "link_options.hpp"
#include "ops/param_info.hpp"

namespace lmcfg::cli {
namespace {

struct ParamCli {
  CommonOptions common;
  std::string upid_text;
  std::string value_text;
  bool ram = false;
  bool rom = false;
};

Result<std::uint16_t> parse_upid(const std::string& t) {
  auto v = parse_number(t, true);
  if (!v || *v > 0xFFFF)
    return Error(Errc::invalid_argument, "UPID '" + t + "' is not 16-bit hex (e.g. 13A2)");
  return static_cast<std::uint16_t>(*v);
}

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
                 const db::ValueSpec& spec, const char* where, std::uint32_t v) {
  const bool known = spec.type || !spec.labels.empty();
  const std::string text = known ? db::format_value(spec, v) : std::to_string(v);
  if (o.common.json) {
    nlohmann::ordered_json j;
    char hex[8];
    std::snprintf(hex, sizeof hex, "%04X", upid);
    j["upid"] = hex;
    j["name"] = d ? d->name : "";
    j["type"] = spec.type ? std::string(db::type_name(*spec.type)) : "";
    j["memory"] = where;
    j["raw"] = v;
    j["value"] = text;
    std::printf("%s\n", j.dump().c_str());
  } else {
    const char* name = !d                ? "(not in database)"
                       : d->name.empty() ? "(no name in database)"
                                         : d->name.c_str();
    std::printf("%04X %s [%s] = %s%s\n", upid, name, where, text.c_str(), known ? "" : " (raw)");
  }
}

int run_get(ParamCli& o) {
  auto upid = parse_upid(o.upid_text);
  if (!upid.ok()) return fail("get", upid.error());
  std::optional<db::Database> holder;
  const db::Database* db = load_database(o.common, holder);
  const db::Parameter* d = db ? db->find(*upid) : nullptr;
  auto session = open_link(o.common);
  if (!session.ok()) return fail("get", session.error());
  auto& c = (*session)->client();
  auto v = o.rom ? c.read_rom(*upid) : c.read_ram(*upid);
  auto spec =
      v.ok() ? describe(c, o, "get", *upid, d, false) : Result<db::ValueSpec>(db::ValueSpec{});
  auto closed = (*session)->close();
  if (!v.ok()) return fail("get", v.error());
  if (!spec.ok()) return fail("get", spec.error());
  if (!closed.ok()) return fail("get", closed.error());
  print_value(o, *upid, d, *spec, o.rom ? "ROM" : "RAM", *v);
  return kOk;
}

int run_set(ParamCli& o) {
  auto upid = parse_upid(o.upid_text);
  if (!upid.ok()) return fail("set", upid.error());
  std::optional<db::Database> holder;
  const db::Database* db = load_database(o.common, holder);
  const db::Parameter* d = db ? db->find(*upid) : nullptr;
  auto session = open_link(o.common);
  if (!session.ok()) return fail("set", session.error());
  auto& c = (*session)->client();
  auto spec = describe(c, o, "set", *upid, d, true);
  if (!spec.ok()) return fail("set", spec.error());
  auto value = db::parse_value(*spec, o.value_text);
  if (!value.ok()) return fail("set", value.error());
  Result<void> w = o.rom && o.ram ? c.write_ram_rom(*upid, *value)
                   : o.rom        ? c.write_rom(*upid, *value)
                                  : c.write_ram(*upid, *value);
  auto closed = (*session)->close();
  if (!w.ok()) return fail("set", w.error());
  if (!closed.ok()) return fail("set", closed.error());
  print_value(o, *upid, d, *spec, o.rom && o.ram ? "RAM+ROM" : o.rom ? "ROM" : "RAM", *value);
  return kOk;
}

const Register reg_get(50, [](CLI::App& app, int& exit_code) {
  auto o = std::make_shared<ParamCli>();
  auto* sub =
      app.add_subcommand("get", "Read one parameter (RAM by default, --rom for the stored value)");
  sub->footer("Example: lmcfg get 13A2 --port /dev/ttyUSB0 --rom");
  sub->add_option("UPID", o->upid_text, "UPID in hex (13A2, 0x13A2, 13A2h)")->required();
  add_link_options(sub, o->common);
  add_output_options(sub, o->common);
  sub->add_flag("--rom", o->rom, "read the ROM value (§10 05h 00h) instead of RAM (§9 03h 00h)");
  sub->callback([o, &exit_code] { exit_code = run_get(*o); });
});

const Register reg_set(51, [](CLI::App& app, int& exit_code) {
  auto o = std::make_shared<ParamCli>();
  auto* sub = app.add_subcommand(
      "set", "Write one parameter (RAM by default; --rom, or --ram --rom for both)");
  sub->footer(
      "VALUE: raw number (16, 0x10), scaled value with unit (100 mm) or enum label (By "
      "Parameter).\n"
      "Example: lmcfg set 13A2 16 --port /dev/ttyUSB0 --rom");
  sub->add_option("UPID", o->upid_text, "UPID in hex")->required();
  sub->add_option("VALUE", o->value_text, "value")->required();
  add_link_options(sub, o->common);
  add_output_options(sub, o->common);
  sub->add_flag("--ram", o->ram, "write RAM (live value)");
  sub->add_flag("--rom", o->rom, "write ROM (acts after a restart, §9.2)");
  sub->callback([o, &exit_code] { exit_code = run_set(*o); });
});

}  // namespace
}  // namespace lmcfg::cli
