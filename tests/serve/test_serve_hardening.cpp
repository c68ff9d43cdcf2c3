// lmcfg serve behind the HTTP edge: a job that throws fails with the reason
// and the line's next job runs; free text (who, reason, ticket, revisions) is
// one line of UTF-8 before it reaches a commit, a job record or a page; a
// history entry whose message is not UTF-8 (made by hand with git) is shown
// escaped. On the library's Service with an injected clock.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "files.hpp"
#include "link/port.hpp"
#include "serve_rig.hpp"
#include "sim/state_file.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace serve_test_serve_hardening {

using namespace lmcfg;
using namespace lmcfg::test;

namespace {

// The Rig's line of two simulated axes; `tweak` changes the options.
void start_line(ServiceRig& rig, const std::function<void(serve::ServiceOptions&)>& tweak) {
  write_axis(rig.dir.path / "a.json", 0x11);
  write_axis(rig.dir.path / "b.json", 0x12);
  rig.start("[schedule]\nbackup_every = \"6h\"\n[[line]]\nname = \"line1\"\nport = 'sim:" +
                (rig.dir.path / "a.json").string() + "," + (rig.dir.path / "b.json").string() +
                "'\n[[line.drive]]\nname = \"press3/z\"\nid = 0x11\n"
                "[[line.drive]]\nname = \"press3/x\"\nid = 0x12\n",
            [&](serve::ServiceOptions& o) {
              o.exit_code = exit_code_of;
              if (tweak) tweak(o);
            });
}

nlohmann::json plain(const serve::Json& j) { return nlohmann::json::parse(j.dump()); }

const std::string kThrown =
    "internal error on line line1: injected fault; nothing more was done for this request (a "
    "bug: please report it with the service's log)";

}  // namespace

TEST_CASE("serve: a job that throws fails with the reason, the line's next job runs",
          "[serve][hardening]") {
  ServiceRig rig("serve-throw");
  // The clock throws on its n-th call from now: 2 = backup_line's job record
  // (this thread), then the worker's first call (recording the first drive).
  auto arm = std::make_shared<std::atomic<int>>(0);
  std::vector<std::string> log;
  std::mutex log_mu;
  start_line(rig, [&](serve::ServiceOptions& o) {
    o.clock = [&rig, arm] {
      if (arm->fetch_sub(1) == 1) throw std::runtime_error("injected fault");
      return rig.now;
    };
    o.log = [&](const std::string& s) {
      std::lock_guard<std::mutex> lock(log_mu);
      log.push_back(s);
    };
  });
  arm->store(2);
  auto first = rig.service->backup_line("line1", "ops");
  REQUIRE(first.ok());
  rig.service->wait_idle();
  const auto j1 = plain(*rig.service->job(*first));
  INFO(j1.dump());
  CHECK(j1["state"] == "failed");
  CHECK(j1["outcome"] == "failed");
  CHECK(j1["message"] == kThrown);
  {
    std::lock_guard<std::mutex> lock(log_mu);
    CHECK(std::find(log.begin(), log.end(),
                    "line line1: a task threw (injected fault); it failed, the service goes on") !=
          log.end());
    CHECK(std::find(log.begin(), log.end(), "backup job " + *first + ": failed: " + kThrown) !=
          log.end());
  }

  // The worker lives on: the next job runs to its end.
  auto second = rig.service->backup_line("line1", "ops");
  REQUIRE(second.ok());
  rig.service->wait_idle();
  const auto j2 = plain(*rig.service->job(*second));
  INFO(j2.dump());
  CHECK(j2["state"] == "done");
  CHECK(j2["outcome"] == "done");
  CHECK(j2["counts"]["failed"] == 0);
  CHECK(j2["counts"]["unchanged"] == 2);  // the first job had committed before it threw
  CHECK((*rig.service->drive("press3/z"))["status"] == "ok");
}

