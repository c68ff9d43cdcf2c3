// A line of a plant (lib/ops/line.cpp): a LinRS line of simulated drives read
// through one session, switching MACID from drive to drive, and a CAN line of
// DeviceNet controllers (seed 000) whose link is opened for each controller.
#include <catch2/catch.hpp>
#include <filesystem>

#include "devicenet/catalogue.hpp"
#include "devicenet_sim.hpp"
#include "e2e_support.hpp"
#include "files.hpp"
#include "ops/line.hpp"
#include "sim/state_file.hpp"
#include "sim_ports.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace ops_test_line {

using namespace lmcfg;

namespace {

std::optional<std::uint32_t> value_of(const config::DriveConfig& cfg, std::uint16_t upid) {
  for (const auto& layer : cfg.layers)
    for (const auto& p : layer)
      if (p.upid == upid) return p.value;
  return std::nullopt;
}

ops::BackupOptions mc_only() {
  ops::BackupOptions bo;
  bo.layers = {false, true, false, false};
  bo.curves = false;
  bo.command_table = false;
  bo.ask_drive = false;
  return bo;
}

}  // namespace

TEST_CASE("line: each controller's DeviceNet options from the line's and its own", "[line]") {
  ops::DevicenetLinkOptions line;
  line.port = "slcan:/dev/ttyACM0";
  line.can_bitrate = 250000;
  line.master.slave_mac = 63;
  line.master.own_mac = 61;
  line.holder = "lmcfg fleet backup";
  ops::LineDrive d;
  d.id = 5;
  auto l = ops::devicenet_link_for(line, d);
  CHECK(l.port == "slcan:/dev/ttyACM0");
  CHECK(l.can_bitrate == 250000);
  CHECK(l.master.slave_mac == 5);
  CHECK(l.master.own_mac == 61);
  CHECK(l.holder == "lmcfg fleet backup");
  // Without modules of its own the line's layout (seed 000's default) stays.
  CHECK(devicenet::module_names(l.master.layout) == devicenet::module_names(line.master.layout));
  devicenet::IoLayout direct;
  direct.direct_in = true;
  direct.direct_out1 = true;
  d.io_modules = direct;
  l = ops::devicenet_link_for(line, d);
  CHECK(devicenet::module_names(l.master.layout) == devicenet::module_names(direct));

  auto read = ops::devicenet_read_for(ops::LineDrive{});
  CHECK_FALSE(read.motors);
  CHECK(read.module_values);
  CHECK(read.live);
  d.motors = std::vector<int>{0, 2};
  d.module_values = false;
  read = ops::devicenet_read_for(d);
  CHECK(read.motors == std::vector<int>{0, 2});
  CHECK_FALSE(read.module_values);
  // A LinRS line converts from its link spec.
  const ops::LineLink linrs(link::LinkSpec{});
  CHECK_FALSE(linrs.is_devicenet());
  ops::LineLink can;
  can.devicenet = line;
  CHECK(can.is_devicenet());
}

