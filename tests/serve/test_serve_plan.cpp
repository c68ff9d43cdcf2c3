// lmcfg serve's restore API (plan, execute, the restore job), diff and report
// of a position, replaced drives (factory-fresh at a position the archive
// holds) with and without the automatic restore, and the daily summary; on
// the library's Service with an injected clock and over HTTP on 127.0.0.1.
// The archive's commits are read with the real git.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "files.hpp"
#include "serve/tokens.hpp"
#include "serve_rig.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace serve_test_serve_plan {

using namespace lmcfg;
using namespace lmcfg::test;
using namespace std::chrono_literals;

namespace {

// A ROM value of the simulated drive's state file.
nlohmann::json rom_of(const fs::path& state, const std::string& upid) {
  const auto j = nlohmann::json::parse(slurp(state));
  for (const auto& p : j["parameters"])
    if (p["upid"] == upid) return p["rom"];
  return nullptr;
}

nlohmann::json plain(const serve::Json& j) { return nlohmann::json::parse(j.dump()); }

}  // namespace

TEST_CASE("serve: plan, execute, the restore job's progress and outcome, a commit with trailers",
          "[serve][plan][git-cli]") {
  Rig rig;
  rig.at(rig.now);  // the archive's first commit: both drives
  const std::string head = git(rig.dir.path / "archive", "rev-parse HEAD").substr(0, 40);
  write_axis(rig.dir.path / "a.json", 0x11, "0010", 9);  // tuned behind the service's back

  auto planned = rig.service->plan("press3/z", "", "ops");
  REQUIRE(planned.ok());
  const auto p = plain(*planned);
  CHECK(p["drive"] == "press3/z");
  CHECK(p["line"] == "line1");
  CHECK(p["rev"] == "approved");
  CHECK(p["commit"] == head);
  CHECK(p["expires"] == "2027-01-15T08:05:00Z");
  CHECK(p["factory_fresh"] == false);
  CHECK(p["problems"].empty());
  CHECK(p["incompatible"].empty());
  // The drive's 9 goes back to the archived 5: MC stopped, the value written, a reset.
  bool wrote = false;
  for (const auto& st : p["steps"]) {
    if (st["kind"] != "write_rom") continue;
    CHECK(st["upid"] == "0010");
    CHECK(st["old"] == "9");
    CHECK(st["new"] == "5");
    CHECK(st["old_raw"] == 9);
    CHECK(st["new_raw"] == 5);
    wrote = true;
  }
  CHECK(wrote);
  CHECK(p["steps"].front()["kind"] == "stop_mc");
  const std::size_t steps = p["steps"].size();
  CHECK(rom_of(rig.dir.path / "a.json", "0010") == 9);  // planning writes nothing

  serve::Service::ExecuteRequest req;
  req.plan_id = p["plan_id"];
  req.audit = {"ops", "tuning lost after a repair", "CHG-4711"};
  auto id = rig.service->execute(req);
  REQUIRE(id.ok());
  rig.service->wait_idle();
  const auto job = plain(*rig.service->job(*id));
  INFO(job.dump());
  CHECK(job["kind"] == "restore");
  CHECK(job["scope"] == "drive press3/z");
  CHECK(job["state"] == "done");
  CHECK(job["who"] == "ops");
  CHECK(job["outcome"] == "restored and verified");
  CHECK(job["exit_code"] == 0);
  CHECK(job["progress"]["done"] == steps);
  CHECK(job["progress"]["total"] == steps);
  CHECK(job["message"] ==
        "restored press3/z.json@" + head.substr(0, 12) + " onto press3/z and verified");
  REQUIRE(job["commit"].is_string());
  CHECK(rom_of(rig.dir.path / "a.json", "0010") == 5);

  // The recording commit, as git reads it: subject, and the audit trailers.
  const auto archive = rig.dir.path / "archive";
  CHECK(git(archive, "rev-parse HEAD").substr(0, 40) == job["commit"]);
  CHECK(git(archive, "log -1 --format=%s") == "fleet restore: press3/z <- press3/z.json at " +
                                                  head.substr(0, 12) +
                                                  " (approved): restored and verified\n");
  CHECK(git(archive, "log -1 '--format=%(trailers)'") ==
        "Operator: ops\nReason: tuning lost after a repair\nTicket: CHG-4711\n\n");

  auto events = rig.take_events();
  REQUIRE(events.size() == 1);
  CHECK(events[0]["event"] == "restored");
  CHECK(events[0]["drive"] == "press3/z");
  CHECK(events[0]["commit"] == job["commit"]);
  CHECK(events[0]["operator"] == "ops");
  CHECK(events[0]["automatic"] == false);
  CHECK((*rig.service->drive("press3/z"))["status"] == "ok");

  // A plan executes once.
  auto again = rig.service->execute(req);
  REQUIRE_FALSE(again.ok());
  CHECK(again.error().message == "no plan '" + req.plan_id + "'");
}

