// README: "when [communication parameters] are [restored], the tool
// reconnects with the new settings after the reset and says so". The drive
// picks MACID and baud rate at start-up from its hex switches or "By
// Parameter" (LinRS §3.2, §10.2, §15); the simulated drive models that, and
// a master at the wrong baud rate hears nothing from it.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>

#include "codec/messages.hpp"
#include "config/config_io.hpp"
#include "db/database.hpp"
#include "e2e_support.hpp"
#include "files.hpp"
#include "link/relink.hpp"
#include "link/session.hpp"
#include "ops/backup.hpp"
#include "ops/expected_link.hpp"
#include "ops/factory_reset.hpp"
#include "ops/restore.hpp"
#include "subprocess.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace link_test_relink {

using namespace lmcfg;
using test::slurp;
using test::temp_dir;
namespace fs = std::filesystem;

namespace {

void set_rom(sim::Drive& d, std::uint16_t upid, std::uint32_t v) {
  auto* p = d.find(upid);
  REQUIRE(p != nullptr);
  p->rom = p->ram = v;
}

// A backup of the commissioned axis whose LinRS parameters select 38400 Bd
// (2012h = 8, the one code LinRS §10.2 gives) and MACID 22h by parameter.
config::DriveConfig moved_axis_file(const db::Database& db) {
  test::SimRig axis("commissioned-axis.json");
  auto cfg = ops::backup(*axis.client, ops::BackupOptions{}, db);
  REQUIRE(cfg.ok());
  auto set = [&](std::uint16_t upid, std::uint32_t v) {
    for (auto& p : cfg->layer(3))
      if (p.upid == upid) {
        p.value = v;
        return;
      }
    cfg->layer(3).push_back(config::Parameter{
        upid, v, std::nullopt, std::nullopt, {}, {}, {}});  // at its default on the axis
    config::canonicalize(*cfg);
  };
  set(ops::kBaudRateSource, ops::kBaudRateByParameter);
  set(ops::kBaudRateCode, 8);
  set(ops::kMacidSource, ops::kMacidByParameter);
  set(ops::kMacidValue, 0x22);
  return std::move(cfg).value();
}

bool answers(sim::SimLink& link, std::uint8_t id) {
  auto req = codec::encode(codec::make_cfg(id, codec::CfgOp::read_rom, 0x13A2));
  REQUIRE(req.ok());
  REQUIRE(link.write(*req).ok());
  auto r = link.read_some(transport::Millis(100));
  REQUIRE(r.ok());
  return !r->empty();
}

}  // namespace

TEST_CASE(
    "sim: a reset takes MACID and baud rate from 206Ch/2076h and 200Eh/2012h (seed 003 §3.2, §15)",
    "[sim][relink]") {
  auto drive = test::load_sim_drive("used-spare.json");  // both sources: hex switches
  REQUIRE(drive->macid() == 0x11);
  REQUIRE(drive->state().link.baud == 57600);
  set_rom(*drive, 0x206C, 3);
  set_rom(*drive, 0x2076, 0x22);
  set_rom(*drive, 0x200E, 2);
  set_rom(*drive, 0x2012, 8);
  CHECK(drive->macid() == 0x11);  // ROM values act at start-up only
  drive->reset(0);
  CHECK(drive->macid() == 0x22);
  CHECK(drive->state().link.baud == 38400);

  // A code outside Options::baud_codes keeps the S1 rate; back to the switches.
  set_rom(*drive, 0x2012, 0x40);
  drive->reset(0);
  CHECK(drive->state().link.baud == 57600);
  set_rom(*drive, 0x206C, 1);
  drive->reset(0);
  CHECK(drive->macid() == 0x11);

  // The state file keeps the switch settings when they differ from the active ones.
  set_rom(*drive, 0x206C, 3);
  drive->reset(0);
  auto reloaded = sim::from_json(sim::to_json(drive->state()));
  REQUIRE(reloaded.ok());
  REQUIRE(reloaded->switches.has_value());
  CHECK(reloaded->switches->macid == 0x11);
  CHECK(reloaded->macid == 0x22);
}

