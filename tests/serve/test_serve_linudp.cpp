// lmcfg serve over LinUDP: two inventory lines whose ports are
// linudp://127.0.0.1:PORT (one drive each, named and labelled, no id:
// LinUDP V2 §3.2, a drive is reached by its address), each served by
// `lmcfg sim --linudp --udp` in its own process. The service's API runs the
// backups of both lines in parallel, finds a change made behind its back
// (drift), restores the archived file through plan and execute, and finds the
// drive back at its approved configuration.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "e2e_support.hpp"
#include "files.hpp"
#include "serve_rig.hpp"
#include "subprocess.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace serve_test_serve_linudp {

using namespace lmcfg;
using namespace lmcfg::test;
using namespace std::chrono_literals;

namespace {

struct UdpSim {
  std::unique_ptr<test::Child> child;
  std::string url;
  explicit UdpSim(const fs::path& state) {
    child = std::make_unique<test::Child>(
        std::vector<std::string>{LMCFG_TOOL_PATH, "sim", "--linudp", "--udp", "127.0.0.1:0",
                                 "--state", state.string(), "--fast"});
    const std::string port = child->read_line();
    (void)child->read_line();
    url = "linudp://127.0.0.1:" + port;
  }
};

nlohmann::json plain(const serve::Json& j) { return nlohmann::json::parse(j.dump()); }

}  // namespace

TEST_CASE("serve over LinUDP: backup, drift and restore through the API, two lines in parallel",
          "[serve][linudp]") {
  ServiceRig rig("serve-linudp");
  write_axis(rig.dir.path / "a.json", 0x11);
  write_axis(rig.dir.path / "b.json", 0x11);
  UdpSim a(rig.dir.path / "a.json");
  UdpSim b(rig.dir.path / "b.json");
  REQUIRE(a.url.size() > std::string("linudp://127.0.0.1:").size());
  rig.start(
      "[schedule]\nbackup_every = \"6h\"\nstatus_every = \"15m\"\n"
      "[[line]]\nname = \"cell4\"\nport = \"" +
          a.url +
          "\"\n"
          "[[line.drive]]\nname = \"cell4/gripper\"\nlabels = { machine = \"cell4\" }\n"
          "[[line]]\nname = \"cell5\"\nport = \"" +
          b.url +
          "\"\n"
          "[[line.drive]]\nname = \"cell5/gripper\"\nlabels = { machine = \"cell5\" }\n",
      [](serve::ServiceOptions& o) { o.exit_code = exit_code_of; });

  const auto t0 = rig.now;
  rig.at(t0);  // both lines backed up (each on its own worker), then a drift check
  CHECK(rig.take_events().empty());
  for (const char* name : {"cell4/gripper", "cell5/gripper"}) {
    auto d = rig.service->drive(name);
    REQUIRE(d.ok());
    INFO(plain(*d).dump());
    CHECK((*d)["status"] == "ok");
    CHECK((*d)["last_backup"] == "2027-01-15T08:00:00Z");
  }
  const auto archive = rig.dir.path / "archive";
  const std::string head = git(archive, "log -1 --format=%H -- cell4/gripper.json").substr(0, 40);
  auto file = nlohmann::json::parse(slurp(archive / "cell4/gripper.json"));
  CHECK(file["curves"].size() == 2);

  // Behind the service's back, over LinUDP: a tuned parameter on cell4's drive.
  auto set = run_tool_in(rig.dir.path, "set 0010 9 --rom --yes --quiet --port " + a.url);
  INFO(set.err);
  REQUIRE(set.exit_code == 0);
  rig.at(t0 + 15min);
  auto events = rig.take_events();
  INFO(nlohmann::json(events).dump());
  REQUIRE(events.size() == 1);
  CHECK(events[0]["event"] == "drift");
  CHECK(events[0]["drive"] == "cell4/gripper");
  CHECK(events[0]["line"] == "cell4");
  REQUIRE(events[0]["upids"].size() == 1);
  CHECK(events[0]["upids"][0]["upid"] == "0010h");
  // Shown with their hex: LinUDP cannot report a type (LinUDP V2 p14) and
  // this service has no UPID database that knows 0010h.
  CHECK(events[0]["upids"][0]["archived"] == "5 (0005h)");
  CHECK(events[0]["upids"][0]["live"] == "9 (0009h)");
  CHECK((*rig.service->drive("cell5/gripper"))["status"] == "ok");

  // The restore through the API: plan, then execute.
  auto planned = rig.service->plan("cell4/gripper", "", "ops");
  REQUIRE(planned.ok());
  const auto p = plain(*planned);
  INFO(p.dump());
  CHECK(p["line"] == "cell4");
  CHECK(p["commit"] == head);
  CHECK(p["problems"].empty());
  serve::Service::ExecuteRequest req;
  req.plan_id = p["plan_id"];
  req.audit = {"ops", "tuning lost", "CHG-1"};
  auto id = rig.service->execute(req);
  REQUIRE(id.ok());
  // Meanwhile, on the other line's worker: a backup of cell5.
  auto other = rig.service->backup_line("cell5");
  REQUIRE(other.ok());
  rig.service->wait_idle();
  CHECK((*rig.service->job(*other))["state"] == "done");
  const auto job = plain(*rig.service->job(*id));
  INFO(job.dump());
  CHECK(job["state"] == "done");
  CHECK(job["outcome"] == "restored and verified");
  events = rig.take_events();
  REQUIRE(events.size() >= 1);
  CHECK(events[0]["event"] == "restored");

  // The drift check finds the drive back at its approved configuration.
  rig.at(t0 + 30min);
  events = rig.take_events();
  INFO(nlohmann::json(events).dump());
  CHECK((*rig.service->drive("cell4/gripper"))["status"] == "ok");
  auto get = run_tool_in(rig.dir.path, "get 0010 --rom --quiet --port " + a.url);
  CHECK(get.out.find("5") != std::string::npos);
}

}  // namespace serve_test_serve_linudp
