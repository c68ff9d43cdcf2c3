// Backup, restore plan, write and verify of the DeviceNet controllers of seed
// 000 (lib/ops/devicenet.cpp), against the simulated controller on an
// in-process CAN bus: the values of §5.2 Table 5-1 with their names, scaled
// units and ranges, the plan's problems, and what a refused Set says.
#include <algorithm>
#include <catch2/catch.hpp>

#include "can/virtual_bus.hpp"
#include "db/database.hpp"
#include "devicenet/catalogue.hpp"
#include "ops/devicenet.hpp"
#include "ops/diff.hpp"
#include "sim/devicenet_controller.hpp"
#include "test_config_support.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace ops_test_devicenet {

using namespace lmcfg;
using devicenet::Motor;

namespace {

const db::Database& real_db() {
  static auto db = db::Database::open(LMCFG_DB_PATH);
  REQUIRE(db.ok());
  return *db;
}

config::DevicenetValue value(int motor, std::uint8_t get, std::uint16_t raw) {
  return {motor, get, raw, {}, {}, {}};
}

// A controller at MAC ID 3Fh with the given motors, commissioned, and a
// connected master.
struct Rig {
  std::shared_ptr<can::VirtualBus> bus = std::make_shared<can::VirtualBus>();
  sim::DeviceNetController controller;
  std::unique_ptr<can::Link> link;
  devicenet::Master master;

  static sim::DeviceNetControllerOptions controller_options(std::array<bool, 4> motors,
                                                            bool error_leaves_run) {
    sim::DeviceNetControllerOptions o;
    o.mac = 0x3F;
    o.motors = motors;
    o.error_leaves_run = error_leaves_run;
    return o;
  }
  static devicenet::MasterOptions master_options() {
    devicenet::MasterOptions o;
    o.slave_mac = 0x3F;
    o.own_mac = 0x3E;
    o.timeout = transport::Millis(20);
    o.duplicate_check_wait = transport::Millis(10);
    return o;
  }
  explicit Rig(std::array<bool, 4> motors = {true, true, false, false},
               bool error_leaves_run = false)
      : controller(controller_options(motors, error_leaves_run)),
        link(bus->open("master")),
        master(*link, master_options()) {
    controller.attach(*bus);
    controller.commission();
    REQUIRE(master.connect().ok());
  }
  config::DriveConfig backup(ops::DevicenetBackupOptions o = {}) {
    auto cfg = ops::devicenet_backup(master, o, real_db());
    INFO((cfg.ok() ? std::string() : cfg.error().message));
    REQUIRE(cfg.ok());
    return std::move(cfg).value();
  }
};

}  // namespace

TEST_CASE("devicenet: CAN ports are told from byte links", "[devicenet_ops]") {
  CHECK(ops::is_can_port("can0"));
  CHECK(ops::is_can_port("slcan:/dev/ttyACM0"));
  CHECK(ops::is_can_port("slcan:tcp://127.0.0.1:4711"));
  CHECK_FALSE(ops::is_can_port("/dev/ttyUSB0"));
  CHECK_FALSE(ops::is_can_port("tcp://10.0.0.5:4001"));
  CHECK_FALSE(ops::is_can_port("sim:axis.json"));
}