TEST_CASE("sim: a master at another baud rate gets no answer until it reconfigures its line",
          "[sim][relink]") {
  auto drive = test::load_sim_drive("used-spare.json");
  sim::SimLink link(drive);
  CHECK(answers(link, 0x11));
  transport::SerialSettings slow;
  slow.baud = 19200;
  REQUIRE(link.reconfigure(slow).ok());
  CHECK_FALSE(answers(link, 0x11));
  CHECK(link.describe().rfind("sim 19200 8N1", 0) == 0);
  slow.baud = 57600;
  REQUIRE(link.reconfigure(slow).ok());
  CHECK(answers(link, 0x11));
  slow.baud = 12345;
  CHECK(link.reconfigure(slow).error().message.find("12345") != std::string::npos);
}

TEST_CASE("relink: the candidates in the order they are tried", "[relink]") {
  // Candidates: overrides, expected, current; then every rate of §3.2.1.
  link::ExpectedLink known{38400u, std::uint8_t{0x22}, {}, {}, {}};
  transport::SerialSettings line;  // 57600 8N1
  auto c = link::relink_candidates(known, {}, line, 0x11, codec::ChecksumConfig{});
  REQUIRE(c.size() == 12);  // 6 rates x 2 IDs
  CHECK(c[0].line.baud == 38400);
  CHECK(c[0].macid == 0x22);
  CHECK(c[1].line.baud == 38400);
  CHECK(c[1].macid == 0x11);
  CHECK(c[2].line.baud == 57600);
  CHECK(c[4].line.baud == 4800);
  link::RelinkOverrides o;
  o.baud = 9600;
  o.macid = 0x05;
  c = link::relink_candidates(known, o, line, 0x11, codec::ChecksumConfig{});
  CHECK(c[0].line.baud == 9600);
  CHECK(c[0].macid == 0x05);
}

TEST_CASE(
    "relink: restore --include-comm writes LinRS parameters last, value before source, and finds "
    "the drive again",
    "[relink][e2e]") {
  auto db = test::built_database();
  REQUIRE(db);
  const auto file = moved_axis_file(*db);
  const auto dir = temp_dir("relink-inproc");
  fs::copy_file(test::sim_fixture("used-spare.json"), dir / "spare.sim.json");
  link::LinkSpec lo;
  lo.port = *link::parse_port("sim:" + (dir / "spare.sim.json").string());
  auto session = link::open_session(lo);
  REQUIRE(session.ok());
  auto& client = (*session)->client();

  ops::RestoreOptions ro;
  auto without = ops::plan_restore(client, file, *db, ro);
  REQUIRE(without.ok());
  CHECK_FALSE(without->link_may_change);

  ro.include_comm = true;
  auto plan = ops::plan_restore(client, file, *db, ro);
  REQUIRE(plan.ok());
  INFO(ops::render_plan(*plan));
  REQUIRE(plan->ok());
  CHECK(plan->link_may_change);
  // The last ROM writes: 2012h before 200Eh and 2076h before 206Ch (both end
  // "By Parameter"), after every other parameter of the layer.
  std::vector<std::uint16_t> rom_keys;
  for (const auto& s : plan->steps)
    if (s.action == ops::PlanStep::Action::write_rom && s.layer == 3)
      rom_keys.push_back(static_cast<std::uint16_t>(s.key));
  REQUIRE(rom_keys.size() >= 4);
  const std::vector<std::uint16_t> tail(rom_keys.end() - 4, rom_keys.end());
  CHECK(tail == std::vector<std::uint16_t>{0x2012, 0x2076, 0x200E, 0x206C});

  REQUIRE(ops::execute_plan(client, *plan, ro).ok());
  // The old settings no longer reach the drive.
  auto lost = client.default_response();
  REQUIRE_FALSE(lost.ok());
  CHECK(lost.error().code == make_error_code(Errc::timeout));

  auto rep = link::reconnect(**session, ops::expected_link(*plan, *db), {});
  REQUIRE(rep.ok());
  CHECK(rep->changed);
  CHECK(rep->attempts == 1);
  CHECK(rep->summary == "the drive answers at 38400 Bd, MACID 22h, checksum none");
  CHECK((*session)->line().baud == 38400);
  CHECK(client.options().id == 0x22);
  auto verify = ops::verify_restore(client, *plan, ro);
  REQUIRE(verify.ok());
  CHECK(verify->ok());
  REQUIRE((*session)->close().ok());
  fs::remove_all(dir);
}

