// `lmcfg default` (lib/ops/factory_reset.cpp) against the simulated drive:
// the steps in their order, the layers at their defaults (LinRS §10.4), the
// communication values kept through a recovery record, the tables deleted
// and saved, and what a step that fails or is interrupted says.
#include <atomic>
#include <catch2/catch.hpp>
#include <filesystem>

#include "e2e_support.hpp"
#include "files.hpp"
#include "ops/factory_reset.hpp"
#include "ops/recovery.hpp"
#include "ops/restore.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace ops_test_factory_reset {

using namespace lmcfg;

namespace {

using Steps = std::vector<std::string>;

// The ROM values of one layer's parameters (UPID base `base`) that differ from their defaults.
std::map<std::uint16_t, std::uint32_t> modified(const sim::Drive& d, std::uint16_t base) {
  std::map<std::uint16_t, std::uint32_t> out;
  for (const auto& [upid, p] : d.state().params)
    if ((upid & 0xF000) == base && p.modified()) out[upid] = p.rom;
  return out;
}

}  // namespace

TEST_CASE("factory_reset: LinRS §10.4 the MC layer defaulted with MC stopped, then reset",
          "[factory_reset]") {
  test::SimRig rig("commissioned-axis.json");
  const auto os_before = modified(*rig.drive, 0x0000);
  const auto intf_before = modified(*rig.drive, 0x2000);
  const auto curves_before = rig.drive->state().curves_flash;
  REQUIRE_FALSE(modified(*rig.drive, 0x1000).empty());
  ops::DefaultOptions d;
  d.layers = {false, true, false, false};
  std::vector<std::size_t> progress;
  d.progress = [&](const std::string& phase, std::size_t done, std::size_t total) {
    CHECK(phase == "default");
    CHECK(total == 0);
    progress.push_back(done);
  };
  auto rep = ops::default_drive(*rig.client, d, db::Database::empty());
  REQUIRE(rep.ok());
  CHECK(rep->done ==
        Steps{"stop MC", "default MC layer", "start MC", "reset (defaults become active)"});
  CHECK(progress == std::vector<std::size_t>{1, 2, 3, 4});
  CHECK(modified(*rig.drive, 0x1000).empty());
  CHECK(modified(*rig.drive, 0x0000) == os_before);
  CHECK(modified(*rig.drive, 0x2000) == intf_before);
  CHECK(rig.drive->state().curves_flash == curves_before);
  CHECK(rig.drive->state().mc_running);
  CHECK(rig.drive->stats().resets == 1);
  CHECK(rep->kept.empty());
  CHECK_FALSE(rep->link_may_change);
  CHECK_FALSE(rep->recovered);
  CHECK(rep->recovery_note.empty());
  CHECK_FALSE(rep->undo);
}

TEST_CASE(
    "factory_reset: the Intf layer's communication values recorded, written back, read "
    "back, record deleted",
    "[factory_reset]") {
  test::ScratchDir dir("factory-reset-keep");
  test::SimRig rig("commissioned-axis.json");
  // LinRS §10.2: 200Eh Baud Rate Source Select 2 and 206Ch MACID Source Select 3 ("By
  // Parameter"); 20C7h is modified too but no communication parameter.
  REQUIRE(modified(*rig.drive, 0x2000) ==
          std::map<std::uint16_t, std::uint32_t>{{0x200E, 2}, {0x206C, 3}, {0x20C7, 1}});
  ops::DefaultOptions d;
  d.layers = {false, false, true, false};
  d.recovery_path = dir.path / "default-sim-11h.json";
  d.port = "sim";
  auto rep = ops::default_drive(*rig.client, d, db::Database::empty());
  REQUIRE(rep.ok());
  CHECK(rep->done == Steps{"stop MC", "default Intf layer",
                           "keep communication parameter 200Eh = 2",
                           "keep communication parameter 206Ch = 3", "read back kept 200Eh",
                           "read back kept 206Ch", "start MC", "reset (defaults become active)"});
  CHECK(rep->kept == std::vector<client::ModifiedParam>{{0x200E, 2}, {0x206C, 3}});
  CHECK(modified(*rig.drive, 0x2000) ==
        std::map<std::uint16_t, std::uint32_t>{{0x200E, 2}, {0x206C, 3}});
  CHECK(rep->recovery_note == "recorded the values to keep in " + d.recovery_path.string() +
                                  "; every kept value read back, record deleted");
  CHECK_FALSE(std::filesystem::exists(d.recovery_path));
  CHECK_FALSE(rep->recovered);
  CHECK_FALSE(rep->link_may_change);
  CHECK(rig.drive->macid() == 0x11);  // still answers where it did
}

