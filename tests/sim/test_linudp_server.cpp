// sim::serve_linudp (lib/sim/linudp_server.*): the simulated drive on a real
// UDP socket answers the LinUDP client.
#include <atomic>
#include <catch2/catch.hpp>
#include <thread>

#include "client/linudp_client.hpp"
#include "e2e_support.hpp"
#include "sim/linudp_server.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace sim_test_linudp_server {

using namespace lmcfg;

TEST_CASE("LinUDP sim server: a client reads a value over loopback UDP", "[linudp][sim][udp]") {
  auto drive = test::load_sim_drive("commissioned-axis.json");
  sim::LinudpDrive udp(drive);
  auto socket = transport::UdpServer::bind("127.0.0.1", 0);
  REQUIRE(socket.ok());
  std::atomic<bool> stop{false};
  sim::LinudpServeOptions opt;
  opt.should_stop = [&] { return stop.load(); };
  std::thread server([&] { (void)sim::serve_linudp(udp, *socket, opt); });
  auto t = transport::open_udp("127.0.0.1", socket->port(), transport::UdpOptions{0});
  REQUIRE(t.ok());
  client::LinudpClient c(**t, client::ClientOptions{});
  const auto& [upid, p] = *drive->state().params.begin();
  auto v = c.read_rom(upid);
  stop = true;
  server.join();
  REQUIRE(v.ok());
  CHECK(*v == p.rom);
}

}  // namespace sim_test_linudp_server