TEST_CASE("devicenet: DeviceNet §5.2 Table 5-1 words, names and scaled values",
          "[devicenet_ops][golden]") {
  const auto& db = real_db();
  // Table 5-1 "Get Minimal Position -32256 to +32256": a signed word.
  const auto* min_pos = db.devicenet_command(0x40);
  REQUIRE(min_pos);
  CHECK(ops::devicenet_word(min_pos, 0xFE00) == -512);
  CHECK(ops::devicenet_word(min_pos, 0x7E00) == 32256);
  // "Get Controller P 0 to 32640": unsigned; without the database unsigned too.
  CHECK(ops::devicenet_word(db.devicenet_command(0x34), 0xFE00) == 0xFE00);
  CHECK(ops::devicenet_word(nullptr, 0xFE00) == 0xFE00);

  // §5.2 "Set Controller P (35h)": "Unit 2.3438mA/mm"; "Minimal Position": "19.53125 µm".
  CHECK(ops::devicenet_value_name(db, value(0, 0x34, 1000)) == "motor A: Controller P (34h)");
  CHECK(ops::devicenet_value_text(db, value(0, 0x34, 1000)) == "2.3438 A/mm (raw 1000)");
  CHECK(ops::devicenet_value_text(db, value(1, 0x40, 0xFE00)) == "-10 mm (raw 65024)");
  CHECK(ops::devicenet_value_name(db, value(1, 0x40, 0)) == "motor B: Minimal Position (40h)");
  CHECK(ops::devicenet_value_name(db, value(config::kDevicenetController, 0x02, 0)) ==
        "controller: Status Low Word (02h)");
  // A word without a unit: the raw number alone.
  CHECK(ops::devicenet_value_text(db, value(0, 0x24, 3)) == "3");

  // Without the database: the capture's name, scaled text and unit, else the command ID.
  const auto& none = db::Database::empty();
  const config::DevicenetValue recorded{3, 0x34, 1000, "Get Controller P", "A/mm", "2.3438"};
  CHECK(ops::devicenet_value_name(none, recorded) == "motor D: Controller P (34h)");
  CHECK(ops::devicenet_value_text(none, recorded) == "2.3438 A/mm (raw 1000)");
  const config::DevicenetValue unitless{0, 0x34, 7, "", "", "7"};
  CHECK(ops::devicenet_value_text(none, unitless) == "7 (raw 7)");
  CHECK(ops::devicenet_value_name(none, value(2, 0x7E, 1)) == "motor C: command 7Eh");
  CHECK(ops::devicenet_value_text(none, value(2, 0x7E, 1)) == "1");
}

TEST_CASE("devicenet: annotate fills names, units and scaled texts from the database",
          "[devicenet_ops][golden]") {
  config::DevicenetSection s;
  s.values = {value(0, 0x34, 1000), value(0, 0x40, 0xFE00), value(0, 0x7E, 5)};
  s.live = {value(config::kDevicenetController, 0x02, 3)};
  ops::annotate_devicenet(s, real_db());
  CHECK(s.values[0].name == "Get Controller P");
  CHECK(s.values[0].unit == "A/mm");
  CHECK(s.values[0].scaled == "2.3438");
  CHECK(s.values[1].name == "Get Minimal Position");
  CHECK(s.values[1].unit == "mm");
  CHECK(s.values[1].scaled == "-10");
  CHECK(s.values[2].name.empty());  // a command Table 5-1 lacks keeps what it had
  CHECK(s.live[0].name == "Get Status Low Word");
  CHECK(s.live[0].scaled.empty());
}

TEST_CASE("devicenet: a backup reads every settable value of the configured motors",
          "[devicenet_ops]") {
  Rig rig;  // motors A and B
  std::vector<std::string> notes;
  ops::DevicenetBackupOptions o;
  o.notes = &notes;
  std::size_t last_done = 0, last_total = 0;
  o.progress = [&](const std::string& phase, std::size_t done, std::size_t total) {
    CHECK(phase == "devicenet");
    last_done = done;
    last_total = total;
  };
  const auto cfg = rig.backup(o);
  REQUIRE(cfg.devicenet);
  const auto& s = *cfg.devicenet;
  CHECK(cfg.scope.layers == std::array<bool, 4>{false, false, false, false});
  CHECK_FALSE(cfg.scope.curves);
  CHECK_FALSE(cfg.scope.command_table);
  CHECK(s.motors == std::vector<int>{0, 1});  // C and D refused with 8111h Drive not master
  CHECK(last_done == last_total);
  REQUIRE_FALSE(s.values.empty());
  for (const auto& v : s.values) {
    INFO(ops::devicenet_value_name(real_db(), v));
    const auto* vc = devicenet::value_command(v.command);
    REQUIRE(vc);
    CHECK(vc->settable);
    CHECK_FALSE(vc->live);
    CHECK(v.raw == rig.controller.value(v.motor == config::kDevicenetController
                                            ? std::nullopt
                                            : std::optional<Motor>(static_cast<Motor>(v.motor)),
                                        v.command));
  }
  auto has = [&](int motor, std::uint8_t get) {
    for (const auto& v : s.values)
      if (v.motor == motor && v.command == get) return true;
    return false;
  };
  CHECK(has(0, 0x34));
  CHECK(has(1, 0x34));
  CHECK_FALSE(has(2, 0x34));
  CHECK(std::any_of(s.live.begin(), s.live.end(), [](const auto& v) { return v.command == 0x02; }));
  // The annotation: Controller P with its unit.
  for (const auto& v : s.values)
    if (v.command == 0x34) CHECK(v.unit == "A/mm");
  // No encoder module: the commands needing one are named in one note.
  REQUIRE(notes.size() == 1);
  CHECK(notes[0].rfind("no master encoder or IO module (coded error 8120h Encoder not exists), "
                       "so not read: ",
                       0) == 0);
}

