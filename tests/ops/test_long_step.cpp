// Long operations whose answer comes late or never (lib/ops/long_step.cpp,
// Client::find_again, docs/field.md "Slow saves") against the simulated
// drive on its virtual clock (40 s saves cost no real time): field reports,
// "A command table flash save took about 39 s and was never
// acknowledged", C1250 notes, "ROM writes and flash saves left drives unresponsive
// for 30-90 s". Restore and default succeed under both readings (answered
// late, never answered); a drive silent past both waits gets a message that
// says what was waited and which options wait longer.
#include <algorithm>
#include <catch2/catch.hpp>
#include <filesystem>

#include "db/database.hpp"
#include "e2e_support.hpp"
#include "files.hpp"
#include "link/session.hpp"
#include "ops/backup.hpp"
#include "ops/factory_reset.hpp"
#include "ops/long_step.hpp"
#include "ops/recovery.hpp"
#include "ops/restore_run.hpp"
#include "session_rig.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace ops_test_long_step {

using namespace lmcfg;
using Stage = ops::RestoreOutcome::Stage;
namespace fs = std::filesystem;

namespace {

constexpr std::int64_t kSeconds = 1'000'000;  // sim::Timing is in microseconds

// The drive's saves and defaulting take `s` seconds; answered late, or never
// (sim Options::unanswered_saves).
void slow_saves(sim::Drive& d, std::int64_t s, bool answered) {
  d.state().timing.flash_save_us = s * kSeconds;
  d.state().timing.defaulting_us = s * kSeconds;
  d.state().options.unanswered_saves = !answered;
  d.state().mc_running = false;  // a save needs MC stopped (§12)
}

using test::demo_backup;
// A session over the simulated drive with the tools' client defaults.
struct SessionRig : test::SessionRig {
  explicit SessionRig(std::shared_ptr<sim::Drive> d) : test::SessionRig(std::move(d), "sim:slow") {}
};

// The run's flash saves and reset as the plan lists them.
std::size_t count_steps(const ops::Plan& p, ops::PlanStep::Action a) {
  std::size_t n = 0;
  for (const auto& s : p.steps) n += s.action == a ? 1 : 0;
  return n;
}

}  // namespace

TEST_CASE("field reports: a 40 s command table save answered late is waited for",
          "[long_step][slow_saves]") {
  test::SimRig rig("commissioned-axis.json");
  slow_saves(*rig.drive, 40, true);
  std::vector<long long> progress;
  auto opt = rig.client->options();
  opt.on_long_wait = [&](const std::string& what, client::Millis waited) {
    CHECK(what == "saving the command table to flash");
    progress.push_back(waited.count());
  };
  rig.client->set_options(opt);
  const auto t0 = rig.sim().clock().now_ns();
  auto r = ops::long_step(*rig.client, "saving the command table to flash",
                          [&] { return rig.client->save_ct(); });
  REQUIRE(r.ok());
  CHECK(r->acknowledged);
  CHECK(r->note.empty());
  const auto took_s = (rig.sim().clock().now_ns() - t0) / 1'000'000'000;
  CHECK(took_s == 40);
  // Progress about once a second, in link time: 1 s .. 40 s.
  REQUIRE(progress.size() == 40);
  CHECK(progress.front() == 1000);
  CHECK(progress.back() == 40000);
}

TEST_CASE("field reports: a 40 s save never answered: the drive is found again",
          "[long_step][slow_saves]") {
  test::SimRig rig("commissioned-axis.json");
  slow_saves(*rig.drive, 40, false);
  std::vector<std::string> waits;
  auto opt = rig.client->options();
  opt.on_long_wait = [&](const std::string& what, client::Millis) { waits.push_back(what); };
  rig.client->set_options(opt);
  REQUIRE_FALSE(rig.drive->state().ct_ram.empty());
  rig.drive->state().ct_ram.erase(rig.drive->state().ct_ram.begin());  // RAM differs from flash
  auto r = ops::long_step(*rig.client, "saving the command table to flash",
                          [&] { return rig.client->save_ct(); });
  REQUIRE(r.ok());
  CHECK_FALSE(r->acknowledged);
  // Silent 40 s, the deadline 120 s: the first poll after it is answered.
  CHECK(r->note ==
        "the drive did not acknowledge saving the command table to flash within 120 s and "
        "answered again 0 s later");
  CHECK(rig.drive->state().ct_flash == rig.drive->state().ct_ram);  // it did save
  REQUIRE_FALSE(waits.empty());
  CHECK(waits.back() == "saving the command table to flash");
}