TEST_CASE("relink: a drive on an unknown hex-switch ID is not found, --reconnect-id finds it",
          "[relink]") {
  auto db = test::built_database();
  REQUIRE(db);
  const auto dir = temp_dir("relink-switch");
  // The spare's switches select 33h; it answers on 11h by parameter now.
  auto spare = test::load_sim_drive("used-spare.json");
  spare->state().switches = sim::HexSwitches{0x33, 57600};
  set_rom(*spare, 0x206C, 3);
  REQUIRE(sim::save_state(spare->state(), (dir / "spare.sim.json").string()).ok());
  link::LinkSpec lo;
  lo.port = *link::parse_port("sim:" + (dir / "spare.sim.json").string());
  auto session = link::open_session(lo);
  REQUIRE(session.ok());
  auto& client = (*session)->client();

  // The file sets the MACID source back to the hex switches (its default).
  test::SimRig axis("used-spare.json");
  auto file = ops::backup(*axis.client, ops::BackupOptions{}, *db);
  REQUIRE(file.ok());
  ops::RestoreOptions ro;
  ro.include_comm = true;
  auto plan = ops::plan_restore(client, *file, *db, ro);
  REQUIRE(plan.ok());
  REQUIRE(plan->ok());
  CHECK(plan->link_may_change);
  REQUIRE(ops::execute_plan(client, *plan, ro).ok());

  const auto expected = ops::expected_link(*plan, *db);
  CHECK_FALSE(expected.macid);
  auto none = link::reconnect(**session, expected, {});
  REQUIRE_FALSE(none.ok());
  CHECK(none.error().code == make_error_code(Errc::timeout));
  CHECK(none.error().message.rfind(
            "after the reset the drive answered none of the 6 link settings tried "
            "(57600 Bd, MACID 11h, checksum none ... 115200 Bd, MACID 11h, checksum none)",
            0) == 0);
  CHECK(none.error().message.find(
            "206Ch MACID Source Select is at its factory default, the hex switches") !=
        std::string::npos);
  CHECK(client.options().id == 0x11);  // back at the settings it had

  link::RelinkOverrides o;
  o.macid = 0x33;
  auto found = link::reconnect(**session, expected, o);
  REQUIRE(found.ok());
  CHECK(found->summary == "the drive answers at 57600 Bd, MACID 33h, checksum none");
  auto verify = ops::verify_restore(client, *plan, ro);
  REQUIRE(verify.ok());
  CHECK(verify->ok());
  fs::remove_all(dir);
}

TEST_CASE(
    "relink: lmcfg restore --include-comm over a pty follows the drive to 38400 Bd and MACID 22h",
    "[relink][e2e][pty]") {
  auto db = test::built_database();
  REQUIRE(db);
  const auto dir = temp_dir("relink-pty");
  const std::string file = (dir / "moved.json").string();
  REQUIRE(config::write_config_file(moved_axis_file(*db), file).ok());
  fs::copy_file(test::sim_fixture("used-spare.json"), dir / "spare.sim.json");
  test::Child spare({LMCFG_TOOL_PATH, "sim", "--state", (dir / "spare.sim.json").string(), "--pty",
                     "--fast", "--save-on-exit"});
  const std::string tty = spare.read_line();
  REQUIRE(tty.rfind("/dev/pts/", 0) == 0);

  const auto err = dir / "restore.err";
  CHECK(test::run_tool("restore " + file + " --port " + tty + " --include-comm --yes 2> " +
                       err.string()) == 0);
  const std::string said = slurp(err);
  INFO(said);
  CHECK(said.find("restore: the restored link settings are active: the drive answers at 38400 Bd, "
                  "MACID 22h, "
                  "checksum none; use them from now on") != std::string::npos);
  // The old settings reach nothing (exit 4); the new ones see the file's configuration.
  CHECK(test::run_tool("diff " + file + " drive --port " + tty +
                       " --quiet --timeout-ms 50 --retries 0 2> /dev/null") == 4);
  CHECK(test::run_tool("diff " + file + " drive --port " + tty +
                       " --baud 38400 --id 0x22 --quiet --ignore-unit > /dev/null") == 0);
  CHECK(spare.stop() == 0);
  auto after = sim::load_state((dir / "spare.sim.json").string());
  REQUIRE(after.ok());
  CHECK(after->macid == 0x22);
  CHECK(after->link.baud == 38400);
  fs::remove_all(dir);
}