TEST_CASE("devicenet: given motors, no live values and no module values", "[devicenet_ops]") {
  Rig rig;
  std::vector<std::string> notes;
  ops::DevicenetBackupOptions o;
  o.motors = std::vector<int>{1};
  o.live = false;
  o.module_values = false;
  o.notes = &notes;
  const auto cfg = rig.backup(o);
  const auto& s = *cfg.devicenet;
  CHECK(s.motors == std::vector<int>{1});
  CHECK(s.live.empty());
  CHECK(notes.empty());
  for (const auto& v : s.values) {
    CHECK(v.motor != 0);
    CHECK_FALSE(devicenet::value_command(v.command)->needs_module);
  }
}

TEST_CASE("devicenet: a coded error pending before the backup refuses it unless reset",
          "[devicenet_ops]") {
  Rig rig;
  // Another master's Set out of Table 5-1's range (curve numbers 0..63), not reset.
  devicenet::PollCommand bad;
  bad.addressed = devicenet::CommandWord{
      {true, false, false, false}, !rig.master.last_status().command_toggle(Motor::A), 0x25};
  bad.addressed_value = 64;
  REQUIRE(rig.master.poll(bad).ok());
  auto refused = ops::devicenet_backup(rig.master, {}, real_db());
  REQUIRE_FALSE(refused.ok());
  CHECK(refused.error().code == make_error_code(Errc::drive_refused));
  CHECK(refused.error().message ==
        "the controller reports coded error 8118h Range error from before this run; values read "
        "now could not be told from refused reads: clear it (the PLC, or --reset-coded-error to "
        "reset it here) and run again");
  std::vector<std::string> notes;
  ops::DevicenetBackupOptions o;
  o.reset_coded_error = true;
  o.module_values = false;
  o.notes = &notes;
  const auto cfg = rig.backup(o);
  CHECK(notes == std::vector<std::string>{"reset the controller's pending coded error 8118h "
                                          "Range error"});
  CHECK_FALSE(cfg.devicenet->values.empty());
}

TEST_CASE("devicenet: a firmware whose refusals stop RUN is named in a note", "[devicenet_ops]") {
  Rig rig({true, false, false, false}, true);
  std::vector<std::string> notes;
  ops::DevicenetBackupOptions o;
  o.module_values = false;
  o.notes = &notes;
  const auto cfg = rig.backup(o);
  CHECK(cfg.devicenet->motors == std::vector<int>{0});
  CHECK_FALSE(rig.master.last_status().run_state());
  REQUIRE_FALSE(notes.empty());
  CHECK(notes.back().rfind("the controller left RUN state during the backup (status ", 0) == 0);
  CHECK(notes.back().ends_with(
      "), after refusing a read; seed 000 §5.2: RUN Request must be released and set again "
      "(the PLC's Control Word). --devicenet-motors and --no-module-values avoid the probes"));
  // Told its motors, the backup sends no probe and stays in RUN.
  Rig quiet({true, false, false, false}, true);
  std::vector<std::string> none;
  o.motors = std::vector<int>{0};
  o.notes = &none;
  quiet.backup(o);
  CHECK(none.empty());
  CHECK(quiet.master.last_status().run_state());
}

