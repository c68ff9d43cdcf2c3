#pragma once
// `lmcfg sim --devicenet` as a child process, on a pseudo-terminal (the path a
// USB-CAN adapter takes) or on loopback TCP (slcan:tcp://), and another master
// changing its values behind lmcfg's back.
#include <catch2/catch.hpp>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "can/link.hpp"
#include "config/config_io.hpp"
#include "devicenet/master.hpp"
#include "link/port.hpp"
#include "subprocess.hpp"

namespace lmcfg::test {

struct DevicenetSim {
  enum class Where { pty, tcp };
  std::unique_ptr<Child> child;
  std::string pty;   // the pty's path ("" on TCP)
  std::string port;  // what --port takes: "slcan:/dev/pts/3", "slcan:tcp://127.0.0.1:4711"
  std::string announced, options;  // the sim's two lines: the pty's path or TCP port; link options
  int mac = 5;
  // A controller at MAC ID `mac` with `motors` (A and B), plus `extra` options.
  explicit DevicenetSim(std::vector<std::string> extra = {}, Where where = Where::pty,
                        int mac_id = 5, const std::string& motors = "A,B")
      : mac(mac_id) {
    std::vector<std::string> argv{
        LMCFG_TOOL_PATH,      "sim", "--devicenet", "--devicenet-macid", std::to_string(mac_id),
        "--devicenet-motors", motors};
    if (where == Where::tcp) {
      argv.push_back("--tcp");
      argv.push_back("127.0.0.1:0");
    }
    argv.insert(argv.end(), extra.begin(), extra.end());
    child = std::make_unique<Child>(argv);
    announced = child->read_line();
    options = child->read_line();  // "link options: --port PORT ..."
    const auto from = options.find("--port ") + 7;
    port = options.substr(from, options.find(' ', from) - from);
    if (where == Where::pty) pty = announced;
  }
  std::string link() const {
    return "--port " + port + " --devicenet-macid " + std::to_string(mac) +
           " --devicenet-listen-ms 20 --timeout-ms 100";
  }
};

// Another master on the controller (a PLC, a technician with LinTalk), as
// the library's master: connected, `change` run, released.
template <class Change>
inline void as_another_master(const DevicenetSim& sim, bool expect_transmit_ack, Change change) {
  auto link = link::open_can_link(sim.port, {125000, expect_transmit_ack, transport::Millis(1000)});
  REQUIRE(link.ok());
  devicenet::MasterOptions o;
  o.slave_mac = static_cast<std::uint8_t>(sim.mac);
  o.own_mac = 61;
  o.timeout = transport::Millis(100);
  o.retries = 5;
  devicenet::Master m(**link, o);
  REQUIRE(m.connect().ok());
  change(m);
  REQUIRE(m.release().ok());
}

// Another tool between two runs of lmcfg sets motor A's Controller P to 2000
// and motor B's Filter Maximal Speed to 5243.
inline void change_two_values(const DevicenetSim& sim) {
  as_another_master(sim, true, [](devicenet::Master& m) {
    REQUIRE(m.command({true, false, false, false}, 0x35, 2000).ok());  // Set Controller P, motor A
    REQUIRE(m.command({false, true, false, false}, 0x51, 5243).ok());  // Set Filter Max Speed, B
  });
}

// Another master sets motor A's Controller P to 2000 (any controller has motor A).
inline void change_motor_a(const DevicenetSim& sim) {
  as_another_master(sim, false, [](devicenet::Master& m) {
    REQUIRE(m.command({true, false, false, false}, 0x35, 2000).ok());  // Set Controller P, motor A
  });
}

// A backup of `sim` in dir/ctl.json, and dir/bad.json: the same with motor B's
// In Position Low Limit (48h) at 600, outside Table 5-1's "2 to 511".
inline void backup_and_out_of_range(const DevicenetSim& sim, const std::filesystem::path& dir) {
  REQUIRE(run_tool_in(dir, "backup " + sim.link() + " -q -o ctl.json").exit_code == 0);
  auto file = config::read_config_file((dir / "ctl.json").string());
  REQUIRE(file.ok());
  for (auto& v : file->devicenet->values)
    if (v.motor == 1 && v.command == 0x48) v.raw = 600;
  REQUIRE(config::write_config_file(*file, (dir / "bad.json").string()).ok());
}

}  // namespace lmcfg::test