TEST_CASE("serve: plan and execute onto the line's second drive (press3/x, 12h)",
          "[serve][plan][multidrop][git-cli]") {
  Rig rig;
  rig.at(rig.now);
  const std::string head = git(rig.dir.path / "archive", "rev-parse HEAD").substr(0, 40);
  write_axis(rig.dir.path / "b.json", 0x12, "0010", 9);  // tuned behind the service's back

  auto planned = rig.service->plan("press3/x", "", "ops");
  REQUIRE(planned.ok());
  const auto p = plain(*planned);
  CHECK(p["drive"] == "press3/x");
  CHECK(p["problems"].empty());
  serve::Service::ExecuteRequest req;
  req.plan_id = p["plan_id"];
  req.audit = {"ops", "tuning lost after a repair", "CHG-4712"};
  auto id = rig.service->execute(req);
  REQUIRE(id.ok());
  rig.service->wait_idle();
  const auto job = plain(*rig.service->job(*id));
  INFO(job.dump());
  CHECK(job["state"] == "done");
  CHECK(job["outcome"] == "restored and verified");
  CHECK(job["exit_code"] == 0);
  CHECK(job["message"] ==
        "restored press3/x.json@" + head.substr(0, 12) + " onto press3/x and verified");
  CHECK(rom_of(rig.dir.path / "b.json", "0010") == 5);
  CHECK(rom_of(rig.dir.path / "a.json", "0010") == 5);  // the first drive untouched
  CHECK((*rig.service->drive("press3/x"))["status"] == "ok");
  CHECK((*rig.service->drive("press3/z"))["status"] == "ok");
}

TEST_CASE("serve: an expired plan, a missing reason, a changed target are refused",
          "[serve][plan]") {
  Rig rig("require_reason = true\n");
  rig.at(rig.now);
  write_axis(rig.dir.path / "a.json", 0x11, "0010", 9);
  auto p = rig.service->plan("press3/z", "", "ops");
  REQUIRE(p.ok());
  serve::Service::ExecuteRequest req;
  req.plan_id = (*p)["plan_id"];
  req.audit.who = "ops";

  auto e = rig.service->execute(req);
  REQUIRE_FALSE(e.ok());
  CHECK(e.error().code == Errc::invalid_argument);
  CHECK(e.error().message ==
        "a reason is required (the inventory sets require_reason = true): give \"reason\"");

  rig.now += 301s;
  req.audit.reason = "repair";
  e = rig.service->execute(req);
  REQUIRE_FALSE(e.ok());
  CHECK(e.error().code == Errc::not_found);
  CHECK(e.error().message == "plan '" + req.plan_id +
                                 "' expired at 2027-01-15T08:05:00Z (a plan is valid for 300 s): "
                                 "make a new one");

  // Planned, then the drive changes again before the execution: nothing written.
  p = rig.service->plan("press3/z", "", "ops");
  REQUIRE(p.ok());
  req.plan_id = (*p)["plan_id"];
  write_axis(rig.dir.path / "a.json", 0x11, "0010", 11);
  auto id = rig.service->execute(req);
  REQUIRE(id.ok());
  rig.service->wait_idle();
  const auto job = plain(*rig.service->job(*id));
  CHECK(job["state"] == "failed");
  CHECK(job["outcome"] == "failed");
  CHECK(job["exit_code"] == 3);
  CHECK(job["message"] == "the target changed since plan " + req.plan_id +
                              " was made (the OS layer's modified parameters); nothing written: "
                              "make a new plan");
  CHECK(job["commit"].is_null());
  CHECK(rom_of(rig.dir.path / "a.json", "0010") == 11);
  auto events = rig.take_events();
  REQUIRE(events.size() == 1);
  CHECK(events[0]["event"] == "restore_failed");
  CHECK(events[0]["exit_code"] == 3);
  CHECK(rig.service->plan("press9/q", "", "ops").error().message ==
        "no drive named 'press9/q' in the inventory");
}

