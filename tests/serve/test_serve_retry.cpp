// lmcfg serve's honest restores (docs/serve.md "Failed and partial restores"):
// a restore the drive stopped answering in waits as an automatic retry of its
// job, shown on the position with who asked and what the drive holds; the
// retry is a job of its own, recorded as automatic; an operator cancels it;
// a restore with values left out leaves the position in drift with them.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "files.hpp"
#include "serve/tokens.hpp"
#include "serve_rig.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace serve_test_serve_retry {

using namespace lmcfg;
using namespace lmcfg::test;
using namespace std::chrono_literals;

namespace {

nlohmann::json plain(const serve::Json& j) { return nlohmann::json::parse(j.dump()); }

// press3/z tuned behind the service's back, then a restore of the approved
// configuration that the drive stops answering in: after its reset it is
// silent (the simulator's silent_after_reset). The failed job's id.
std::string failed_restore(Rig& rig) {
  rig.at(rig.now);  // the first backup approves itself (commissioning)
  write_axis(rig.dir.path / "a.json", 0x11, "0010", 9);
  set_sim_option(rig.dir.path / "a.json", "silent_after_reset", true);
  auto planned = rig.service->plan("press3/z", "", "ops");
  REQUIRE(planned.ok());
  serve::Service::ExecuteRequest req;
  req.plan_id = plain(*planned)["plan_id"];
  req.audit = {"ops", "tuning lost", ""};
  auto id = rig.service->execute(req);
  REQUIRE(id.ok());
  rig.service->wait_idle();
  return *id;
}

constexpr const char* kSilentState =
    "written, but it has not answered since its restart: whether it holds the whole "
    "configuration is known when it answers again (a restore then reads it back)";

}  // namespace

TEST_CASE(
    "serve: a restore cut by a silent drive waits as an automatic retry of its job, "
    "which runs as a job of its own and is recorded as automatic",
    "[serve][retry][git-cli]") {
  Rig rig;
  const std::string first = failed_restore(rig);
  const auto job = plain(*rig.service->job(first));
  INFO(job.dump());
  CHECK(job["state"] == "failed");
  CHECK(job["exit_code"] == 4);
  CHECK(job["automatic"] == false);
  CHECK(job["retry_of"].is_null());
  CHECK(job["drive_state"] == kSilentState);
  CHECK(job["retry_pending"] == true);

  auto d = plain(*rig.service->drive("press3/z"));
  INFO(d.dump());
  CHECK(d["status"] == "failed");
  CHECK(d["drive_state"] == kSilentState);
  REQUIRE(d["retry"].is_object());
  CHECK(d["retry"]["of_job"] == first);
  CHECK(d["retry"]["asked_by"] == "ops");
  CHECK(d["retry"]["running"] == false);
  CHECK(d["retry"]["drive_state"] == kSilentState);
  // The list's text, written without building it, is the built list's dump
  // with the retry in it (Service::drives_text).
  CHECK(
      rig.service->drives_text() ==
      rig.service->drives().dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace));
  CHECK(d["retry"]["will"] ==
        "restore the same revision again when the drive answers, before the line's next drift "
        "check or backup (a restore run again converges)");
  rig.take_events();

  // The drive answers again, having lost what was written before its restart
  // (a save never made); the line's next drift check runs the retry first.
  write_axis(rig.dir.path / "a.json", 0x11, "0010", 9);
  rig.at(rig.now + 15min);
  // The drift check's job was made when it was due; the retry when the line's
  // worker took the check up.
  nlohmann::json retry;
  for (unsigned long n = std::stoul(first) + 1; n < std::stoul(first) + 4; ++n)
    if (auto j = rig.service->job(std::to_string(n)); j.ok() && (*j)["kind"] == "restore")
      retry = plain(*j);
  INFO(retry.dump());
  CHECK(retry["kind"] == "restore");
  CHECK(retry["scope"] == "drive press3/z");
  CHECK(retry["position"] == "press3/z");
  CHECK(retry["state"] == "done");
  CHECK(retry["automatic"] == true);
  CHECK(retry["retry_of"] == first);
  CHECK(retry["asked_by"] == "ops");
  CHECK(retry["who"] == "lmcfg serve (automatic retry)");
  CHECK(retry["retry_pending"] == false);

  // The record's subject says it was the automatic retry; the Operator is who asked.
  const auto archive = rig.dir.path / "archive";
  const std::string subject = git(archive, "log -1 --format=%s");
  CHECK(subject.find("(automatic retry of job " + first + ")") != std::string::npos);
  CHECK(git(archive, "log -1 '--format=%(trailers)'") == "Operator: ops\nReason: tuning lost\n\n");
  d = plain(*rig.service->drive("press3/z"));
  CHECK(d["status"] == "ok");
  CHECK(d["retry"].is_null());
  CHECK(d["drive_state"].is_null());
}

