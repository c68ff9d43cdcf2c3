// lmcfg serve's service over a simulated RS485 line (sim:A.json,B.json state
// files changed behind its back): the schedule with an injected clock, events
// on state changes only, /metrics through promtool (the REST API's routes
// are tested in test_http.cpp, event delivery in test_notify.cpp).
#include <httplib.h>

#include <catch2/catch.hpp>
#include <mutex>
#include <nlohmann/json.hpp>

#include "devicenet_sim.hpp"
#include "files.hpp"
#include "link/session.hpp"
#include "promtool.hpp"
#include "serve/http.hpp"
#include "serve/service.hpp"
#include "serve_rig.hpp"
#include "sim/state_file.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace serve_test_service {

using namespace lmcfg;
using namespace lmcfg::test;
namespace fs = std::filesystem;
using namespace std::chrono_literals;

// GET /api/v1/drives writes the list's text without building it
// (Service::drives_text): the same bytes as the built list's dump.
std::string built_list_text(const serve::Service& s) {
  return s.drives().dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

TEST_CASE(
    "serve: the schedule is due at start, then every period, drift notified once, "
    "recovered once",
    "[serve][service]") {
  Rig rig;
  const auto t0 = rig.now;
  rig.at(t0);  // first tick: a backup (the archive's first commit), then a drift check
  CHECK(rig.service->next_backup() == t0 + 6h);
  CHECK(rig.service->next_status() == t0 + 15min);
  CHECK(rig.take_events().empty());  // new positions, archived: no state change to report
  auto drives = rig.service->drives();
  REQUIRE(drives.size() == 2);
  CHECK(drives[0]["status"] == "ok");
  CHECK(drives[0]["last_backup"] == "2027-01-15T08:00:00Z");
  CHECK(drives[1]["last_attempt"]["job"] == "status");
  CHECK(rig.service->drives_text() == built_list_text(*rig.service));
  REQUIRE(rig.service->job("1").ok());
  CHECK((*rig.service->job("1"))["commits"].size() == 1);
  CHECK((*rig.service->job("2"))["kind"] == "status");

  rig.at(t0 + 14min);  // nothing due
  CHECK_FALSE(rig.service->job("3").ok());
  CHECK(rig.service->next_status() == t0 + 15min);

  // Behind the service's back: a tuned parameter on press3/x, and an ignored
  // (volatile) UPID on press3/z.
  write_axis(rig.dir.path / "b.json", 0x12, "0010", 7);
  write_axis(rig.dir.path / "a.json", 0x11, "0020", 2000);
  rig.at(t0 + 15min);
  auto events = rig.take_events();
  REQUIRE(events.size() == 1);
  CHECK(events[0]["event"] == "drift");
  CHECK(events[0]["drive"] == "press3/x");
  CHECK(events[0]["line"] == "line1");
  CHECK(events[0]["time"] == "2027-01-15T08:15:00Z");
  CHECK(events[0]["job"] == "status");
  CHECK(events[0]["parameters"] == 1);
  CHECK(events[0]["differences"] == 1);
  REQUIRE(events[0]["upids"].size() == 1);
  CHECK(events[0]["upids"][0]["upid"] == "0010h");
  CHECK(events[0]["upids"][0]["archived"] == "5");
  // A link to the diff as lmcfg report renders it (the console's /diff page):
  // the approved configuration (the first backup's, commissioning) against the drive.
  const std::string approved = git(rig.dir.path / "archive", "rev-parse HEAD").substr(0, 40);
  CHECK(events[0]["report"] == "/diff?name=press3%2Fx&from=" + approved + "&to=live");
  CHECK(events[0]["upids"][0]["live"] == "7");
  CHECK((*rig.service->drive("press3/x"))["status"] == "drift");
  CHECK((*rig.service->drive("press3/x"))["differences"] == 1);
  CHECK(rig.service->drives()[1]["differing"].size() == 1);
  CHECK(rig.service->drives_text() == built_list_text(*rig.service));
  CHECK((*rig.service->drive("press3/z"))["status"] == "ok");
  CHECK(rig.service->next_status() == t0 + 30min);

  rig.at(t0 + 30min);  // still drifted: the same state is not notified twice
  CHECK(rig.take_events().empty());
  CHECK((*rig.service->drive("press3/x"))["status"] == "drift");

  write_axis(rig.dir.path / "b.json", 0x12);  // put back
  rig.at(t0 + 45min);
  events = rig.take_events();
  REQUIRE(events.size() == 1);
  CHECK(events[0]["event"] == "recovered");
  CHECK(events[0]["drive"] == "press3/x");
  CHECK(events[0]["previous"] == "drift");
  rig.at(t0 + 60min);
  CHECK(rig.take_events().empty());

  // A line that cannot be opened: backup_failed once, with the CLI's exit category.
  fs::remove(rig.dir.path / "b.json");
  rig.at(t0 + 75min);
  rig.at(t0 + 90min);
  events = rig.take_events();
  REQUIRE(events.size() == 2);  // both drives of the line, once each
  CHECK(events[0]["event"] == "backup_failed");
  CHECK(events[0]["job"] == "status");
  CHECK(events[0]["exit_code"] == 4);
  CHECK(events[0]["reason"].get<std::string>().find("line 'line1'") == 0);
  CHECK((*rig.service->drive("press3/z"))["status"] == "failed");
  CHECK(rig.service->drives_text() == built_list_text(*rig.service));
  write_axis(rig.dir.path / "b.json", 0x12);
  rig.at(t0 + 105min);
  events = rig.take_events();
  REQUIRE(events.size() == 2);
  CHECK(events[0]["event"] == "recovered");
  CHECK(events[0]["previous"] == "failed");
}

TEST_CASE("serve: a backup that finds a change commits it and says so once", "[serve][service]") {
  Rig rig;
  rig.at(rig.now);
  write_axis(rig.dir.path / "a.json", 0x11, "0010", 9);
  auto job = rig.service->backup_drive("press3/z");
  REQUIRE(job.ok());
  rig.service->wait_idle();
  auto events = rig.take_events();
  REQUIRE(events.size() == 1);
  CHECK(events[0]["event"] == "drift");
  CHECK(events[0]["job"] == "backup");
  const auto j = *rig.service->job(*job);
  CHECK(j["state"] == "done");
  CHECK(j["scope"] == "drive press3/z");
  CHECK(j["drives"] == 1);
  CHECK(j["counts"]["changed"] == 1);
  REQUIRE(j["commits"].size() == 1);
  CHECK(events[0]["committed"].get<std::string>() == j["commits"][0].get<std::string>());
  // Archived is not approved: the position differs from its approved configuration.
  CHECK((*rig.service->drive("press3/z"))["status"] == "drift");
  CHECK((*rig.service->drive("press3/z"))["message"] ==
        "1 parameter, 0 curves, 0 CT entries differ from the approved configuration (archived)");
  auto history = rig.service->history("press3/z");
  REQUIRE(history.ok());
  REQUIRE(history->size() == 2);  // the first backup and this one
  CHECK((*history)[0]["commit"] == j["commits"][0]);
  CHECK((*history)[0]["message"].get<std::string>().rfind("fleet backup: 1 changed, 0 unchanged",
                                                          0) == 0);
  CHECK((*history)[0]["author"].get<std::string>().find('<') != std::string::npos);
  CHECK(rig.service->history("press3/x")->size() == 1);
  CHECK(rig.service->backup_drive("press9/q").error().message ==
        "no drive named 'press9/q' in the inventory");
  CHECK(rig.service->backup_line("line9").error().message ==
        "no line named 'line9' in the inventory");
}

TEST_CASE("serve: /metrics passes promtool check metrics", "[serve][metrics]") {
  Rig rig;
  rig.at(rig.now);
  write_axis(rig.dir.path / "b.json", 0x12, "0010", 7);
  rig.at(rig.now + 15min);
  Server server(*rig.service);
  httplib::Client c("127.0.0.1", server.port);
  auto res = c.Get("/metrics");
  REQUIRE(res);
  CHECK(res->status == 200);
  const std::string& text = res->body;
  CHECK(text.find("lmcfg_drive_drift{drive=\"press3/x\",line=\"line1\"} 1\n") != std::string::npos);
  CHECK(text.find("lmcfg_drive_drift{drive=\"press3/z\",line=\"line1\"} 0\n") != std::string::npos);
  CHECK(text.find("lmcfg_drive_differences{drive=\"press3/x\",line=\"line1\"} 1\n") !=
        std::string::npos);
  CHECK(text.find("lmcfg_drive_last_attempt_success{drive=\"press3/x\",line=\"line1\"} 1\n") !=
        std::string::npos);
  CHECK(text.find("lmcfg_drive_last_backup_timestamp_seconds{drive=\"press3/x\",line=\"line1\"} "
                  "1800000000\n") != std::string::npos);
  CHECK(text.find("lmcfg_line_runs_total{line=\"line1\"} 3\n") != std::string::npos);
  CHECK(text.find("lmcfg_serve_uptime_seconds 900\n") != std::string::npos);
  CHECK(text.find("lmcfg_line_telegrams_total{line=\"line1\"} 0\n") == std::string::npos);

  test::check_with_promtool(text, rig.dir.path);
}

TEST_CASE(
    "serve: a DeviceNet line (lmcfg sim --devicenet on loopback TCP) is backed up by the "
    "schedule and a value changed behind its back is drift, notified once",
    "[serve][service][devicenet]") {
  test::DevicenetSim sim({}, test::DevicenetSim::Where::tcp);
  test::ScratchDir dir{"serve-dn"};
  auto inv = fleet::parse_inventory(
      "[schedule]\nbackup_every = \"6h\"\nstatus_every = \"15m\"\n[[line]]\nname = \"can\"\n"
      "port = \"" +
          sim.port + "\"\n[[line.drive]]\nname = \"press5/controller\"\ndevicenet_macid = 5\n",
      "plant.toml");
  REQUIRE(inv.ok());
  serve::TimePoint now = serve::Clock::from_time_t(1'800'000'000);
  std::mutex mu;
  std::vector<nlohmann::json> events;
  serve::ServiceOptions o;
  o.inventory = *inv;
  o.archive = (dir.path / "archive").string();
  ops::DevicenetLinkOptions dn;
  dn.port = sim.port;
  dn.master.timeout = transport::Millis(100);
  dn.master.duplicate_check_wait = transport::Millis(20);
  ops::LineLink link;
  link.devicenet = dn;
  o.links = {link};
  o.exit_code = [](const Error&) { return 4; };
  o.clock = [&] { return now; };
  o.notify = [&](const serve::Json& e) {
    std::lock_guard<std::mutex> lock(mu);
    events.push_back(nlohmann::json::parse(e.dump()));
  };
  auto service = serve::Service::create(std::move(o));
  REQUIRE(service.ok());
  (*service)->tick(now);  // a backup (the archive's first commit), then a drift check
  (*service)->wait_idle();
  auto drives = (*service)->drives();
  REQUIRE(drives.size() == 1);
  CHECK(drives[0]["status"] == "ok");
  CHECK(fs::exists(dir.path / "archive/press5/controller.json"));

  test::change_two_values(sim);
  now += 15min;
  (*service)->tick(now);
  (*service)->wait_idle();
  std::lock_guard<std::mutex> lock(mu);
  REQUIRE(events.size() == 1);
  CHECK(events[0]["event"] == "drift");
  CHECK(events[0]["drive"] == "press5/controller");
  CHECK(events[0]["line"] == "can");
}

TEST_CASE(
    "serve: job numbers go on after a restart, and a job of the earlier run says it ended "
    "before the restart",
    "[serve][service][jobs]") {
  Rig rig;
  rig.at(rig.now);
  auto before = rig.service->backup_drive("press3/z", "ops");
  REQUIRE(before.ok());
  rig.service->wait_idle();
  rig.restart();
  auto after = rig.service->backup_drive("press3/z", "ops");
  REQUIRE(after.ok());
  CHECK(std::stoul(*after) > std::stoul(*before));
  auto old = rig.service->job(*before);
  REQUIRE_FALSE(old.ok());
  CHECK(old.error().code == Errc::not_found);
  CHECK(old.error().message ==
        "job " + *before +
            " ended before the service restarted: its record is not kept across a restart; the "
            "position's history lists what it did");
  {
    // The console's job page of it says so too, not "No such job".
    Server server(*rig.service);
    httplib::Client c("127.0.0.1", server.port);
    auto page = c.Get("/job?id=" + *before);
    REQUIRE(page);
    CHECK(page->status == 404);
    CHECK(page->body.find("Job no longer kept") != std::string::npos);
    CHECK(page->body.find("ended before the service restarted") != std::string::npos);
  }
  const std::string never = std::to_string(std::stoul(*after) + 1);
  CHECK(rig.service->job(never).error().message == "no job " + never);
  CHECK(rig.service->job("0").error().message == "no job 0");
  // A later restart does not give a number twice either.
  rig.service->wait_idle();
  rig.restart();
  auto third = rig.service->backup_drive("press3/z", "ops");
  REQUIRE(third.ok());
  CHECK(std::stoul(*third) > std::stoul(*after));
}

TEST_CASE(
    "serve: the archive's commits are by the service on its host, the person who asked in "
    "the Operator trailer",
    "[serve][service][git-cli]") {
  Rig rig;
  rig.tweaked_with = [](serve::ServiceOptions& o) {
    o.exit_code = exit_code_of;
    o.host = "plant-pc<1>";
  };
  rig.restart();
  rig.at(rig.now);
  write_axis(rig.dir.path / "a.json", 0x11, "0010", 9);
  REQUIRE(rig.service->backup_drive("press3/z", "night-shift").ok());
  rig.service->wait_idle();
  const auto archive = rig.dir.path / "archive";
  CHECK(git(archive, "log -1 '--format=%an <%ae>|%cn'") ==
        "lmcfg serve on plant-pc1 <lmcfg-serve@plant-pc1>|lmcfg serve on plant-pc1\n");
  CHECK(git(archive, "log -1 '--format=%(trailers)'") == "Operator: night-shift\n\n");
}

TEST_CASE(
    "serve: a second technician's restore of a position another restore waits or runs on "
    "is refused, naming that job, who asked and since when",
    "[serve][service][restore]") {
  // The line's worker can be held in the drift event (notify runs on it).
  std::mutex gate;
  std::unique_lock<std::mutex> held(gate, std::defer_lock);
  Rig rig;
  rig.tweaked_with = [&gate](serve::ServiceOptions& o) {
    o.exit_code = exit_code_of;
    o.notify = [&gate](const serve::Json& e) {
      if (e["event"] == "drift") std::lock_guard<std::mutex> wait(gate);
    };
  };
  rig.restart();
  rig.at(rig.now);
  write_axis(rig.dir.path / "a.json", 0x11, "0010", 9);
  auto mine = rig.service->plan("press3/z", "", "day-shift");
  auto theirs = rig.service->plan("press3/z", "", "night-shift");
  REQUIRE(mine.ok());
  REQUIRE(theirs.ok());
  held.lock();
  // A backup finds the change: its drift event holds the worker.
  REQUIRE(rig.service->backup_drive("press3/z", "day-shift").ok());
  serve::Service::ExecuteRequest req;
  req.plan_id = (*mine)["plan_id"].get<std::string>();
  req.audit = {"day-shift", "tuning lost", ""};
  auto first = rig.service->execute(req);
  INFO((first.ok() ? "" : first.error().message));
  REQUIRE(first.ok());
  req.plan_id = (*theirs)["plan_id"].get<std::string>();
  req.audit = {"night-shift", "tuning lost", ""};
  auto second = rig.service->execute(req);
  REQUIRE_FALSE(second.ok());
  CHECK(second.error().code == Errc::plan_refused);
  CHECK(second.error().message ==
        "another restore of drive press3/z is waiting for the line as job " + *first +
            ", asked for by day-shift at " + serve::iso_time(rig.now) +
            "; nothing written: wait for it to end (GET /api/v1/jobs/" + *first +
            "), then plan again");
  held.unlock();
  rig.service->wait_idle();
  CHECK((*rig.service->job(*first))["state"] == "done");
}

}  // namespace serve_test_service