TEST_CASE("serve: plan and execute over HTTP, a viewer's token may not, who is the token's name",
          "[serve][plan][http][git-cli]") {
  Rig rig;
  rig.at(rig.now);
  const std::string file = (rig.dir.path / "tokens").string();
  const auto viewer = *serve::add_token(file, "grafana", serve::Role::viewer);
  const auto op = *serve::add_token(file, "maria", serve::Role::operator_);
  Server server(*rig.service, *serve::load_tokens(file));
  httplib::Client c("127.0.0.1", server.port);
  const httplib::Headers as_viewer{{"Authorization", "Bearer " + viewer}};
  const httplib::Headers as_op{{"Authorization", "Bearer " + op}};
  write_axis(rig.dir.path / "a.json", 0x11, "0010", 7);

  auto res = c.Post("/api/v1/drives/press3/z/plan", as_viewer, "{}", "application/json");
  REQUIRE(res);
  CHECK(res->status == 403);
  CHECK(nlohmann::json::parse(res->body) ==
        nlohmann::json{{"error", "token 'grafana' has role viewer: POST needs role operator"},
                       {"exit_code", 2}});
  res = c.Post("/api/v1/drives/press3/z/plan", as_op, "{\"rev\": 5}", "application/json");
  REQUIRE(res);
  CHECK(res->status == 400);
  CHECK(nlohmann::json::parse(res->body)["error"] == "\"rev\" must be a string");
  res =
      c.Post("/api/v1/drives/press3/z/plan", as_op, "{\"rev\": \"nosuchrev\"}", "application/json");
  REQUIRE(res);
  CHECK(res->status == 404);
  CHECK(nlohmann::json::parse(res->body)["exit_code"] == 2);

  res = c.Post("/api/v1/drives/press3/z/plan", as_op, "{\"rev\": \"HEAD\"}", "application/json");
  REQUIRE(res);
  REQUIRE(res->status == 200);
  const auto plan = nlohmann::json::parse(res->body);
  CHECK(plan["who"] == "maria");
  const std::string execute = "/api/v1/plans/" + plan["plan_id"].get<std::string>() + "/execute";
  res = c.Post(execute, as_viewer, "{}", "application/json");
  REQUIRE(res);
  CHECK(res->status == 403);
  res = c.Post("/api/v1/plans/0123abcd/execute", as_op, "{}", "application/json");
  REQUIRE(res);
  CHECK(res->status == 404);
  CHECK(nlohmann::json::parse(res->body) ==
        nlohmann::json{{"error", "no plan '0123abcd'"}, {"exit_code", 2}});
  res = c.Post(execute, as_op, "{\"reason\": \"drift\", \"ticket\": \"T-1\"}", "application/json");
  REQUIRE(res);
  CHECK(res->status == 202);
  const std::string job_id = nlohmann::json::parse(res->body)["job"];
  rig.service->wait_idle();
  res = c.Get("/api/v1/jobs/" + job_id, as_viewer);
  REQUIRE(res);
  const auto job = nlohmann::json::parse(res->body);
  INFO(job.dump());
  CHECK(job["state"] == "done");
  CHECK(job["outcome"] == "restored and verified");
  CHECK(git(rig.dir.path / "archive", "log -1 '--format=%(trailers)'") ==
        "Operator: maria\nReason: drift\nTicket: T-1\n\n");

  // An API backup records who asked for it.
  write_axis(rig.dir.path / "a.json", 0x11, "0010", 8);
  res = c.Post("/api/v1/drives/press3/z/backup", as_op, "", "application/json");
  REQUIRE(res);
  CHECK(res->status == 202);
  rig.service->wait_idle();
  CHECK(git(rig.dir.path / "archive", "log -1 --format=%s") ==
        "fleet backup: 1 changed, 0 unchanged, 0 new, 0 failed\n");
  CHECK(git(rig.dir.path / "archive", "log -1 '--format=%(trailers)'") == "Operator: maria\n\n");
}