TEST_CASE("field reports: a drive silent 150 s after a save is polled until it answers",
          "[long_step][slow_saves]") {
  test::SimRig rig("commissioned-axis.json");
  slow_saves(*rig.drive, 150, false);
  std::vector<std::string> waits;
  auto opt = rig.client->options();
  opt.on_long_wait = [&](const std::string& what, client::Millis) { waits.push_back(what); };
  rig.client->set_options(opt);
  const auto t0 = rig.sim().clock().now_ns();
  auto r = ops::long_step(*rig.client, "saving the curves to flash",
                          [&] { return rig.client->save_curves(); });
  REQUIRE(r.ok());
  CHECK_FALSE(r->acknowledged);
  CHECK(r->note ==
        "the drive did not acknowledge saving the curves to flash within 120 s and answered "
        "again 30 s later");
  const double took_s = static_cast<double>(rig.sim().clock().now_ns() - t0) / 1e9;
  CHECK(took_s >= 150.0);
  CHECK(took_s < 152.0);  // found within a poll of its return
  CHECK(std::count(waits.begin(), waits.end(),
                   "waiting for drive 11h to answer again after saving the curves to flash") >= 29);
}

TEST_CASE("field reports: a drive silent past both waits: what was waited, how to wait longer",
          "[long_step][slow_saves]") {
  test::SimRig rig("commissioned-axis.json");
  slow_saves(*rig.drive, 400, false);
  const auto t0 = rig.sim().clock().now_ns();
  auto r = ops::long_step(*rig.client, "saving the command table to flash",
                          [&] { return rig.client->save_ct(); });
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == Errc::timeout);
  CHECK(r.error().message ==
        "no answer within 120 s, and drive 11h did not answer again within 180 s after saving "
        "the command table to flash (polled with §6 default response requests); the drive may "
        "still be busy (real drives were silent for 30-90 s after saves and ROM writes) or gone: "
        "if it is slow, wait longer with --long-timeout-s (now 120) or --recover-timeout-s (now "
        "180), else check its power and wiring");
  const double took_s = static_cast<double>(rig.sim().clock().now_ns() - t0) / 1e9;
  CHECK(took_s >= 300.0);
  CHECK(took_s < 302.0);
}

TEST_CASE("long step: a refusal is no missing answer (nothing polled)", "[long_step]") {
  test::SimRig rig("commissioned-axis.json");  // MC runs: the save is refused (§12)
  const auto before = rig.wire->tx.size();
  auto r = ops::long_step(*rig.client, "saving the command table to flash",
                          [&] { return rig.client->save_ct(); });
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == ErrorClass::drive_refusal);
  CHECK(rig.wire->tx.size() == before + 1);
}

TEST_CASE("field reports: restore onto a drive whose saves take 40 s: answered late or never",
          "[long_step][slow_saves][restore_run]") {
  const auto file = demo_backup();
  for (const bool answered : {true, false}) {
    DYNAMIC_SECTION((answered ? "answered late" : "never answered")) {
      test::ScratchDir dir("slow");
      SessionRig rig(test::load_sim_drive("used-spare.json"));
      slow_saves(*rig.drive, 40, answered);
      rig.drive->state().mc_running = true;  // as found; the restore stops MC
      ops::RestoreRunOptions o;
      o.restore.recovery_path = dir.path / "restore-sim-11h.json";
      o.restore.port = "sim:slow";
      const auto out = ops::run_restore(*rig.session, file, db::Database::empty(), o);
      INFO((out.error ? out.error->message : std::string()));
      REQUIRE(out.stage == Stage::restored);
      CHECK(out.mismatches.empty());
      const std::size_t saves = count_steps(out.plan, ops::PlanStep::Action::save_ct) +
                                count_steps(out.plan, ops::PlanStep::Action::save_curves);
      REQUIRE(saves == 2);
      if (answered) {
        CHECK(out.unacknowledged.empty());
      } else {
        // Each save went unacknowledged; the read-back after the reset matched.
        std::size_t unacked_saves = 0;
        for (const auto& u : out.unacknowledged) {
          INFO(u);
          CHECK(u.find("within 120 s and answered again 0 s later") != std::string::npos);
          unacked_saves += u.find("the drive did not acknowledge saving the ") != std::string::npos;
        }
        CHECK(unacked_saves == saves);
      }
      CHECK_FALSE(fs::exists(o.restore.recovery_path));  // removed once verified
      CHECK(rig.drive->state().ct_flash == rig.drive->state().ct_ram);
      CHECK(rig.drive->state().curves_flash == rig.drive->state().curves_ram);
    }
  }
}