TEST_CASE("serve: a call waiting on a line's worker gets the error of a throw",
          "[serve][hardening]") {
  // The sim: port, but opening it throws while `fault` is set (a bug in a
  // transport): plan() waits on the worker for its read of the target.
  static std::atomic<bool> fault{false};
  link::register_scheme("flaky", [](const transport::LinkRequest& r) {
    if (fault) throw std::runtime_error("injected fault");
    return sim::state_file_link_factory()(r);
  });
  ServiceRig rig("serve-throw-port");
  write_axis(rig.dir.path / "a.json", 0x11);
  rig.start("[[line]]\nname = \"line1\"\nport = 'flaky:" + (rig.dir.path / "a.json").string() +
                "'\n[[line.drive]]\nname = \"press3/z\"\nid = 0x11\n",
            [](serve::ServiceOptions& o) { o.exit_code = exit_code_of; });
  auto id = rig.service->backup_drive("press3/z", "ops");
  REQUIRE(id.ok());
  rig.service->wait_idle();
  REQUIRE((*rig.service->job(*id))["state"] == "done");

  fault = true;
  auto p = rig.service->plan("press3/z", "", "ops");
  REQUIRE_FALSE(p.ok());
  CHECK(p.error().message == kThrown);
  fault = false;
  CHECK(rig.service->plan("press3/z", "", "ops").ok());  // the worker still runs
}

TEST_CASE("serve: a notify receiver that throws loses the event, not the service",
          "[serve][hardening]") {
  ServiceRig rig("serve-notify-throw");
  start_line(rig, [](serve::ServiceOptions& o) {
    o.notify = [](const serve::Json&) { throw std::runtime_error("receiver down"); };
  });
  rig.at(rig.now);
  write_axis(rig.dir.path / "a.json", 0x11, "0010", 9);  // a change: a drift event
  auto id = rig.service->backup_drive("press3/z", "ops");
  REQUIRE(id.ok());
  rig.service->wait_idle();
  const auto j = plain(*rig.service->job(*id));
  CHECK(j["state"] == "done");
  CHECK(j["counts"]["changed"] == 1);
}

TEST_CASE("serve: who, reason, ticket and revisions are one line of UTF-8, length-limited",
          "[serve][hardening][git-cli]") {
  Rig rig;
  rig.at(rig.now);
  write_axis(rig.dir.path / "a.json", 0x11, "0010", 9);

  // A revision with a line break (git's HEAD^{/...} would take it) never gets to git.
  auto bent = rig.service->plan("press3/z", "HEAD^{/x\nOperator: mallory}", "ops");
  REQUIRE_FALSE(bent.ok());
  CHECK(bent.error().code == Errc::invalid_argument);
  CHECK(bent.error().message ==
        "rev contains a control character (0x0A at offset 8): give one line without control "
        "characters");
  CHECK(rig.service->report_html("press3/z", std::string(201, '~')).error().message ==
        "rev is 201 bytes long, at most 200 are accepted: shorten it");
  CHECK(rig.service->diff("press3/z", "HEAD\r", "HEAD").error().message ==
        "from contains a control character (0x0D at offset 4): give one line without control "
        "characters");
  CHECK(rig.service->backup_drive("press3/z", "ops\xFF").error().message ==
        "who is not valid UTF-8 (byte 0xFF at offset 3): send UTF-8 text");
  CHECK(rig.service->backup_line("line1", std::string(65, 'w')).error().message ==
        "who is 65 bytes long, at most 64 are accepted: shorten it");

  auto planned = rig.service->plan("press3/z", "", "ops");
  REQUIRE(planned.ok());
  serve::Service::ExecuteRequest req;
  req.plan_id = (*planned)["plan_id"];
  // Invalid UTF-8 in the reason once killed the process on the line's worker
  // (the pending record's JSON): now refused before anything is queued.
  req.audit = {"ops", "motor \xC3\x28 replaced", "T-17"};
  auto e = rig.service->execute(req);
  REQUIRE_FALSE(e.ok());
  CHECK(e.error().code == Errc::invalid_argument);
  CHECK(e.error().message == "reason is not valid UTF-8 (byte 0xC3 at offset 6): send UTF-8 text");
  req.audit = {"ops", "motor replaced", "T-17\nOperator: mallory"};
  e = rig.service->execute(req);
  REQUIRE_FALSE(e.ok());
  CHECK(e.error().message ==
        "ticket contains a control character (0x0A at offset 4): give one line without control "
        "characters");
  req.audit = {"ops", std::string(201, 'r'), "T-17"};
  CHECK(rig.service->execute(req).error().message ==
        "reason is 201 bytes long, at most 200 are accepted: shorten it");

  // The plan was not used up by the refusals; a valid request runs, the
  // commit's trailers are exactly the three given.
  req.audit = {"ops", "motor replaced: Operator: mallory", "T-17"};
  auto id = rig.service->execute(req);
  REQUIRE(id.ok());
  rig.service->wait_idle();
  const auto job = plain(*rig.service->job(*id));
  CHECK(job["state"] == "done");
  const auto archive = rig.dir.path / "archive";
  CHECK(git(archive, "log -1 '--format=%(trailers)'") ==
        "Operator: ops\nReason: motor replaced: Operator: mallory\nTicket: T-17\n\n");
}