TEST_CASE(
    "serve: an operator cancels the automatic retry: the position says what the drive "
    "holds and nothing runs again",
    "[serve][retry]") {
  Rig rig;
  const std::string first = failed_restore(rig);
  auto cancelled = rig.service->cancel_retry("press3/z", "night-shift");
  REQUIRE(cancelled.ok());
  CHECK(plain(*cancelled) ==
        nlohmann::json::parse(R"({"drive": "press3/z", "cancelled_job": ")" + first +
                              R"(", "drive_state": ")" + kSilentState + "\"}"));
  auto d = plain(*rig.service->drive("press3/z"));
  CHECK(d["retry"].is_null());
  CHECK(d["status"] == "failed");
  CHECK(d["message"] == std::string("automatic retry cancelled by night-shift; the drive is ") +
                            kSilentState + ": plan a restore to configure it, or check the drive");
  auto events = rig.take_events();
  REQUIRE_FALSE(events.empty());
  CHECK(events.back()["event"] == "retry_cancelled");
  CHECK(events.back()["operator"] == "night-shift");

  // Nothing waits any more: a second cancel is refused, and the next check runs no restore.
  auto again = rig.service->cancel_retry("press3/z", "night-shift");
  REQUIRE_FALSE(again.ok());
  CHECK(again.error().message == "no automatic retry is waiting for drive press3/z");
  set_sim_option(rig.dir.path / "a.json", "silent_after_reset", false);
  rig.at(rig.now + 15min);
  for (unsigned long n = std::stoul(first) + 1; n < std::stoul(first) + 4; ++n)
    if (auto j = rig.service->job(std::to_string(n)); j.ok()) CHECK((*j)["kind"] == "status");
  const auto pending = rig.dir.path / "archive" / ".git" / "lmcfg-serve" / "pending";
  CHECK((!fs::exists(pending) || fs::is_empty(pending)));

  auto unknown = rig.service->cancel_retry("press9/q", "night-shift");
  REQUIRE_FALSE(unknown.ok());
  CHECK(unknown.error().message == "no drive named 'press9/q' in the inventory");
}

TEST_CASE("serve: cancelling the automatic retry over HTTP needs role operator", "[serve][retry]") {
  Rig rig;
  failed_restore(rig);
  const std::string tokens_file = (rig.dir.path / "tokens").string();
  const std::string viewer = *serve::add_token(tokens_file, "wall", serve::Role::viewer);
  const std::string op = *serve::add_token(tokens_file, "night-shift", serve::Role::operator_);
  Server server(*rig.service, *serve::load_tokens(tokens_file));
  httplib::Client c("127.0.0.1", server.port);
  const std::string path = "/api/v1/drives/press3%2Fz/retry/cancel";
  auto res =
      c.Post(path, httplib::Headers{{"Authorization", "Bearer " + viewer}}, "", "application/json");
  REQUIRE(res);
  CHECK(res->status == 403);
  res = c.Post(path, httplib::Headers{{"Authorization", "Bearer " + op}}, "", "application/json");
  REQUIRE(res);
  CHECK(res->status == 200);
  res = c.Post(path, httplib::Headers{{"Authorization", "Bearer " + op}}, "", "application/json");
  REQUIRE(res);
  CHECK(res->status == 404);
  CHECK(nlohmann::json::parse(res->body)["error"] ==
        "no automatic retry is waiting for drive press3/z");
}

TEST_CASE(
    "serve: a restore without the values the drive cannot take leaves the position in "
    "drift with each of them listed",
    "[serve][retry]") {
  Rig rig;
  rig.at(rig.now);
  // The drive at press3/z now runs a firmware without UPID 3010h, and was tuned.
  write_axis(rig.dir.path / "a.json", 0x11, "0010", 9);
  drop_sim_parameter(rig.dir.path / "a.json", "3010");
  auto planned = rig.service->plan("press3/z", "", "ops");
  REQUIRE(planned.ok());
  const auto p = plain(*planned);
  REQUIRE(p["incompatible"].size() == 1);
  serve::Service::ExecuteRequest req;
  req.plan_id = p["plan_id"];
  req.audit = {"ops", "spare with older firmware", ""};
  req.skip_incompatible = true;
  auto id = rig.service->execute(req);
  REQUIRE(id.ok());
  rig.service->wait_idle();
  const auto job = plain(*rig.service->job(*id));
  INFO(job.dump());
  CHECK(job["state"] == "done");
  CHECK(job["outcome"] == "restored except the listed values, verified");
  REQUIRE(job["skipped"].size() == 1);
  CHECK(job["skipped"][0].get<std::string>().find("3010h") != std::string::npos);
  const auto d = plain(*rig.service->drive("press3/z"));
  CHECK(d["status"] == "drift");
  CHECK(d["differences"] == 1);
  CHECK(d["differing"] == job["skipped"]);
  const std::string message = d["message"];
  CHECK(message.rfind("restored from press3/z.json@", 0) == 0);
  CHECK(message.substr(message.find(' ', 20)) == " except 1 value(s) this drive cannot take");
}