TEST_CASE("factory_reset: a layer without communication values writes no recovery record",
          "[factory_reset]") {
  test::ScratchDir dir("factory-reset-none");
  test::SimRig rig("commissioned-axis.json");
  ops::DefaultOptions d;
  d.layers = {false, false, false, true};
  d.recovery_path = dir.path / "default-sim-11h.json";
  auto rep = ops::default_drive(*rig.client, d, db::Database::empty());
  REQUIRE(rep.ok());
  CHECK(rep->done ==
        Steps{"stop MC", "default Appl layer", "start MC", "reset (defaults become active)"});
  CHECK(rep->recovery_note.empty());
  CHECK(modified(*rig.drive, 0x3000).empty());
  CHECK_FALSE(std::filesystem::exists(d.recovery_path));
}

TEST_CASE("factory_reset: the record of an interrupted run is finished with the values it holds",
          "[factory_reset]") {
  test::ScratchDir dir("factory-reset-recover");
  test::SimRig rig("commissioned-axis.json");
  // The earlier run defaulted the Intf layer and stopped before writing back.
  for (std::uint16_t upid : std::initializer_list<std::uint16_t>{0x200E, 0x206C, 0x20C7}) {
    auto& p = rig.drive->state().params.at(upid);
    p.rom = p.ram = p.def;
  }
  ops::DefaultOptions d;
  d.layers = {false, false, true, false};
  d.recovery_path = dir.path / "default-sim-11h.json";
  d.port = "sim";
  // 1037h is an MC value: the MC layer is not defaulted now, so it is not written.
  ops::RecoveryRecord rec{"default", "sim", 0x11, "2026-11-24T17:15:00Z", {}, {}, {}};
  rec.keep = {{0x200E, 2}, {0x206C, 3}, {0x1037, 5}};
  REQUIRE(ops::save_recovery(d.recovery_path, rec).ok());
  const auto mc_before = modified(*rig.drive, 0x1000);
  auto rep = ops::default_drive(*rig.client, d, db::Database::empty());
  REQUIRE(rep.ok());
  CHECK(rep->recovered);
  CHECK(rep->recovery_note == "found the recovery record " + d.recovery_path.string() +
                                  " of an interrupted run (2026-11-24T17:15:00Z): writing back "
                                  "the values it recorded; every kept value read back, record "
                                  "deleted");
  CHECK(rep->kept == std::vector<client::ModifiedParam>{{0x200E, 2}, {0x206C, 3}});
  CHECK(modified(*rig.drive, 0x2000) ==
        std::map<std::uint16_t, std::uint32_t>{{0x200E, 2}, {0x206C, 3}});
  CHECK(modified(*rig.drive, 0x1000) == mc_before);
  CHECK_FALSE(std::filesystem::exists(d.recovery_path));
}

TEST_CASE("factory_reset: curves and command table deleted and saved, no reset without a layer",
          "[factory_reset]") {
  test::SimRig rig("commissioned-axis.json");
  REQUIRE_FALSE(rig.drive->state().curves_flash.empty());
  REQUIRE_FALSE(rig.drive->state().ct_flash.empty());
  const auto params_before = rig.drive->state().params;
  ops::DefaultOptions d;
  d.curves = true;
  d.command_table = true;
  auto rep = ops::default_drive(*rig.client, d, db::Database::empty());
  REQUIRE(rep.ok());
  CHECK(rep->done == Steps{"stop MC", "delete all command table entries",
                           "save command table to flash", "delete all curves",
                           "save curves to flash", "start MC"});
  CHECK(rig.drive->state().curves_ram.empty());
  CHECK(rig.drive->state().curves_flash.empty());
  CHECK(rig.drive->state().ct_ram.empty());
  CHECK(rig.drive->state().ct_flash.empty());
  CHECK(rig.drive->stats().resets == 0);
  CHECK(rig.drive->state().mc_running);
  CHECK(rig.drive->state().params == params_before);

  ops::DefaultOptions curves_only;
  curves_only.curves = true;
  auto again = ops::default_drive(*rig.client, curves_only, db::Database::empty());
  REQUIRE(again.ok());
  CHECK(again->done == Steps{"stop MC", "delete all curves", "save curves to flash", "start MC"});
}

TEST_CASE("factory_reset: --include-comm defaults the communication values too",
          "[factory_reset]") {
  test::SimRig rig("commissioned-axis.json");
  rig.drive->state().switches = sim::HexSwitches{0x11, 57600};
  ops::DefaultOptions d;
  d.layers = {false, false, true, false};
  d.include_comm = true;
  auto rep = ops::default_drive(*rig.client, d, db::Database::empty());
  REQUIRE(rep.ok());
  CHECK(rep->link_may_change);
  CHECK(rep->kept.empty());
  CHECK(modified(*rig.drive, 0x2000).empty());
  // The switches select the same MACID and rate here, so the reset's answer arrives.
  CHECK(rep->done ==
        Steps{"stop MC", "default Intf layer", "start MC", "reset (defaults become active)"});
}

