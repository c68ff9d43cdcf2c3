// lmcfg link: show a drive's LinRS settings and change them safely
// (ops::read_link_settings, ops::plan_link_change, ops::apply_link_change).
#include <cstdio>

#include "command.hpp"
#include "common/bytes.hpp"
#include "confirm.hpp"
#include "fleet/inventory.hpp"
#include "link/port.hpp"
#include "link_options.hpp"
#include "ops/link_settings.hpp"
#include "ops/recovery.hpp"
#include "report/json_reports.hpp"

namespace lmcfg::cli {
namespace {

struct LinkCli {
  CommonOptions common;
  std::string set_baud, set_id, set_checksum, set_parity, set_stop_bits;
  std::vector<std::string> maps;
  std::string inventory, drive;
  bool dry_run = false;
  bool yes = false;
};

Result<ops::LinkChange> parse_change(const LinkCli& o) {
  ops::LinkChange ch;
  auto bad = [](const std::string& opt, const std::string& v, const std::string& why) {
    return Error(Errc::invalid_argument, opt + " '" + v + "': " + why + "; nothing written");
  };
  if (!o.set_baud.empty()) {
    auto b = parse_number(o.set_baud, false);
    transport::SerialSettings s;
    s.baud = b ? *b : 0;
    if (auto v = transport::validate(s); !v.ok())
      return bad("--set-baud", o.set_baud, v.error().message);
    ch.baud = s.baud;
  }
  if (!o.set_id.empty()) {
    auto id = parse_number(o.set_id, false);
    if (!id || *id > 0xFF) return bad("--set-id", o.set_id, "not a MACID 0..255 (0x00..0xFF)");
    ch.macid = static_cast<std::uint8_t>(*id);
  }
  if (!o.set_checksum.empty()) {
    auto c = link::parse_checksum(o.set_checksum);
    if (!c.ok()) return bad("--set-checksum", o.set_checksum, c.error().message);
    ch.checksum = *c;
  }
  if (!o.set_parity.empty()) {
    auto p = link::parse_parity(o.set_parity);
    if (!p.ok()) return bad("--set-parity", o.set_parity, p.error().message);
    ch.parity = *p;
  }
  if (!o.set_stop_bits.empty()) {
    if (o.set_stop_bits != "1" && o.set_stop_bits != "2")
      return bad("--set-stop-bits", o.set_stop_bits, "not 1 or 2");
    ch.stop_bits = o.set_stop_bits == "1" ? 1U : 2U;
  }
  return ch;
}

std::string value_line(ops::LinkSetting s, const ops::LinkValue& v) {
  std::string line = std::string(ops::setting_title(s)) + ": ";
  if (!v.rom) return line + "unknown (" + v.note + ")";
  line += hex(*v.upid, 4, "h") + " = " + std::to_string(*v.rom);
  line += v.text.empty() ? " (" + v.note + ")" : " (" + v.text + ")";
  return line;
}

fleet::LinkKeys keys_of(const link::RelinkCandidate& c) {
  fleet::LinkKeys k;
  k.baud = c.line.baud;
  k.parity = std::string(transport::parity_name(c.line.parity));
  k.stop_bits = c.line.stop_bits;
  k.checksum = link::checksum_name({c.checksum.mode, c.checksum.crc_init, {}});
  k.checksum_coverage = std::string(link::coverage_name(c.checksum.coverage));
  k.id = c.macid;
  return k;
}

// The inventory of --inventory (with --drive), or none.
Result<std::optional<fleet::Inventory>> inventory_of(const LinkCli& o) {
  if (o.drive.empty() != o.inventory.empty())
    return Error(Errc::invalid_argument,
                 "--inventory and --drive go together (the inventory's keys of "
                 "that drive's line are printed); nothing written");
  if (o.inventory.empty()) return std::optional<fleet::Inventory>();
  LMCFG_ASSIGN_OR_RETURN(auto inv, fleet::load_inventory(o.inventory));
  if (!inv.find_drive(o.drive))
    return Error(Errc::invalid_argument,
                 o.inventory + ": no drive is called '" + o.drive + "' (--drive)");
  return std::optional<fleet::Inventory>(std::move(inv));
}

// What lmcfg link prints: the drive's settings, the plan, the inventory's
// keys, as text or as one JSON document.
struct LinkReport {
  LinkReport(const LinkCli& opt, const ops::LinkState& now)
      : o(opt), drive("drive " + hex(now.in_use.macid, 2, "h") + " on " + opt.common.port) {
    j = report::link_json(o.common.port, now);
  }
  void state(const ops::LinkState& st, const char* title) const {
    std::printf("%s %s, talking at: %s\n", drive.c_str(), title,
                link::link_options_of(st.in_use).c_str());
    for (std::size_t i = 0; i < ops::kLinkSettings; ++i)
      std::printf("  %s\n", value_line(static_cast<ops::LinkSetting>(i), st.values[i]).c_str());
  }
  void set_plan(const ops::LinkPlan& p) {
    plan = &p;
    report::add_link_plan(j, p);
  }
  void print_plan() const {
    std::printf("%s: write to ROM (MC stopped, seed 003 §10), then reset (§13.1):\n",
                drive.c_str());
    for (const auto& w : plan->writes) std::printf("  %s\n", w.text.c_str());
  }
  void print_keys(const char* verb) const {
    if (!edit) {
      std::printf(
          "fleet: for an inventory, run with --inventory FILE --drive NAME to see the keys "
          "to change\n");
      return;
    }
    if (edit->keys.empty()) std::printf("inventory: no key %s to change\n", verb);
    for (const auto& k : edit->keys) std::printf("inventory: %s\n", k.c_str());
    for (const auto& w : edit->warnings)
      std::fprintf(stderr, "lmcfg link: warning: %s\n", w.c_str());
  }
  void json_keys() {
    if (!edit) return;
    j["inventory"] = edit->keys;
    j["warnings"] = edit->warnings;
  }
  // "outcome" comes before what the outcome adds.
  void outcome(const char* what) { j["outcome"] = what; }
  void print_json() const { std::printf("%s\n", j.dump(2).c_str()); }