TEST_CASE("field reports: restore: the recovery record lists an unacknowledged save",
          "[long_step][slow_saves][recovery]") {
  const auto file = demo_backup();
  test::ScratchDir dir("slowrec");
  SessionRig rig(test::load_sim_drive("used-spare.json"));
  slow_saves(*rig.drive, 400, false);  // silent past 120 + 180 s
  rig.drive->state().mc_running = true;
  ops::RestoreRunOptions o;
  o.restore.recovery_path = dir.path / "restore-sim-11h.json";
  o.restore.port = "sim:slow";
  auto opt = rig.session->client().options();
  opt.recover_timeout = client::Millis(10000);
  rig.session->client().set_options(opt);
  const auto out = ops::run_restore(*rig.session, file, db::Database::empty(), o);
  REQUIRE(out.stage == Stage::failed);
  REQUIRE(out.error);
  CHECK(out.error->code == Errc::timeout);
  const std::string& m = out.error->message;
  // The first long step that went unanswered (a defaulting or a save).
  CHECK(m.find(": no answer within 120 s, and drive 11h did not answer again within 10 s after ") !=
        std::string::npos);
  CHECK(m.find("--recover-timeout-s (now 10)") != std::string::npos);
  CHECK(m.find(". The drive is partially configured and MC is stopped: steps 1..") !=
        std::string::npos);
  CHECK(m.find("Once the drive answers, run the same restore with longer waits to converge.") !=
        std::string::npos);
  CHECK(m.find("run the same restore again") == std::string::npos);
  // The record stays for the re-run (it saves the tables again).
  auto rec = ops::load_recovery(o.restore.recovery_path);
  REQUIRE(rec.ok());
  REQUIRE(rec->has_value());
  CHECK((*rec)->unacknowledged.empty());  // the save was never found acknowledged nor answered
}

TEST_CASE("field reports: default with 40 s defaulting and saves: answered late or never",
          "[long_step][slow_saves][default]") {
  for (const bool answered : {true, false}) {
    DYNAMIC_SECTION((answered ? "answered late" : "never answered")) {
      test::SimRig rig("commissioned-axis.json");
      slow_saves(*rig.drive, 40, answered);
      rig.drive->state().mc_running = true;
      ops::DefaultOptions d;
      d.layers = {false, true, false, false};
      d.curves = true;
      d.command_table = true;
      auto rep = ops::default_drive(*rig.client, d, db::Database::empty());
      INFO((rep.ok() ? std::string() : rep.error().message));
      REQUIRE(rep.ok());
      if (answered) {
        CHECK(rep->unacknowledged.empty());
      } else {
        REQUIRE(rep->unacknowledged.size() == 3);
        CHECK(rep->unacknowledged[0] ==
              "default MC layer: the drive did not acknowledge defaulting layer MC within 120 s "
              "and answered again 0 s later");
        CHECK(rep->unacknowledged[1] ==
              "save command table to flash: the drive did not acknowledge saving the command "
              "table to flash within 120 s and answered again 0 s later");
        CHECK(rep->unacknowledged[2] ==
              "save curves to flash: the drive did not acknowledge saving the curves to flash "
              "within 120 s and answered again 0 s later");
        // Each read back: the layer, then (after the restart) both tables.
        CHECK(std::find(rep->done.begin(), rep->done.end(), "read back the MC layer (defaulted)") !=
              rep->done.end());
        CHECK(rep->done.back() == "read back the curves (none)");
      }
      CHECK(rig.drive->state().ct_flash.empty());
      CHECK(rig.drive->state().curves_flash.empty());
      CHECK(rig.drive->state().mc_running);
    }
  }
}

}  // namespace ops_test_long_step