TEST_CASE(
    "factory_reset: --include-comm finishes an interrupted run's record without writing it back",
    "[factory_reset]") {
  test::ScratchDir dir("factory-reset-include-comm-record");
  test::SimRig rig("commissioned-axis.json");
  rig.drive->state().switches = sim::HexSwitches{0x11, 57600};
  ops::DefaultOptions d;
  d.layers = {false, false, true, false};
  d.include_comm = true;
  d.recovery_path = dir.path / "default-sim-11h.json";
  d.port = "sim";
  ops::RecoveryRecord rec{"default", "sim", 0x11, "2026-11-24T17:15:00Z", {}, {}, {}};
  rec.keep = {{0x200E, 2}, {0x206C, 3}};
  REQUIRE(ops::save_recovery(d.recovery_path, rec).ok());
  auto rep = ops::default_drive(*rig.client, d, db::Database::empty());
  REQUIRE(rep.ok());
  CHECK_FALSE(rep->recovered);
  CHECK(rep->kept.empty());
  CHECK(rep->recovery_note == "found the recovery record " + d.recovery_path.string() +
                                  " of an interrupted run (2026-11-24T17:15:00Z): --include-comm "
                                  "defaults the communication values too, nothing to write "
                                  "back; record deleted");
  CHECK(modified(*rig.drive, 0x2000).empty());
  CHECK_FALSE(std::filesystem::exists(d.recovery_path));
}

TEST_CASE("factory_reset: an interrupt between two steps names the step and the undo record",
          "[factory_reset]") {
  test::ScratchDir dir("factory-reset-interrupt");
  std::atomic<bool> cancel{false};
  client::ClientOptions co;
  co.cancel = &cancel;
  test::SimRig rig("commissioned-axis.json", co);
  const auto mc_before = modified(*rig.drive, 0x1000);
  ops::DefaultOptions d;
  d.layers = {false, true, false, false};
  d.undo = ops::UndoOptions{true, dir.path / "undo", "/dev/ttyS0", 0x11, "default", 10};
  // SIGINT right after MC was stopped.
  d.progress = [&](const std::string&, std::size_t done, std::size_t) {
    if (done == 1) cancel = true;
  };
  auto rep = ops::default_drive(*rig.client, d, db::Database::empty());
  REQUIRE_FALSE(rep.ok());
  CHECK(rep.error().code == make_error_code(Errc::interrupted));
  const auto undo_dir = dir.path / "undo" / "_dev_ttyS0-11h";
  REQUIRE(std::filesystem::is_directory(undo_dir));
  const auto record = std::filesystem::directory_iterator(undo_dir)->path();
  CHECK(rep.error().message ==
        "interrupted at step 'default MC layer': interrupted by a signal before the next "
        "telegram (the telegram in flight was completed). The drive is partially defaulted (MC "
        "stopped): run the same command again; the previous values are in the undo record " +
            record.string() + " (lmcfg undo --port /dev/ttyS0 --id 0x11).");
  CHECK_FALSE(rig.drive->state().mc_running);
  CHECK(modified(*rig.drive, 0x1000) == mc_before);
}

TEST_CASE("factory_reset: a failed step names the step and the recovery record to finish from",
          "[factory_reset]") {
  test::ScratchDir dir("factory-reset-fail");
  test::SimRig rig("commissioned-axis.json");
  ops::DefaultOptions d;
  d.layers = {false, false, true, false};
  d.recovery_path = dir.path / "default-sim-11h.json";
  d.port = "sim";
  // The drive stops answering once the Intf layer has been defaulted.
  d.progress = [&](const std::string&, std::size_t done, std::size_t) {
    if (done == 2) rig.drive->state().macid = 0x22;
  };
  auto rep = ops::default_drive(*rig.client, d, db::Database::empty());
  REQUIRE_FALSE(rep.ok());
  CHECK(rep.error().code == ErrorClass::link_failure);
  const std::string m = rep.error().message;
  CHECK(m.rfind("stopped at step 'keep communication parameter 200Eh = 2': ", 0) == 0);
  CHECK(
      m.ends_with(". The drive is partially defaulted (MC stopped): run the same command "
                  "again; it finishes from the recovery record " +
                  d.recovery_path.string() + "."));
  auto rec = ops::load_recovery(d.recovery_path);
  REQUIRE(rec.ok());
  REQUIRE(*rec);
  CHECK((*rec)->command == "default");
  CHECK((*rec)->port == "sim");
  CHECK((*rec)->macid == 0x11);
  CHECK((*rec)->keep == std::vector<client::ModifiedParam>{{0x200E, 2}, {0x206C, 3}});

  // The re-run at the drive's address finishes from the record.
  rig.drive->state().macid = 0x11;
  d.progress = nullptr;
  auto again = ops::default_drive(*rig.client, d, db::Database::empty());
  REQUIRE(again.ok());
  CHECK(again->recovered);
  CHECK(modified(*rig.drive, 0x2000) ==
        std::map<std::uint16_t, std::uint32_t>{{0x200E, 2}, {0x206C, 3}});
  CHECK_FALSE(std::filesystem::exists(d.recovery_path));
}

}  // namespace ops_test_factory_reset