  const LinkCli& o;
  const std::string drive;
  report::Json j;
  const ops::LinkPlan* plan = nullptr;
  std::optional<fleet::InventoryEdit> edit;
};

// No --set-*: the settings as the ROM holds them.
int show(const SessionHandle& session, LinkReport& r, const ops::LinkState& now) {
  auto closed = session->close();
  if (!closed.ok()) return session.fail("link", closed.error());
  if (r.o.common.json) {
    r.outcome("shown");
    r.print_json();
  } else {
    r.state(now, "(ROM values)");
  }
  return kOk;
}

// A plan that writes nothing, or --dry-run: the plan, and nothing written.
int without_writing(const SessionHandle& session, LinkReport& r) {
  auto closed = session->close();
  if (!closed.ok()) return session.fail("link", closed.error());
  if (r.plan->nothing_to_do()) {
    if (r.o.common.json) {
      r.outcome("nothing_to_do");
      r.print_json();
    } else {
      std::printf("nothing to do: %s already holds these settings\n", r.drive.c_str());
    }
    return kOk;
  }
  if (r.o.common.json) {
    r.outcome("dry_run");
    r.json_keys();
    r.print_json();
  } else {
    r.print_plan();
    std::printf("link options after the reset: %s\n", link::link_options_of(r.plan->after).c_str());
    r.print_keys("would have");
    std::printf("dry run: nothing written\n");
  }
  return kOk;
}

// Asks (or --yes), writes, resets, finds the drive again and reads back.
int change_settings(const SessionHandle& session, LinkReport& r, const ops::LinkMap& map,
                    const std::filesystem::path& record) {
  std::string question = "Write";
  for (const auto& w : r.plan->writes) question += "\n  " + w.text;
  question += "\nto the ROM of " + r.drive + " and reset it (the axis stops)?";
  auto consent = confirm(question, "change a drive's link settings", r.o.yes);
  if (!consent.ok()) return session.fail("link", consent.error());
  if (*consent == ops::Consent::declined) {
    std::fprintf(stderr, "cancelled; nothing written\n");
    return kOk;
  }
  auto rep = ops::apply_link_change(*session, map, *r.plan, r.o.common.port, record);
  auto closed = session->close();
  if (!rep.ok()) return session.fail("link", rep.error());
  if (!closed.ok()) return session.fail("link", closed.error());
  const std::string options = link::link_options_of(rep->relink.used);
  if (r.o.common.json) {
    report::add_link_changed(r.j, *rep);
    r.json_keys();
    r.print_json();
  } else {
    r.print_plan();
    std::printf("%s; read back: every value as written\n", rep->relink.summary.c_str());
    std::printf("link options: --port %s %s\n", r.o.common.port.c_str(), options.c_str());
    r.print_keys("has");
  }
  return kOk;
}

int run(LinkCli& o) {
  if (is_devicenet(o.common))
    return fail("link", Error(Errc::invalid_argument,
                              "--port " + o.common.port +
                                  " is a DeviceNet (CAN) link: lmcfg link changes the LinRS "
                                  "settings of seed 003 §15; a DeviceNet controller's MACID and "
                                  "bit rate are set with its switches or the vendor's PC software "
                                  "(seed 000 §1.1); nothing written"));
  if (link::scheme_of(o.common.port).protocol == link::Protocol::linudp)
    return fail("link", Error(Errc::invalid_argument,
                              "--port " + o.common.port +
                                  " is a LinUDP drive: lmcfg link changes the LinRS settings of "
                                  "seed 003 §15, which a drive on Ethernet does not use "
                                  "(docs/linudp.md); nothing written"));
  auto change = parse_change(o);
  if (!change.ok()) return fail("link", change.error());
  auto inv = inventory_of(o);
  if (!inv.ok()) return fail("link", inv.error());
  const db::Database db = load_database(o.common);
  auto map = ops::link_map(db, o.maps);
  if (!map.ok()) return fail("link", map.error());
  if (auto c = ops::check_link_change(*map, *change); !c.ok()) return fail("link", c.error());
  auto lo = link_options(o.common);
  if (!lo.ok()) return fail("link", lo.error());
  auto record = ops::recovery_path("link", o.common.port, lo->client.id);
  if (!record.ok()) return fail("link", record.error());
  if (auto old = ops::load_recovery(*record); old.ok() && *old && !o.common.quiet)
    std::fprintf(stderr,
                 "lmcfg link: note: %s is the recovery record of an earlier lmcfg link (%s): the "
                 "drive was expected at %s; it holds the previous values\n",
                 record->string().c_str(), (*old)->created.c_str(), (*old)->expect.c_str());

  auto session = open_link(o.common);
  if (!session.ok()) return fail("link", session.error());
  if (auto l = ops::learn_from_drive(**session, *map); !l.ok())
    return session->fail("link", l.error());
  auto now = ops::read_link_settings(**session, *map);
  if (!now.ok()) return session->fail("link", now.error());
  LinkReport r(o, *now);
  if (!change->any()) return show(*session, r, *now);

  auto plan = ops::plan_link_change(**session, *map, *now, *change);
  if (!plan.ok()) return session->fail("link", plan.error());
  r.set_plan(*plan);
  if (*inv) {
    auto e = fleet::link_inventory_edit(**inv, o.drive, keys_of(plan->after));
    if (!e.ok()) return session->fail("link", e.error());
    r.edit = std::move(e).value();
  }
  if (plan->nothing_to_do() || o.dry_run) return without_writing(*session, r);
  return change_settings(*session, r, *map, *record);
}

}  // namespace

void add_link(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<LinkCli>();
  auto* sub = app.add_subcommand(
      "link",
      "Show a drive's LinRS settings (rate, MACID, checksum, parity, stop bits); change "
      "them safely");
  sub->footer(
      "Examples:\n"
      "  lmcfg link --port /dev/ttyUSB0 --id 0x11\n"
      "  lmcfg link --port /dev/ttyUSB0 --set-baud 38400 --dry-run\n"
      "  lmcfg link --port /dev/ttyUSB0 --map checksum@UPID:none=0,add=1,crc=2 --set-checksum crc "
      "--yes\n"
      "Without --set-*: prints the ROM values of the settings (seed 003 §15) and the link in use.\n"
      "With --set-*: stops MC, writes ROM (a value before its source select), resets the drive,\n"
      "finds it at the new settings (scanning its MACID if it must), reads the values back and\n"
      "prints the new link options. A recovery record in $XDG_STATE_HOME/lmcfg (else\n"
      "~/.local/state/lmcfg) holds the previous values until the drive answers at the new ones.\n"
      "Seed 003 gives the UPIDs of the baud rate and MACID settings (200Eh, 2012h, 206Ch, 2076h)\n"
      "but only the raw value 8 = 38400 Baud; checksum, parity and stop bits have no UPID in it:\n"
      "--map gives what your firmware's documentation says (docs/link.md).");
  add_link_options(sub, o->common);
  add_output_options(sub, o->common);
  sub->add_option("--set-baud", o->set_baud,
                  "new baud rate (4800..115200, seed 003 §3.2.1): writes 2012h and 200Eh = By "
                  "Parameter");
  sub->add_option("--set-id", o->set_id,
                  "new MACID (0x00..0xFF): writes 2076h and 206Ch = By Parameter; refused when "
                  "a drive already answers to it");
  sub->add_option("--set-checksum", o->set_checksum,
                  "new checksum: none, add, crc (= crc-ffff), crc-0000, crc-kermit (needs --map "
                  "checksum@UPID:...)");
  sub->add_option("--set-parity", o->set_parity,
                  "new parity: none, even, odd (needs --map parity@UPID:...)");
  sub->add_option("--set-stop-bits", o->set_stop_bits,
                  "new stop bits: 1, 2 (needs --map stop-bits@UPID:...)");
  sub->add_option("--map", o->maps,
                  "SETTING[@UPID]:VALUE=RAW,... where a setting lives and its raw values, from "
                  "your firmware's documentation (repeatable): checksum@UPID:none=0,crc=2, "
                  "baud:115200=RAW, parity@UPID:..., stop-bits@UPID:...");
  sub->add_option("--inventory", o->inventory,
                  "with --drive: print the inventory keys to change (lmcfg fleet)");
  sub->add_option("--drive", o->drive, "the drive's name in --inventory");
  sub->add_flag("--dry-run", o->dry_run, "print what would be written; write nothing");
  sub->add_flag("--yes,-y", o->yes, "do not ask for confirmation");
  sub->callback([o, &exit_code] { exit_code = run(*o); });
}

}  // namespace lmcfg::cli