TEST_CASE("devicenet: DeviceNet §5.2 the plan's problems and writes", "[devicenet_ops][golden]") {
  const auto& db = real_db();
  const auto file = config::testing::devicenet_capture();  // motors A and B
  SECTION("a LinRS capture") {
    const auto p = ops::plan_devicenet_restore(config::DriveConfig{}, file, db);
    CHECK(p.problems ==
          std::vector<std::string>{"the file is a LinRS drive capture, not a DeviceNet "
                                   "controller's"});
    CHECK(p.refused());
  }
  SECTION("the same values: nothing to write") {
    const auto p = ops::plan_devicenet_restore(file, file, db);
    CHECK_FALSE(p.refused());
    CHECK(p.writes.empty());
    CHECK(p.unchanged == 4);
    CHECK(ops::render_devicenet_plan(p, "ctl.json") ==
          "restore plan for ctl.json: 0 Set command(s), 4 value(s) already equal\nnote: " +
              std::string(ops::kRuntimeNote) + ".\n");
  }
  SECTION("one value differs: one Set command, shown in Table 5-1's units") {
    auto current = file;
    for (auto& v : current.devicenet->values)
      if (v.motor == 0 && v.command == 0x34) v.raw = 500;
    const auto p = ops::plan_devicenet_restore(file, current, db);
    REQUIRE(p.writes.size() == 1);
    const auto& w = p.writes[0];
    CHECK(w.motor == 0);
    CHECK(w.get == 0x34);
    CHECK(w.from == 500);
    CHECK(w.to == 1000);
    CHECK(w.name == "motor A: Controller P (34h)");
    CHECK(w.from_display == "1.1719 A/mm (raw 500)");
    CHECK(w.to_display == "2.3438 A/mm (raw 1000)");
    CHECK(w.what == "motor A: Controller P (34h): 1.1719 A/mm (raw 500) -> 2.3438 A/mm (raw 1000)");
    CHECK(p.unchanged == 3);
    CHECK(ops::render_devicenet_plan(p, "ctl.json") ==
          "restore plan for ctl.json: 1 Set command(s), 3 value(s) already equal\n"
          "  set 35h motor A: Controller P (34h): 1.1719 A/mm (raw 500) -> 2.3438 A/mm (raw "
          "1000)\nnote: " +
              std::string(ops::kRuntimeNote) + ".\n");
  }
  SECTION("a motor the controller lacks, a value out of range, a live value, one not read") {
    auto want = file;
    auto& values = want.devicenet->values;
    for (auto& v : values)
      if (v.motor == 0 && v.command == 0x40) v.raw = 0x8000;  // -32768 < -32256
    values.push_back({0, 0x48, 600, "", "", ""});             // "2 to 511"
    values.push_back({config::kDevicenetController, 0x02, 3, "", "", ""});
    values.push_back({0, 0x4A, 10, "", "", ""});  // settable, but absent from the read
    auto current = file;
    current.devicenet->motors = {0};
    std::erase_if(current.devicenet->values, [](const auto& v) { return v.motor == 1; });
    const auto p = ops::plan_devicenet_restore(want, current, db);
    CHECK(p.problems ==
          std::vector<std::string>{
              "motor B is in the file but not configured on the controller (it refuses commands "
              "to it)",
              "motor A: Minimal Position (40h): -640 mm (raw 32768) is outside Table 5-1's range "
              "-32256 to +32256 (unit 0.01953 mm)",
              "motor A: In Position Low Limit (48h): 11.71875 mm (raw 600) is outside Table "
              "5-1's range 2 to 511 (unit 0.01953 mm)",
              "controller: Status Low Word (02h): Table 5-1 has no Set command for it",
              "motor A: In Position High Limit (4Ah): the controller did not let it be read (see "
              "the notes)"});
    CHECK(ops::render_devicenet_plan(p, "want.json")
              .rfind(
                  "restore plan for want.json: REFUSED, nothing written:\n  problem: motor B is in "
                  "the file but not configured on the controller (it refuses commands to it)\n",
                  0) == 0);
  }
}