TEST_CASE(
    "relink: lmcfg default keeps the LinRS parameters even without a database, --include-comm says "
    "the switches rule",
    "[relink]") {
  test::SimRig rig("manual-drive.json");  // 38400 Bd and MACID 11h, both by parameter
  ops::DefaultOptions d;
  d.layers = {false, false, true, false};
  auto kept = ops::default_drive(*rig.client, d, db::Database::empty());
  REQUIRE(kept.ok());
  CHECK_FALSE(kept->link_may_change);
  CHECK(rig.drive->state().link.baud == 38400);
  CHECK(rig.drive->rom(ops::kBaudRateSource) == ops::kBaudRateByParameter);

  rig.drive->state().switches = sim::HexSwitches{0x05, 57600};
  d.include_comm = true;
  auto dropped = ops::default_drive(*rig.client, d, db::Database::empty());
  REQUIRE(dropped.ok());
  CHECK(dropped->link_may_change);
  CHECK(dropped->done.back() ==
        "reset (defaults become active; no answer with the old link settings)");
  CHECK(rig.drive->macid() == 0x05);
  CHECK(rig.drive->state().link.baud == 57600);
}

// Field reports, C1250 notes: "ROM writes and flash saves left drives unresponsive
// for 30-90 s". A drive whose restart after the restored link settings takes
// 90 s: one round of reconnect finds nothing, reconnect_within keeps trying
// until it answers (docs/field.md "Slow saves"), and gives up only after its
// budget, saying so.
TEST_CASE("field reports: relink: a drive silent 90 s after its reset is found again",
          "[relink][slow_saves]") {
  auto db = test::built_database();
  REQUIRE(db);
  const auto file = moved_axis_file(*db);
  for (const int budget_s : {180, 30}) {
    DYNAMIC_SECTION("budget " << budget_s << " s") {
      const auto dir = temp_dir("relink-slow");
      auto spare = test::load_sim_drive("used-spare.json");
      spare->state().timing.reset_us = 90'000'000;
      REQUIRE(sim::save_state(spare->state(), (dir / "spare.sim.json").string()).ok());
      link::LinkSpec lo;
      lo.port = *link::parse_port("sim:" + (dir / "spare.sim.json").string());
      auto session = link::open_session(lo);
      REQUIRE(session.ok());
      auto& client = (*session)->client();
      ops::RestoreOptions ro;
      ro.include_comm = true;
      auto plan = ops::plan_restore(client, file, *db, ro);
      REQUIRE(plan.ok());
      REQUIRE(plan->link_may_change);
      const auto t0 = client.link().now_ns();
      REQUIRE(ops::execute_plan(client, *plan, ro).ok());
      // The reset's answer (at the new settings) was waited for 6 s only.
      CHECK((client.link().now_ns() - t0) / 1'000'000'000 < 20);
      const auto expected = ops::expected_link(*plan, *db);
      const auto t1 = client.link().now_ns();  // 6 s after the reset was sent
      auto rep =
          link::reconnect_within(**session, expected, {}, transport::Millis(budget_s * 1000));
      const double took_s = static_cast<double>(client.link().now_ns() - t1) / 1e9;
      if (budget_s == 180) {
        REQUIRE(rep.ok());
        CHECK(rep->summary == "the drive answers at 38400 Bd, MACID 22h, checksum none");
        CHECK(took_s >= 83.0);  // the drive's 90 s, less the reset's 6 s wait
        CHECK(took_s < 95.0);   // found within a round of candidates after it wakes
        auto verify = ops::verify_restore(client, *plan, ro);
        REQUIRE(verify.ok());
        CHECK(verify->ok());
      } else {
        REQUIRE_FALSE(rep.ok());
        CHECK(rep.error().code == make_error_code(Errc::timeout));
        CHECK(rep.error().message.rfind("after the reset the drive answered none of the ", 0) == 0);
        const std::string tail = "; looked for it for 30 s (--recover-timeout-s)";
        CHECK(rep.error().message.substr(rep.error().message.size() - tail.size()) == tail);
        CHECK(took_s >= 30.0);
        CHECK(took_s < 45.0);
      }
      fs::remove_all(dir);
    }
  }
}

}  // namespace link_test_relink
