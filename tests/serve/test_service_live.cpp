// lmcfg serve's live reads (docs/serve.md "Live reads"): a diff against the
// drive and a restore plan read it on the line's worker as jobs; the request
// waits a bounded time and otherwise answers "line busy" (HTTP 503,
// Retry-After) naming the job, whose answer the same request asked again
// gets. A drive that never answers holds its line, never the other clients.
#include <catch2/catch.hpp>
#include <future>
#include <nlohmann/json.hpp>
#include <set>

#include "files.hpp"
#include "hung_line.hpp"
#include "serve_rig.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace serve_test_service_live {

using namespace lmcfg;
using namespace lmcfg::test;
using namespace std::chrono_literals;

namespace {

nlohmann::json plain(const serve::Json& j) { return nlohmann::json::parse(j.dump()); }

// Two lines: line1 the simulator's press3/z, line2 press4/q on `port2` (its
// line timeout_ms 60 s, no retries: a deaf drive holds a read for a minute).
std::string plant(const fs::path& dir, const std::string& port2) {
  return "[[line]]\nname = \"line1\"\nport = 'sim:" + (dir / "a.json").string() +
         "'\nignore = [\"0020h\"]\n[[line.drive]]\nname = \"press3/z\"\nid = 0x11\n" +
         "[[line]]\nname = \"line2\"\nport = '" + port2 +
         "'\ntimeout_ms = 60000\nretries = 0\nignore = [\"0020h\"]\n"
         "[[line.drive]]\nname = \"press4/q\"\nid = 0x11\n";
}

// The service with both positions archived (line2 on the simulator then),
// started again with line2 on `port2`; `tweak` sets its options.
void start_archived(ServiceRig& rig, const std::string& port2,
                    const std::function<void(serve::ServiceOptions&)>& tweak) {
  write_axis(rig.dir.path / "a.json", 0x11);
  write_axis(rig.dir.path / "c.json", 0x11);
  rig.start(plant(rig.dir.path, "sim:" + (rig.dir.path / "c.json").string()), tweak);
  REQUIRE(rig.service->backup_line("line1", "ops").ok());
  REQUIRE(rig.service->backup_line("line2", "ops").ok());
  rig.service->wait_idle();
  rig.service.reset();
  rig.start(plant(rig.dir.path, port2), tweak);
}

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

TEST_CASE(
    "serve: live diffs and plans against a drive that never answers are 503 line busy, and "
    "every other request answers within 1 s meanwhile",
    "[serve][live]") {
  HungLine hung;
  REQUIRE(hung.port() != 0);
  ServiceRig rig("serve-live");
  start_archived(rig, "tcp://127.0.0.1:" + std::to_string(hung.port()),
                 [](serve::ServiceOptions& o) {
                   o.exit_code = exit_code_of;
                   o.live_wait = 1500ms;  // the service's default
                 });
  Server server(*rig.service);
  const std::string diff = "/api/v1/drives/press4%2Fq/diff?from=HEAD&to=live";
  const std::string plan = "/api/v1/drives/press4%2Fq/plan";

  // 12 live diffs and 4 plans at once, as many as four HTTP workers would
  // each have held for minutes.
  std::vector<std::future<httplib::Result>> asked;
  for (int i = 0; i < 16; ++i) {
    asked.push_back(std::async(std::launch::async, [&, i] {
      httplib::Client c("127.0.0.1", server.port);
      c.set_read_timeout(30, 0);
      return i % 4 == 3 ? c.Post(plan, "{}", "application/json") : c.Get(diff);
    }));
  }
  // Meanwhile the drives, the metrics and a drive's state answer within 1 s.
  httplib::Client other("127.0.0.1", server.port);
  other.set_read_timeout(30, 0);
  double slowest = 0;
  for (int i = 0; i < 10; ++i) {
    for (const char* path : {"/api/v1/drives", "/metrics", "/api/v1/drives/press3%2Fz"}) {
      const auto t0 = std::chrono::steady_clock::now();
      auto res = other.Get(path);
      slowest = std::max(slowest, ms_since(t0));
      REQUIRE(res);
      CHECK(res->status == 200);
    }
    std::this_thread::sleep_for(50ms);
  }
  INFO("slowest other request: " << slowest << " ms");
  CHECK(slowest < 1000);

  std::set<std::string> diff_jobs;
  for (auto& f : asked) {
    auto res = f.get();
    REQUIRE(res);
    INFO(res->body);
    CHECK(res->status == 503);
    CHECK(res->get_header_value("Retry-After") == "2");
    const auto j = nlohmann::json::parse(res->body);
    const std::string message = j["error"];
    CHECK(message.find(": line line2 is busy (job ") != std::string::npos);
    if (j.contains("job")) {
      CHECK(j["job_url"] == "/api/v1/jobs/" + j["job"].get<std::string>());
      const auto job = plain(*rig.service->job(j["job"].get<std::string>()));
      CHECK(job["state"] != "done");
      if (job["kind"] == "diff") diff_jobs.insert(j["job"].get<std::string>());
    }
  }
  // The diffs of one position share one read of the drive.
  CHECK(diff_jobs.size() == 1);

  // The drive's line comes back refusing connections: the read in progress
  // ends, and the same diff asked again answers with its failure, not busy.
  hung.release();
  rig.service->wait_idle();
  const auto job = plain(*rig.service->job(*diff_jobs.begin()));
  INFO(job.dump());
  CHECK(job["kind"] == "diff");
  CHECK(job["state"] == "failed");
  CHECK(job["result"].is_null());
  httplib::Client c("127.0.0.1", server.port);
  auto res = c.Get(diff);
  REQUIRE(res);
  CHECK(res->status != 503);
  CHECK(nlohmann::json::parse(res->body)["error"] == job["message"]);
}

TEST_CASE(
    "serve: a live read that ends after its request stopped waiting is the answer of the "
    "same request asked again, once",
    "[serve][live]") {
  ServiceRig rig("serve-live");
  write_axis(rig.dir.path / "c.json", 0x11);
  start_archived(rig, "sim:" + (rig.dir.path / "c.json").string(), [](serve::ServiceOptions& o) {
    o.exit_code = exit_code_of;
    o.live_waiters = 0;  // no request waits: each answer comes from its job
  });
  write_axis(rig.dir.path / "a.json", 0x11, "0010", 9);  // tuned behind the service's back

  auto first = rig.service->diff("press3/z", "HEAD", "live");
  REQUIRE_FALSE(first.ok());
  const auto busy = serve::line_busy(first.error());
  REQUIRE(busy);
  CHECK(first.error().message ==
        "drive press3/z: line line1 is busy (job " + busy->job +
            " reads the drive after the work queued before it, or the drive is slow to "
            "answer): ask again in 2 s, or see GET /api/v1/jobs/" +
            busy->job + " for its answer");
  rig.service->wait_idle();
  const auto job = plain(*rig.service->job(busy->job));
  INFO(job.dump());
  CHECK(job["kind"] == "diff");
  CHECK(job["state"] == "done");
  CHECK(job["position"] == "press3/z");
  REQUIRE(job["result"].is_object());
  auto again = rig.service->diff("press3/z", "HEAD", "live");
  REQUIRE(again.ok());
  CHECK(plain(*again) == job["result"]);
  CHECK(plain(*again)["differences"][0]["upid"] == "0010");
  // Given once: the next diff reads the drive again, as a new job.
  auto third = rig.service->diff("press3/z", "HEAD", "live");
  REQUIRE_FALSE(third.ok());
  REQUIRE(serve::line_busy(third.error()));
  CHECK(serve::line_busy(third.error())->job == std::to_string(std::stoul(busy->job) + 1));
  rig.service->wait_idle();

  // A plan: the same person asking again gets the plan the job made, which executes.
  auto planned = rig.service->plan("press3/z", "", "ops");
  REQUIRE_FALSE(planned.ok());
  const std::string plan_job = serve::line_busy(planned.error())->job;
  rig.service->wait_idle();
  auto by_other = rig.service->plan("press3/z", "", "night-shift");
  REQUIRE_FALSE(by_other.ok());
  CHECK(serve::line_busy(by_other.error())->job != plan_job);
  planned = rig.service->plan("press3/z", "", "ops");
  REQUIRE(planned.ok());
  CHECK(plain(*planned) == plain(*rig.service->job(plan_job))["result"]);
  serve::Service::ExecuteRequest req;
  req.plan_id = plain(*planned)["plan_id"];
  req.audit = {"ops", "tuning lost", ""};
  auto restore = rig.service->execute(req);
  REQUIRE(restore.ok());
  rig.service->wait_idle();
  CHECK(plain(*rig.service->job(*restore))["state"] == "done");
}

TEST_CASE("serve: a line takes a bounded number of live reads, more are refused as busy",
          "[serve][live]") {
  HungLine hung;
  REQUIRE(hung.port() != 0);
  ServiceRig rig("serve-live");
  start_archived(rig, "tcp://127.0.0.1:" + std::to_string(hung.port()),
                 [](serve::ServiceOptions& o) {
                   o.exit_code = exit_code_of;
                   o.live_waiters = 0;
                   o.live_queued = 2;
                 });
  // A diff holds the line's worker: the drive does not answer.
  auto d = rig.service->diff("press4/q", "HEAD", "live");
  REQUIRE_FALSE(d.ok());
  const std::string reading = serve::line_busy(d.error())->job;
  for (int i = 0; i < 500 && (*rig.service->job(reading))["state"] != "running"; ++i)
    std::this_thread::sleep_for(10ms);
  REQUIRE((*rig.service->job(reading))["state"] == "running");
  // Two plans wait behind it; a third is refused without a job.
  for (const char* who : {"a", "b"}) {
    auto p = rig.service->plan("press4/q", "", who);
    REQUIRE_FALSE(p.ok());
    REQUIRE(serve::line_busy(p.error()));
    CHECK_FALSE(serve::line_busy(p.error())->job.empty());
  }
  auto refused = rig.service->plan("press4/q", "", "c");
  REQUIRE_FALSE(refused.ok());
  REQUIRE(serve::line_busy(refused.error()));
  CHECK(serve::line_busy(refused.error())->job.empty());
  CHECK(refused.error().message ==
        "line line2 is busy: 2 live reads wait for it already; ask again in 2 s");
  // The same plan asked again joins its job rather than being refused.
  auto joined = rig.service->plan("press4/q", "", "a");
  REQUIRE_FALSE(joined.ok());
  CHECK_FALSE(serve::line_busy(joined.error())->job.empty());
  hung.release();
  rig.service->wait_idle();
}

TEST_CASE(
    "serve: while a line's worker is stuck in a drive read, every read of the service's state "
    "answers at once (no lock is held across the read)",
    "[serve][live]") {
  HungLine hung;
  REQUIRE(hung.port() != 0);
  ServiceRig rig("serve-live");
  start_archived(rig, "tcp://127.0.0.1:" + std::to_string(hung.port()),
                 [](serve::ServiceOptions& o) { o.exit_code = exit_code_of; });
  auto& s = *rig.service;
  // A backup of the line whose drive never answers: its worker is in the read
  // (the job runs, the drive's port has its connection) for a minute.
  auto stuck = s.backup_line("line2", "ops");
  REQUIRE(stuck.ok());
  for (int i = 0; i < 500 && (hung.connections() == 0 || (*s.job(*stuck))["state"] != "running");
       ++i)
    std::this_thread::sleep_for(10ms);
  REQUIRE(hung.connections() > 0);
  REQUIRE((*s.job(*stuck))["state"] == "running");

  // Each of the service's parts, read and written meanwhile: the positions
  // (the stuck one too), the job table, the metrics, the plans, the schedule
  // and the other line's worker.
  double slowest = 0;
  std::string slowest_call;
  auto timed = [&](const std::string& what, const std::function<void()>& call) {
    const auto t0 = std::chrono::steady_clock::now();
    call();
    if (ms_since(t0) > slowest) {
      slowest = ms_since(t0);
      slowest_call = what;
    }
  };
  timed("drives", [&] { CHECK(s.drives().size() == 2); });
  timed("drive", [&] { CHECK((*s.drive("press4/q"))["name"] == "press4/q"); });
  timed("job", [&] { CHECK((*s.job(*stuck))["state"] == "running"); });
  timed("metrics", [&] {
    CHECK(s.metrics().find("lmcfg_line_runs_total{line=\"line2\"}") != std::string::npos);
  });
  timed("history", [&] { CHECK(s.history("press4/q").ok()); });
  timed("execute", [&] {
    serve::Service::ExecuteRequest req;
    req.plan_id = "0123";
    CHECK(s.execute(req).error().message == "no plan '0123'");
  });
  timed("tick", [&] { s.tick(serve::Clock::now()); });
  INFO("slowest: " << slowest_call << ", " << slowest << " ms");
  CHECK(slowest < 1000);
  // The other line's worker goes on: a plan and a backup of line1 end while
  // line2's read is still stuck.
  auto planned = s.plan("press3/z", "", "ops");
  for (int i = 0; i < 20 && !planned.ok() && serve::line_busy(planned.error()); ++i)
    planned = s.plan("press3/z", "", "ops");  // a slow machine: the same plan's answer
  CHECK(planned.ok());
  auto other = s.backup_line("line1", "ops");
  REQUIRE(other.ok());
  for (int i = 0; i < 2000 && (*s.job(*other))["state"] != "done"; ++i)
    std::this_thread::sleep_for(10ms);
  CHECK((*s.job(*other))["state"] == "done");
  CHECK((*s.job(*stuck))["state"] == "running");
  hung.release();
  s.wait_idle();
  CHECK((*s.job(*stuck))["state"] == "done");
  CHECK((*s.job(*stuck))["outcome"] == "some drives failed");
}

}  // namespace serve_test_service_live
