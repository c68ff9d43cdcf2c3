// serve/task_limit.hpp: the service's threads against its control group's
// pids.max. The /proc/self/cgroup forms are cgroups(7)'s ("hierarchy-ID:
// controller-list:cgroup-path"; v2's entry "0::/path").
#include <catch2/catch.hpp>

#include "fleet/inventory.hpp"
#include "serve/task_limit.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace serve_test_task_limit {

using namespace lmcfg;

fleet::Inventory lines(std::size_t n) {
  fleet::Inventory inv;
  for (std::size_t i = 0; i < n; ++i) {
    fleet::LineEntry line;
    line.name = "line" + std::to_string(i + 1);
    inv.lines.push_back(line);
  }
  return inv;
}

TEST_CASE("task limit: a worker per line and the service's own threads", "[serve][task_limit]") {
  CHECK(serve::tasks_needed(lines(0), 4) == 9);
  CHECK(serve::tasks_needed(lines(119), 4) == 128);
  CHECK(serve::tasks_needed(lines(10), 0) == 16);  // at least one HTTP worker
}

TEST_CASE("task limit: the pids.max file named by /proc/self/cgroup (cgroups(7))",
          "[serve][task_limit]") {
  CHECK(serve::pids_max_path("0::/system.slice/lmcfg-serve.service\n") ==
        "/sys/fs/cgroup/system.slice/lmcfg-serve.service/pids.max");
  CHECK(serve::pids_max_path("0::/\n") == "/sys/fs/cgroup/pids.max");
  // v1 (and hybrid: v1's pids controller holds the limit).
  CHECK(serve::pids_max_path("9:name=systemd:/x\n8:pids:/system.slice/a.service\n0::/x\n") ==
        "/sys/fs/cgroup/pids/system.slice/a.service/pids.max");
  CHECK(serve::pids_max_path("3:cpu,pids:/a\n") == "/sys/fs/cgroup/pids/a/pids.max");
  CHECK(serve::pids_max_path("4:memory:/a\n") == "");
  CHECK(serve::pids_max_path("") == "");
  CHECK(serve::pids_max_path("garbage") == "");
}

TEST_CASE("task limit: pids.max's number, or none for max", "[serve][task_limit]") {
  CHECK(serve::parse_pids_max("128\n") == std::optional<std::uint64_t>(128));
  CHECK_FALSE(serve::parse_pids_max("max\n"));
  CHECK_FALSE(serve::parse_pids_max(""));
  CHECK_FALSE(serve::parse_pids_max("12a"));
  CHECK_FALSE(serve::parse_pids_max("99999999999999999999"));
}

TEST_CASE("task limit: the start refuses an inventory over the limit, saying what to raise",
          "[serve][task_limit]") {
  const serve::TaskLimit unit{128, "/sys/fs/cgroup/system.slice/lmcfg-serve.service/pids.max"};
  CHECK(serve::check_task_limit(lines(119), 4, unit).ok());
  CHECK(serve::check_task_limit(lines(500), 4, std::nullopt).ok());  // no limit
  auto r = serve::check_task_limit(lines(120), 4, unit);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == Errc::invalid_argument);
  CHECK(r.error().message ==
        "the inventory's 120 line(s) need 129 tasks (a worker per line, 4 HTTP workers, the "
        "event loop, the schedule, the notifier and its command, the archive push), and this "
        "control group allows 128 (/sys/fs/cgroup/system.slice/lmcfg-serve.service/pids.max, "
        "systemd's TasksMax=): raise it with `systemctl edit lmcfg-serve`, [Service] "
        "TasksMax=141, or split the inventory");
  r = serve::check_task_limit(lines(500), 4, unit);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().message.find("need 509 tasks") != std::string::npos);
  CHECK(r.error().message.find("TasksMax=559,") != std::string::npos);
}

}  // namespace serve_test_task_limit