namespace {

constexpr const char* kStoppedState =
    "partially configured, and its motion control is stopped: the axis does not move until a "
    "restore completes";

// press3/z with command table entry 2 changed behind the service's back (its
// first position 80 84 1E 00 instead of 40 42 0F 00); `gone`: its flash saves
// never answered and the drive deaf for days after one, gone during "save the
// command table to flash".
void changed_table(const fs::path& state, bool gone) {
  write_axis(state, 0x11);
  auto j = nlohmann::json::parse(slurp(state));
  for (auto& e : j["command_table"]["flash"]) {
    if (e["entry"] != 2) continue;
    std::string data = e["data"];
    data.replace(data.find("40 42 0F 00 20 A1"), 11, "80 84 1E 00");
    e["data"] = data;
  }
  if (gone) {
    j["options"]["unanswered_saves"] = true;
    j["timing_us"]["flash_save"] = 1'000'000'000'000;
  }
  spit(state, j.dump(1));
}

}  // namespace

TEST_CASE(
    "serve: a drive gone during a flash save stays partially configured through the failed "
    "automatic retries, each listed and counted, until the retry completes",
    "[serve][retry][git-cli]") {
  Rig rig;
  rig.at(rig.now);  // the first backup approves itself (commissioning)
  const auto state = rig.dir.path / "a.json";
  changed_table(state, true);
  auto planned = rig.service->plan("press3/z", "", "ops");
  REQUIRE(planned.ok());
  serve::Service::ExecuteRequest req;
  req.plan_id = plain(*planned)["plan_id"];
  req.audit = {"ops", "table entry 2 lost", ""};
  auto first = rig.service->execute(req);
  REQUIRE(first.ok());
  rig.service->wait_idle();
  auto job = plain(*rig.service->job(*first));
  INFO(job.dump());
  CHECK(job["state"] == "failed");
  CHECK(job["outcome"] == "failed after writing");
  CHECK(job["drive_state"] == kStoppedState);
  CHECK(job["retry_pending"] == true);
  // The bar stops where the restore stopped, not at its end.
  CHECK(job["progress"]["done"].get<int>() < job["progress"]["total"].get<int>());
  // ... and names the step it stopped in.
  CHECK(job["progress"]["step"].get<std::string>().rfind("save the command table to flash", 0) ==
        0);

  // The drive's line cannot be opened any more (the drive is gone): each
  // automatic retry fails on the connection and learns nothing of the drive.
  fs::remove(state);
  for (int attempt = 1; attempt <= 2; ++attempt) {
    rig.at(rig.now + 15min);
    const auto d = plain(*rig.service->drive("press3/z"));
    INFO(d.dump());
    CHECK(d["status"] == "failed");
    CHECK(d["drive_state"] == kStoppedState);
    REQUIRE(d["retry"].is_object());
    CHECK(d["retry"]["drive_state"] == kStoppedState);
    CHECK(d["retry"]["of_job"] == *first);
    CHECK(d["retry"]["failed_attempts"] == attempt);
    REQUIRE(d["retry"]["failures"].size() == static_cast<std::size_t>(attempt));
    const auto& last = d["retry"]["failures"].back();
    CHECK(last["time"] == serve::iso_time(rig.now));
    CHECK(last["reason"] == d["message"]);
    CHECK(d["retry"]["next_attempt"] == serve::iso_time(rig.now + 15min));
    const auto retry = plain(*rig.service->job(last["job"].get<std::string>()));
    CHECK(retry["retry_of"] == *first);
    CHECK(retry["state"] == "failed");
    CHECK(retry["drive_state"] == kStoppedState);
    CHECK(rig.service->metrics().find(
              "lmcfg_drive_restore_retries_failed_total{drive=\"press3/z\",line=\"line1\"} " +
              std::to_string(attempt) + "\n") != std::string::npos);
  }
  {
    // The console's position page lists the failed attempts and what the drive holds.
    Server server(*rig.service);
    httplib::Client c("127.0.0.1", server.port);
    auto page = c.Get("/position?name=press3%2Fz");
    REQUIRE(page);
    CHECK(page->body.find("2 automatic attempt(s) failed so far; the next is due at " +
                          serve::iso_time(rig.now + 15min)) != std::string::npos);
    CHECK(page->body.find("id=\"retry-failures\"") != std::string::npos);
    CHECK(page->body.find("untouched") == std::string::npos);
    CHECK(page->body.find("motion control is stopped") != std::string::npos);
    auto job_page = c.Get("/job?id=" + *first + "&name=press3%2Fz");
    REQUIRE(job_page);
    CHECK(job_page->body.find(" step(s) before it stopped") != std::string::npos);
    CHECK(job_page->body.find("It stopped during: <span id=\"now\">Saving the command table") !=
          std::string::npos);
  }

  // The drive is back, its table as it was before the restore: the retry completes.
  changed_table(state, false);
  rig.at(rig.now + 15min);
  const auto d = plain(*rig.service->drive("press3/z"));
  INFO(d.dump());
  CHECK(d["status"] == "ok");
  CHECK(d["retry"].is_null());
  CHECK(d["drive_state"].is_null());
}

}  // namespace serve_test_serve_retry