TEST_CASE("devicenet: the plan written and verified on the controller", "[devicenet_ops]") {
  Rig rig;
  ops::DevicenetBackupOptions o;
  o.module_values = false;
  auto file = rig.backup(o);
  const std::size_t values = file.devicenet->values.size();
  // The file wants motor A's Controller P at 1000 and motor B's at 1200.
  for (auto& v : file.devicenet->values) {
    if (v.command != 0x34) continue;
    v.raw = v.motor == 0 ? 1000 : 1200;
  }
  rig.controller.set_value(Motor::A, 0x34, 500);
  rig.controller.set_value(Motor::B, 0x34, 1200);
  const auto current = rig.backup(o);
  const auto plan = ops::plan_devicenet_restore(file, current, real_db());
  REQUIRE_FALSE(plan.refused());
  REQUIRE(plan.writes.size() == 1);
  CHECK(plan.unchanged == values - 1);
  std::vector<std::string> phases;
  auto done = ops::execute_devicenet_plan(rig.master, plan, file, real_db(),
                                          [&](const std::string& phase, std::size_t, std::size_t) {
                                            if (phases.empty() || phases.back() != phase)
                                              phases.push_back(phase);
                                          });
  REQUIRE(done.ok());
  CHECK(done->empty());
  CHECK(phases == std::vector<std::string>{"write", "verify"});
  CHECK(rig.controller.value(Motor::A, 0x34) == 1000);

  // Someone else changes a value after the plan: the read-back names it.
  rig.controller.set_value(Motor::B, 0x34, 500);
  auto stale = ops::execute_devicenet_plan(rig.master, ops::DevicenetPlan{}, file, real_db(), {});
  REQUIRE(stale.ok());
  CHECK(*stale == std::vector<std::string>{"motor B: Controller P (34h): file 2.81256 A/mm (raw "
                                           "1200), controller 1.1719 A/mm (raw 500)"});
}

TEST_CASE("devicenet: a Set the controller refuses stops the restore and says how far it got",
          "[devicenet_ops]") {
  Rig rig;
  ops::DevicenetPlan plan;
  ops::DevicenetWrite ok{0, 0x34, 0, 1000, "motor A: Controller P (34h): ... -> ...", "", "", ""};
  ops::DevicenetWrite bad{0,  0x24, 0, 64, "motor A: (Rise) Curve Number (24h): 0 -> 64",
                          "", "",   ""};
  plan.writes = {ok, bad, ok};
  auto r = ops::execute_devicenet_plan(rig.master, plan, config::testing::devicenet_capture(),
                                       real_db(), {});
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == make_error_code(Errc::drive_refused));
  CHECK(r.error().message ==
        "command 25h to DeviceNet MAC ID 63: the controller reports an error, coded error 8118h "
        "Range error (writing motor A: (Rise) Curve Number (24h): 0 -> 64, which the controller "
        "may or may not have executed; 1 of 3 Set command(s) done before it, the rest not sent: "
        "run the restore again)");
  CHECK(rig.controller.value(Motor::A, 0x34) == 1000);
}

TEST_CASE("devicenet: a refused plan or a LinRS file sends no command", "[devicenet_ops]") {
  Rig rig;
  ops::DevicenetPlan plan;
  ops::DevicenetWrite w{0, 0x34, 0, 1000, "motor A: Controller P (34h): ... -> ...", "", "", ""};
  plan.writes = {w};
  const std::string problem = "motor C is in the file but not configured on the controller";
  plan.problems = {problem};
  rig.controller.set_value(Motor::A, 0x34, 500);  // the plan would set 1000
  auto r = ops::execute_devicenet_plan(rig.master, plan, config::testing::devicenet_capture(),
                                       real_db(), {});
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == make_error_code(Errc::plan_refused));
  CHECK(r.error().message == "restore refused: " + problem + "; nothing written");
  CHECK(rig.controller.value(Motor::A, 0x34) == 500);

  plan.problems.clear();
  r = ops::execute_devicenet_plan(rig.master, plan, config::DriveConfig{}, real_db(), {});
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == make_error_code(Errc::plan_refused));
  CHECK(r.error().message ==
        "the file is a LinRS drive capture, not a DeviceNet controller's; nothing written");
  CHECK(rig.controller.value(Motor::A, 0x34) == 500);
}

