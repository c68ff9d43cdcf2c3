// One program per port, through the real binary: a port held by one lmcfg
// (or by this test in its place) is refused to a second lmcfg with the
// holder's name and PID, exit 4, and not a telegram from the second.
#include <poll.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <thread>

#include "files.hpp"
#include "pty_sim.hpp"
#include "subprocess.hpp"
#include "transport/transport.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace tools_test_port_lock_cli {

using namespace lmcfg;
namespace fs = std::filesystem;

namespace {

using test::PtySim;

transport::SerialSettings line(const std::string& device) {
  return {device, 57600, transport::Parity::none, 1};
}

}  // namespace

TEST_CASE("port lock cli: get on a port held by a backup: the holder, exit 4, nothing sent",
          "[cli][lock]") {
  PtySim sim;
  const auto dir = test::temp_dir("lock-cli");
  // This test holds the port the way `lmcfg backup` does.
  auto held = transport::open_serial(line(sim.tty), nullptr, transport::PortClaim{"lmcfg backup"});
  REQUIRE(held.ok());

  auto r = test::run_tool_in(dir, "get 13A2 --port " + sim.tty + " --trace get.trace");
  CHECK(r.exit_code == 4);
  CHECK(r.err == "lmcfg get: port " + sim.tty + " is in use by lmcfg backup (PID " +
                     std::to_string(::getpid()) + ")\n");
  CHECK(r.out.empty());
  // Not a telegram: no trace was even started, and the simulated drive sent
  // no answer (it answers every request to MACID 11h) to the holder's side.
  CHECK_FALSE(fs::exists(dir / "get.trace"));
  auto heard = (*held)->read_some(transport::Millis(300));
  REQUIRE(heard.ok());
  CHECK(heard->empty());

  // Released: the same command talks to the drive.
  held->reset();
  auto again = test::run_tool_in(dir, "get 13A2 --port " + sim.tty + " --quiet");
  CHECK(again.exit_code == 0);
}

TEST_CASE("port lock cli: a running lmcfg holds its port, the second is told which and its PID",
          "[cli][lock]") {
  PtySim sim;
  const auto dir = test::temp_dir("lock-cli-two");
  // A slow scan (every MACID at 4800 Bd, where the drive at 57600 hears nothing)
  // holds the port for seconds.
  test::Child scan({LMCFG_TOOL_PATH, "scan", "--port", sim.tty, "--baud", "4800", "--from", "0",
                    "--to", "0xFF", "--quiet"});
  std::optional<transport::PortHolder> holder;
  for (int i = 0; i < 500 && !holder; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    holder = transport::port_holder(sim.tty);
  }
  REQUIRE(holder);
  CHECK(holder->holder == "lmcfg scan");
  CHECK(holder->pid == scan.pid());

  auto r = test::run_tool_in(dir, "info --port " + sim.tty + " --trace info.trace");
  CHECK(r.exit_code == 4);
  CHECK(r.err == "lmcfg info: port " + sim.tty + " is in use by lmcfg scan (PID " +
                     std::to_string(scan.pid()) + ")\n");
  CHECK_FALSE(fs::exists(dir / "info.trace"));
  scan.stop();
}

TEST_CASE("port lock cli: the slcan adapter's serial port is locked too",
          "[cli][lock][devicenet]") {
  test::Child sim({LMCFG_TOOL_PATH, "sim", "--devicenet", "--devicenet-macid", "5"});
  const std::string tty = sim.read_line();
  (void)sim.read_line();
  REQUIRE(tty.rfind("/dev/pts/", 0) == 0);
  const auto dir = test::temp_dir("lock-cli-can");
  auto held = transport::open_serial({tty, 115200, transport::Parity::none, 1}, nullptr,
                                     transport::PortClaim{"lmcfg restore"});
  REQUIRE(held.ok());
  auto r = test::run_tool_in(dir, "backup --port slcan:" + tty +
                                      " --devicenet-macid 5 --devicenet-listen-ms 20 -o x.json");
  CHECK(r.exit_code == 4);
  CHECK(r.err == "lmcfg backup: port " + tty + " is in use by lmcfg restore (PID " +
                     std::to_string(::getpid()) + ")\n");
  CHECK_FALSE(fs::exists(dir / "x.json"));
  auto heard = (*held)->read_some(transport::Millis(300));
  REQUIRE(heard.ok());
  CHECK(heard->empty());
}

}  // namespace tools_test_port_lock_cli