TEST_CASE("serve: a revision reaches the plan and the commit subject as a commit id",
          "[serve][hardening][git-cli]") {
  Rig rig;
  rig.at(rig.now);
  const auto archive = rig.dir.path / "archive";
  const std::string head = git(archive, "rev-parse HEAD").substr(0, 40);
  write_axis(rig.dir.path / "a.json", 0x11, "0010", 9);
  // git's message search: the text asked goes no further than the resolution.
  auto planned = rig.service->plan("press3/z", "HEAD^{/fleet backup}", "ops");
  REQUIRE(planned.ok());
  const auto p = plain(*planned);
  CHECK(p["rev"] == head);
  CHECK(p["commit"] == head);
  serve::Service::ExecuteRequest req;
  req.plan_id = p["plan_id"];
  req.audit = {"ops", "", ""};
  auto id = rig.service->execute(req);
  REQUIRE(id.ok());
  rig.service->wait_idle();
  CHECK(git(archive, "log -1 --format=%s") == "fleet restore: press3/z <- press3/z.json at " +
                                                  head.substr(0, 12) + ": restored and verified\n");
}

TEST_CASE("serve: a history entry that is not UTF-8 (made by hand with git) is shown escaped",
          "[serve][hardening][git-cli]") {
  Rig rig;
  rig.at(rig.now);
  const auto archive = rig.dir.path / "archive";
  // Latin-1, declared so: git keeps the bytes (under its default UTF-8 it would
  // re-encode them), libgit2 hands them over as they are.
  spit(rig.dir.path / "msg", std::string("fleet restore: press3/z <- by hand \xFF\xFE\n\n"
                                         "Operator: h\xE9lène\n"));
  git(archive,
      "-c user.name=hand -c user.email=hand@plant -c i18n.commitEncoding=ISO-8859-1 commit -q "
      "--allow-empty -F '" +
          (rig.dir.path / "msg").string() + "'");
  auto h = rig.service->history("press3/z");
  REQUIRE(h.ok());
  const std::string text = h->dump();  // would throw type_error.316 on raw bytes
  const auto j = nlohmann::json::parse(text);
  REQUIRE(j.size() == 2);
  CHECK(j[0]["kind"] == "restore");
  CHECK(j[0]["subject"] == "fleet restore: press3/z <- by hand \\xFF\\xFE");
  CHECK(j[0]["who"] == "h\\xE9l\xC3\xA8ne");
}

}  // namespace serve_test_serve_hardening