TEST_CASE("serve: diff of a position between revisions and to the live drive, its HTML report",
          "[serve][plan][http][git-cli]") {
  Rig rig;
  rig.at(rig.now);
  const auto archive = rig.dir.path / "archive";
  const std::string first = git(archive, "rev-parse HEAD").substr(0, 40);
  write_axis(rig.dir.path / "b.json", 0x12, "0010", 7);
  write_axis(rig.dir.path / "a.json", 0x11, "0020", 2000);  // ignored on this line

  auto live = rig.service->diff("press3/x", "HEAD", "live");
  REQUIRE(live.ok());
  auto d = plain(*live);
  REQUIRE(d["differences"].size() == 1);
  CHECK(d["differences"][0]["upid"] == "0010");
  CHECK(d["differences"][0]["a"] == "5");
  CHECK(d["differences"][0]["b"] == "7");
  CHECK(plain(*rig.service->diff("press3/z", "HEAD", "live"))["differences"].empty());

  REQUIRE(rig.service->backup_drive("press3/x").ok());
  rig.service->wait_idle();
  auto revs = rig.service->diff("press3/x", first, "HEAD");
  REQUIRE(revs.ok());
  CHECK(plain(*revs)["differences"].size() == 1);
  CHECK(rig.service->diff("press3/x", "nosuchrev", "live").error().code == Errc::not_found);

  auto html = rig.service->report_html("press3/x", first);
  REQUIRE(html.ok());
  CHECK(html->rfind("<!DOCTYPE html>", 0) == 0);
  CHECK(html->find("press3/x.json@" + first.substr(0, 12)) != std::string::npos);

  Server server(*rig.service);
  httplib::Client c("127.0.0.1", server.port);
  auto res = c.Get("/api/v1/drives/press3/x/diff?from=" + first + "&to=live");
  REQUIRE(res);
  CHECK(res->status == 200);
  CHECK(nlohmann::json::parse(res->body)["differences"].size() == 1);
  res = c.Get("/api/v1/drives/press3/x/diff");
  REQUIRE(res);
  CHECK(res->status == 400);
  res = c.Get("/api/v1/drives/press3/x/report?rev=" + first);
  REQUIRE(res);
  CHECK(res->status == 200);
  CHECK(res->get_header_value("Content-Type") == "text/html; charset=utf-8");
  CHECK(res->body == *html);
  res = c.Get("/api/v1/drives/press9/q/report");
  REQUIRE(res);
  CHECK(res->status == 404);
}