namespace {

// A controller with the first `motors` of A..D, commissioned, under one
// toggle and one absent-motor reading, and a connected master.
struct ReadingRig {
  std::shared_ptr<can::VirtualBus> bus = std::make_shared<can::VirtualBus>();
  sim::DeviceNetController controller;
  std::unique_ptr<can::Link> link;
  devicenet::Master master;
  static sim::DeviceNetControllerOptions options(int motors, sim::ToggleRule rule,
                                                 sim::AbsentMotor absent) {
    sim::DeviceNetControllerOptions o;
    o.mac = 0x3F;
    o.motors = {motors > 0, motors > 1, motors > 2, motors > 3};
    o.toggle_rule = rule;
    o.absent_motor = absent;
    return o;
  }
  ReadingRig(int motors, sim::ToggleRule rule, sim::AbsentMotor absent)
      : controller(options(motors, rule, absent)),
        link(bus->open("master")),
        master(*link, Rig::master_options()) {
    controller.attach(*bus);
    controller.commission();
    REQUIRE(master.connect().ok());
  }
  config::DriveConfig backup() {
    auto cfg = ops::devicenet_backup(master, {}, real_db());
    INFO((cfg.ok() ? std::string() : cfg.error().message));
    REQUIRE(cfg.ok());
    return std::move(cfg).value();
  }
};

}  // namespace

TEST_CASE(
    "devicenet: seed 000 §5.2 controllers with 1 to 4 motors backed up, diffed and restored "
    "under every toggle and absent-motor reading",
    "[devicenet_ops][absent]") {
  const char* absent_readings[] = {"coded-error",   "coded-error-8110", "no-toggle",
                                   "error-no-echo", "echo-only",        "ignore"};
  for (int motors = 1; motors <= 4; ++motors) {
    for (const char* rule : {"seed", "get-set-ignore", "module"}) {
      for (const char* absent : absent_readings) {
        INFO(motors << " motor(s), toggle " << rule << ", absent motor " << absent);
        ReadingRig rig(motors, *sim::parse_toggle_rule(rule), *sim::parse_absent_motor(absent));
        const auto file = rig.backup();
        std::vector<int> expected;
        for (int m = 0; m < motors; ++m) expected.push_back(m);
        CHECK(file.devicenet->motors == expected);
        CHECK(ops::diff(file, rig.backup(), real_db(), {}, {}).identical());

        // Another master changes motor A's Controller P and the last motor's
        // Filter Maximal Speed.
        const auto last = static_cast<Motor>(motors - 1);
        const auto p = rig.controller.value(Motor::A, 0x34);
        const auto speed = rig.controller.value(last, 0x50);
        rig.controller.set_value(Motor::A, 0x34, static_cast<std::uint16_t>(p + 7));
        rig.controller.set_value(last, 0x50, static_cast<std::uint16_t>(speed + 9));
        const auto changed = rig.backup();
        const auto d = ops::diff(file, changed, real_db(), {}, {});
        CHECK(d.items.size() == 2);

        const auto plan = ops::plan_devicenet_restore(file, changed, real_db());
        REQUIRE_FALSE(plan.refused());
        CHECK(plan.writes.size() == 2);
        auto done = ops::execute_devicenet_plan(rig.master, plan, file, real_db(), {});
        INFO((done.ok() ? std::string() : done.error().message));
        REQUIRE(done.ok());
        CHECK(done->empty());
        CHECK(rig.controller.value(Motor::A, 0x34) == p);
        CHECK(rig.controller.value(last, 0x50) == speed);
        CHECK(ops::diff(file, rig.backup(), real_db(), {}, {}).identical());
      }
    }
  }
}

}  // namespace ops_test_devicenet