TEST_CASE("line: two LinRS drives on one line read through one session", "[line]") {
  REQUIRE(test::kSimPortsRegistered);
  test::ScratchDir dir("line-linrs");
  const auto a = (dir.path / "a.json").string(), b = (dir.path / "b.json").string();
  std::filesystem::copy_file(test::sim_fixture("commissioned-axis.json"), a);
  auto second = sim::load_state(test::sim_fixture("commissioned-axis.json"));
  REQUIRE(second.ok());
  second->macid = 0x22;
  second->switches = sim::HexSwitches{0x22, 57600};
  second->params.at(0x13A2).rom = second->params.at(0x13A2).ram = 41;
  REQUIRE(sim::save_state(*second, b).ok());

  link::LinkSpec spec;
  spec.port = *link::parse_port("sim:" + a + "," + b);
  auto line = ops::LineSession::open(ops::LineLink(spec), 0x11);
  REQUIRE(line.ok());
  std::vector<std::string> phases;
  auto bo = mc_only();
  bo.progress = [&](const std::string& phase, std::size_t, std::size_t) {
    phases.push_back(phase);
  };
  ops::LineDrive drive_b;
  drive_b.id = 0x22;
  auto from_b = (*line)->backup(drive_b, bo, db::Database::empty());
  REQUIRE(from_b.ok());
  CHECK(value_of(*from_b, 0x13A2) == 41u);
  CHECK(from_b->identity.link.port == "sim:" + a + "," + b);
  CHECK(from_b->identity.link.baud == "57600");
  CHECK_FALSE(phases.empty());
  const auto after_b = (*line)->stats().requests;
  CHECK(after_b > 0);
  auto from_a = (*line)->backup(ops::LineDrive{}, mc_only(), db::Database::empty());
  REQUIRE(from_a.ok());
  CHECK(value_of(*from_a, 0x13A2) == 40u);  // commissioned-axis.json's P gain
  CHECK((*line)->stats().requests > after_b);

  ops::LineDrive absent;
  absent.id = 0x33;
  auto none = (*line)->backup(absent, mc_only(), db::Database::empty());
  REQUIRE_FALSE(none.ok());
  CHECK(none.error().code == ErrorClass::link_failure);
  REQUIRE((*line)->close().ok());
  // Closing saved both drives' states back to their files.
  auto saved = sim::load_state(b);
  REQUIRE(saved.ok());
  CHECK(saved->macid == 0x22);
}

TEST_CASE("line: a CAN line opens nothing until a controller is read", "[line]") {
  ops::LineLink can;
  can.devicenet = ops::DevicenetLinkOptions{};
  can.devicenet->port = "slcan:/nonexistent/ttyACM9";
  auto line = ops::LineSession::open(can, 5);
  REQUIRE(line.ok());
  CHECK((*line)->stats().requests == 0);
  ops::LineDrive d;
  d.id = 5;
  auto r = (*line)->backup(d, ops::BackupOptions{}, db::Database::empty());
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().message.find("/nonexistent/ttyACM9") != std::string::npos);
  CHECK((*line)->stats().requests == 0);  // a CAN line has no LinRS telegrams
  CHECK((*line)->close().ok());
}

TEST_CASE("line: DeviceNet §5.2 a controller on a CAN line read with its motors", "[line][pty]") {
  test::DevicenetSim sim;  // MAC ID 5, motors A and B
  ops::LineLink can;
  can.devicenet = ops::DevicenetLinkOptions{};
  can.devicenet->port = sim.port;
  can.devicenet->master.timeout = transport::Millis(100);
  can.devicenet->master.duplicate_check_wait = transport::Millis(20);
  auto line = ops::LineSession::open(can, 5);
  REQUIRE(line.ok());
  ops::LineDrive d;
  d.id = 5;
  d.motors = std::vector<int>{0, 1};
  d.module_values = false;
  bool progress = false;
  ops::BackupOptions bo;
  bo.progress = [&](const std::string& phase, std::size_t, std::size_t) {
    CHECK(phase == "devicenet");
    progress = true;
  };
  auto cfg = (*line)->backup(d, bo, db::Database::empty());
  INFO((cfg.ok() ? std::string() : cfg.error().message));
  REQUIRE(cfg.ok());
  CHECK(progress);
  REQUIRE(cfg->devicenet);
  CHECK(cfg->devicenet->motors == std::vector<int>{0, 1});
  CHECK(cfg->devicenet->can_bitrate == 125000);
  CHECK(cfg->identity.macid == "5");
  CHECK(cfg->identity.link.port == sim.port);
  CHECK(cfg->identity.link.baud == "125000");
  CHECK_FALSE(cfg->devicenet->values.empty());
  for (const auto& v : cfg->devicenet->values)
    CHECK_FALSE(devicenet::value_command(v.command)->needs_module);
  CHECK((*line)->stats().requests == 0);
  CHECK((*line)->close().ok());
}

}  // namespace ops_test_line
