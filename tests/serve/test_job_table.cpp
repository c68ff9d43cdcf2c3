// The service's job table (lib/serve/job_table.cpp): numbers that outlive a
// restart (jobs.json reserved in blocks), the newest 1000 kept and the words
// for a job that is not, one job shared by the requests asking the same
// question, the bounded wait for a job, and one unfinished restore per position.
#include <catch2/catch.hpp>
#include <future>
#include <thread>

#include "files.hpp"
#include "serve/job_table.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace serve_test_job_table {

using namespace lmcfg;
using namespace lmcfg::serve;
using namespace lmcfg::serve::detail;
using namespace std::chrono_literals;

namespace {

struct Table {
  test::ScratchDir dir{"job-table"};
  std::vector<std::string> logged;
  TimePoint now = TimePoint(std::chrono::seconds(1'800'000'000));
  JobTable jobs{dir.path, [this] { return now; },
                [this](const std::string& s) { logged.push_back(s); }};
};

std::string error_of(const Result<JobTable::Shown>& r) { return r.ok() ? "" : r.error().message; }

}  // namespace

TEST_CASE("serve job table: numbers go on after a restart, reserved 100 at a time",
          "[serve][jobs]") {
  test::ScratchDir dir("job-table-numbers");
  auto clock = [] { return TimePoint(std::chrono::seconds(1'800'000'000)); };
  auto quiet = [](const std::string&) {};
  {
    JobTable jobs(dir.path, clock, quiet);
    jobs.load();
    CHECK(jobs.add(Kind::backup, "line l1")->id == "1");
    CHECK(jobs.add(Kind::status, "scheduled")->id == "2");
    const auto file = nlohmann::json::parse(test::slurp(dir.path / "jobs.json"));
    CHECK(file["format"] == "lmcfg-serve-jobs");
    CHECK(file["next"] == 101);  // the block 1..100 is this run's
  }
  JobTable again(dir.path, clock, quiet);
  again.load();
  CHECK(again.add(Kind::backup, "line l1")->id == "101");
  const auto gone = again.show("2");
  REQUIRE_FALSE(gone.ok());
  CHECK(gone.error().code == Errc::not_found);
  CHECK(error_of(gone) ==
        "job 2 ended before the service restarted: its record is not kept across a restart; "
        "the position's history lists what it did");
  CHECK(error_of(again.show("102")) == "no job 102");
  CHECK(error_of(again.show("x1")) == "no job x1");
  CHECK(error_of(again.show("")) == "no job ");
}

TEST_CASE("serve job table: a jobs.json of something else is logged and numbering starts at 1",
          "[serve][jobs]") {
  Table t;
  test::spit(t.dir.path / "jobs.json", "{\"next\": \"many\"}");
  t.jobs.load();
  REQUIRE(t.logged.size() == 1);
  CHECK(t.logged[0] == "jobs: " + (t.dir.path / "jobs.json").string() +
                           " is not a job numbers file of lmcfg serve; jobs start at 1");
  CHECK(t.jobs.add(Kind::backup, "line l1")->id == "1");
}

TEST_CASE("serve job table: the newest 1000 jobs are kept", "[serve][jobs]") {
  Table t;
  for (int i = 0; i < 1001; ++i) t.jobs.add(Kind::status, "scheduled");
  CHECK(error_of(t.jobs.show("1")) ==
        "job 1 is no longer kept (the service keeps its newest 1000 jobs); the position's "
        "history lists what it did");
  auto kept = t.jobs.show("2");
  REQUIRE(kept.ok());
  CHECK(kept->json["id"] == "2");
  CHECK(kept->json["state"] == "queued");
  CHECK(kept->json["kind"] == "status");
}

TEST_CASE("serve job table: a job's fields are set under the lock and shown as they are",
          "[serve][jobs]") {
  Table t;
  auto job = t.jobs.add(Kind::restore, "drive press/a", "press/a", [](Job& j) {
    j.who = "ops";
    j.total = 1;
  });
  auto shown = t.jobs.show(job->id);
  REQUIRE(shown.ok());
  CHECK(shown->kind == Kind::restore);
  CHECK(shown->position == "press/a");
  CHECK_FALSE(shown->failed);
  CHECK(shown->json["who"] == "ops");
  CHECK(shown->json["state"] == "queued");
  CHECK(shown->json["created"] == "2027-01-15T08:00:00Z");
  t.jobs.update(*job, [&](Job& j) {
    j.started = true;
    j.step_done = 2;
    j.step_total = 5;
    j.step = "writing 0010h";
  });
  shown = t.jobs.show(job->id);
  CHECK(shown->json["state"] == "running");
  CHECK(shown->json["progress"] == Json{{"done", 2}, {"total", 5}, {"step", "writing 0010h"}});
  CHECK(t.jobs.running_restore("press/a") == job->id);
  CHECK(t.jobs.running_restore("press/b").empty());
  t.jobs.update(*job, [&](Job& j) {
    j.finished = t.now;
    j.failed_job = true;
    j.outcome = "failed";
  });
  shown = t.jobs.show(job->id);
  CHECK(shown->failed);
  CHECK(shown->json["state"] == "failed");
  CHECK(t.jobs.running_restore("press/a").empty());
}

TEST_CASE("serve job table: one unfinished restore per position, the refusal names it",
          "[serve][jobs]") {
  Table t;
  auto first = t.jobs.add_restore("press/a", [](Job& j) { j.who = "day-shift"; });
  REQUIRE(first.ok());
  auto second = t.jobs.add_restore("press/a", [](Job& j) { j.who = "night-shift"; });
  REQUIRE_FALSE(second.ok());
  CHECK(second.error().code == Errc::plan_refused);
  CHECK(second.error().message ==
        "another restore of drive press/a is waiting for the line as job 1, asked for by "
        "day-shift at 2027-01-15T08:00:00Z; nothing written: wait for it to end (GET "
        "/api/v1/jobs/1), then plan again");
  CHECK(t.jobs.unfinished_restore("press/a") == second.error().message);
  CHECK_FALSE(t.jobs.unfinished_restore("press/b"));
  CHECK(t.jobs.add_restore("press/b", {}).ok());
  t.jobs.update(**first, [&](Job& j) { j.finished = t.now; });
  CHECK(t.jobs.add_restore("press/a", {}).ok());
}

TEST_CASE("serve job table: requests asking the same question share one job", "[serve][jobs]") {
  Table t;
  int admitted = 0;
  auto admit = [&]() -> Result<void> {
    ++admitted;
    return {};
  };
  auto unfinished = [](const Job& j) { return !j.finished; };
  auto init = [](Job& j) { j.key = "diff\npress/a"; };
  auto a = t.jobs.share("diff\npress/a", unfinished, admit, Kind::diff, "press/a", init);
  REQUIRE(a.ok());
  CHECK(a->made);
  CHECK(a->job->scope == "drive press/a");
  auto b = t.jobs.share("diff\npress/a", unfinished, admit, Kind::diff, "press/a", init);
  REQUIRE(b.ok());
  CHECK_FALSE(b->made);
  CHECK(b->job == a->job);
  CHECK(admitted == 1);
  // Finished: the next request gets a job of its own, when admitted.
  t.jobs.update(*a->job, [&](Job& j) { j.finished = t.now; });
  auto refused = t.jobs.share(
      "diff\npress/a", unfinished, [] { return Result<void>(Error(Errc::io_error, "full")); },
      Kind::diff, "press/a", init);
  REQUIRE_FALSE(refused.ok());
  CHECK(refused.error().message == "full");
  auto c = t.jobs.share("diff\npress/a", unfinished, admit, Kind::diff, "press/a", init);
  REQUIRE(c.ok());
  CHECK(c->made);
  CHECK(c->job->id == "2");
}

TEST_CASE("serve job table: a wait for a job is bounded in time and in waiters", "[serve][jobs]") {
  Table t;
  auto job = t.jobs.add(Kind::diff, "drive press/a", "press/a");
  // No waiter allowed: the answer at once.
  CHECK_FALSE(t.jobs.wait_finished(*job, 10s, 0, false));
  // Not finished within the wait.
  const auto t0 = std::chrono::steady_clock::now();
  CHECK_FALSE(t.jobs.wait_finished(*job, 50ms, 1, false));
  CHECK(std::chrono::steady_clock::now() - t0 >= 50ms);
  // Finished meanwhile by another thread: the waiter wakes, the job is handed.
  auto done = std::async(std::launch::async, [&] {
    std::this_thread::sleep_for(50ms);
    t.jobs.update(*job, [&](Job& j) { j.finished = t.now; });
  });
  const auto t1 = std::chrono::steady_clock::now();
  CHECK(t.jobs.wait_finished(*job, 10s, 1, false));
  CHECK(std::chrono::steady_clock::now() - t1 < 5s);
  done.get();
  CHECK(t.jobs.read(*job, [](const Job& j) { return j.handed; }));
  // A stop wakes the waiters of a job that never ends.
  auto never = t.jobs.add(Kind::plan, "drive press/a", "press/a");
  auto waiting =
      std::async(std::launch::async, [&] { return t.jobs.wait_finished(*never, 30s, 2, false); });
  std::this_thread::sleep_for(50ms);
  const auto t2 = std::chrono::steady_clock::now();
  t.jobs.stop();
  CHECK_FALSE(waiting.get());
  CHECK(std::chrono::steady_clock::now() - t2 < 5s);
}

TEST_CASE("serve job table: a job just made is its maker's answer only when it may wait",
          "[serve][jobs]") {
  Table t;
  auto job = t.jobs.add(Kind::diff, "drive press/a", "press/a");
  t.jobs.update(*job, [&](Job& j) { j.finished = t.now; });  // a read faster than the request
  // The maker may not wait (no waiter allowed): "busy", the answer kept.
  CHECK_FALSE(t.jobs.wait_finished(*job, 10s, 0, true));
  CHECK_FALSE(t.jobs.read(*job, [](const Job& j) { return j.handed; }));
  // The same request asked again (not the maker) takes it.
  CHECK(t.jobs.wait_finished(*job, 10s, 0, false));
  CHECK(t.jobs.read(*job, [](const Job& j) { return j.handed; }));
  // A maker that may wait has it at once.
  auto fast = t.jobs.add(Kind::plan, "drive press/a", "press/a");
  t.jobs.update(*fast, [&](Job& j) { j.finished = t.now; });
  CHECK(t.jobs.wait_finished(*fast, 10s, 1, true));
}

TEST_CASE("serve job table: job_json of a backup, a live read and a restore", "[serve][jobs]") {
  Job b;
  b.id = "7";
  b.kind = Kind::backup;
  b.scope = "line l1";
  b.total = 2;
  b.done = 2;
  b.failed = 1;
  b.commits = {"abc"};
  b.finished = TimePoint(std::chrono::seconds(0));
  auto j = job_json(b);
  CHECK(j["state"] == "done");
  CHECK(j["outcome"] == "some drives failed");
  CHECK(j["commit"] == "abc");
  CHECK(j["position"].is_null());
  Job d;
  d.kind = Kind::diff;
  d.result = Json{{"differences", Json::array()}};
  CHECK(job_json(d)["result"].is_null());  // not finished: no answer yet
  d.finished = TimePoint(std::chrono::seconds(0));
  CHECK(job_json(d)["result"] == d.result);
  Job r;
  r.kind = Kind::restore;
  r.who = "lmcfg serve (automatic)";
  CHECK(job_json(r)["automatic"] == true);
  CHECK_FALSE(job_json(r).contains("retry_pending"));  // the state store's to add
}

}  // namespace serve_test_job_table