TEST_CASE(
    "serve: a factory-fresh drive at an archived position is replaced: notified, not archived",
    "[serve][replaced][git-cli]") {
  Rig rig;
  const auto t0 = rig.now;
  rig.at(t0);
  const auto archive = rig.dir.path / "archive";
  const std::string head = git(archive, "rev-parse HEAD");
  write_fresh_axis(rig.dir.path / "a.json", 0x11);
  rig.at(t0 + 15min);  // a drift check
  auto events = rig.take_events();
  REQUIRE(events.size() == 1);
  CHECK(events[0]["event"] == "replaced");
  CHECK(events[0]["drive"] == "press3/z");
  CHECK(events[0]["on_replaced"] == "notify");
  CHECK((*rig.service->drive("press3/z"))["status"] == "replaced");

  // A backup keeps the archived file: a factory state never overwrites it.
  auto job = rig.service->backup_drive("press3/z");
  rig.service->wait_idle();
  CHECK(git(archive, "rev-parse HEAD") == head);
  CHECK((*rig.service->job(*job))["counts"]["replaced"] == 1);
  CHECK(rig.take_events().empty());  // still replaced: not notified twice
  auto plan = rig.service->plan("press3/z", "", "ops");
  REQUIRE(plan.ok());
  CHECK((*plan)["factory_fresh"] == true);

  write_axis(rig.dir.path / "a.json", 0x11);  // the old drive is back
  rig.at(t0 + 30min);
  events = rig.take_events();
  REQUIRE(events.size() == 1);
  CHECK(events[0]["event"] == "recovered");
  CHECK(events[0]["previous"] == "replaced");
}

TEST_CASE("serve: on_replaced = restore puts the archived file on a factory-fresh drive",
          "[serve][replaced][git-cli]") {
  Rig rig("", "on_replaced = \"restore\"\n");
  const auto t0 = rig.now;
  rig.at(t0);
  const auto archive = rig.dir.path / "archive";
  const std::string head = git(archive, "rev-parse HEAD").substr(0, 40);
  write_fresh_axis(rig.dir.path / "a.json", 0x11);
  rig.at(t0 + 15min);
  auto events = rig.take_events();
  REQUIRE(events.size() == 2);
  CHECK(events[0]["event"] == "replaced");
  CHECK(events[0]["on_replaced"] == "restore");
  CHECK(events[1]["event"] == "restored");
  CHECK(events[1]["drive"] == "press3/z");
  CHECK(events[1]["automatic"] == true);
  CHECK(events[1]["outcome"] == "restored and verified");
  CHECK(git(archive, "log -1 --format=%s") == "fleet restore: press3/z <- press3/z.json at " +
                                                  head.substr(0, 12) +
                                                  " (automatic: factory-fresh drive found)\n");
  CHECK(git(archive, "log -1 '--format=%(trailers)'") ==
        "Operator: lmcfg serve (automatic)\nReason: factory-fresh drive found at the "
        "position\n\n");
  CHECK((*rig.service->drive("press3/z"))["status"] == "ok");
  CHECK(rom_of(rig.dir.path / "a.json", "0010") == 5);

  // The drive matches the archive: the next drift check finds nothing.
  rig.at(t0 + 30min);
  INFO(plain(*rig.service->diff("press3/z", "HEAD", "live")).dump());
  CHECK(rig.take_events().empty());
  CHECK((*rig.service->drive("press3/z"))["status"] == "ok");
  CHECK(plain(*rig.service->diff("press3/z", "HEAD", "live"))["differences"].empty());
}

TEST_CASE("serve: the daily summary counts positions per status when a day begins",
          "[serve][summary]") {
  Rig rig;
  const auto t0 = rig.now;  // 08:00 UTC
  rig.at(t0);
  rig.at(t0 + 15h);  // 23:00: the same day
  write_axis(rig.dir.path / "b.json", 0x12, "0010", 7);
  rig.at(t0 + 15h + 15min);
  auto drift = rig.take_events();
  REQUIRE(drift.size() == 1);
  CHECK(drift[0]["event"] == "drift");
  rig.at(t0 + 16h);  // 00:00 the next day
  auto events = rig.take_events();
  REQUIRE(events.size() == 1);
  CHECK(events[0]["event"] == "summary");
  CHECK(events[0]["drive"].is_null());
  CHECK(events[0]["time"] == "2027-01-16T00:00:00Z");
  CHECK(events[0]["drives"] == 2);
  CHECK(events[0]["counts"] ==
        nlohmann::json{{"ok", 1}, {"drift", 1}, {"failed", 0}, {"replaced", 0}, {"unknown", 0}});
  rig.at(t0 + 16h + 15min);
  CHECK(rig.take_events().empty());
}

}  // namespace serve_test_serve_plan
