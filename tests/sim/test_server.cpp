// End to end: a simulated drive served on a pseudo-terminal in a thread, a
// client talking to it through the serial transport.
#include <atomic>
#include <thread>

#include "sim/server.hpp"
#include "test_sim_harness.hpp"
#include "transport/pty.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace sim_test_server {

using namespace lmcfg;
using namespace lmcfg::codec;

namespace {
Bytes read_frame(transport::Transport& t, int total_ms) {
  Bytes out;
  StreamDecoder dec;
  const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(total_ms);
  while (std::chrono::steady_clock::now() < until) {
    auto r = t.read_some(transport::Millis(50));
    REQUIRE(r.ok());
    out.insert(out.end(), r->begin(), r->end());
    dec.feed(*r);
    if (auto f = dec.next(); f && f->ok()) return out;
  }
  return out;
}
}  // namespace

TEST_CASE("sim: pty server end to end through the serial transport", "[sim][sim-server]") {
  auto pty = transport::open_pty();
  REQUIRE(pty.ok());
  sim::Drive drive(test::load_fixture("manual-drive.json"));
  const std::string slave = pty->slave_path;
  transport::FdTransport master(std::move(pty->master), "pty " + slave);

  std::atomic<bool> stop{false};
  sim::ServeStats stats;
  Result<void> served;
  std::thread server([&] {
    sim::ServeOptions o;
    o.real_time = true;
    o.poll = transport::Millis(10);
    o.should_stop = [&] { return stop.load(); };
    served = sim::serve(drive, master, o, &stats);
  });

  {
    auto client = transport::open_serial({slave, 38400, transport::Parity::none, 1});
    REQUIRE(client.ok());
    auto& c = **client;
    // §10.1: read ROM of 13A2h.
    REQUIRE(c.write(from_hex("01 11 05 02 00 05 A2 13 04").value()).ok());
    CHECK(read_frame(c, 2000) == from_hex("01 11 0A 02 50 00 00 A2 13 0A 00 00 00 04").value());
    // §14.3 error counters.
    REQUIRE(c.write(from_hex("01 11 03 02 02 07 04").value()).ok());
    CHECK(read_frame(c, 2000) == from_hex("01 11 08 02 72 00 00 15 00 90 00 04").value());
    // A frame for another ID gets no answer.
    REQUIRE(c.write(from_hex("01 12 05 02 00 05 A2 13 04").value()).ok());
    CHECK(read_frame(c, 200).empty());
  }
  stop = true;
  server.join();
  CHECK(served.ok());
  CHECK(stats.answers == 2);
  CHECK(drive.stats().ignored_other_id == 1);
}

namespace {

// Serves `drives` on a new pty until the scope ends (--fast unless real_time).
struct PtyLine {
  std::string slave;
  transport::UniqueFd slave_fd;  // held open: without it the master reads EIO until a client opens
  std::unique_ptr<transport::FdTransport> master;
  std::atomic<bool> stop{false};
  std::thread server;
  PtyLine(std::vector<sim::Drive*> drives, bool real_time) {
    auto pty = transport::open_pty();
    REQUIRE(pty.ok());
    slave = pty->slave_path;
    slave_fd = std::move(pty->slave);
    master = std::make_unique<transport::FdTransport>(std::move(pty->master), "pty " + slave);
    server = std::thread([this, drives, real_time] {
      sim::ServeOptions o;
      o.real_time = real_time;
      o.poll = transport::Millis(10);
      o.should_stop = [this] { return stop.load(); };
      (void)sim::serve_bus(drives, *master, o);
    });
  }
  ~PtyLine() {
    stop = true;
    server.join();
  }
};

}  // namespace

TEST_CASE("sim: one served line with several MACIDs, only the addressed drive answers",
          "[sim][sim-server]") {
  sim::Drive a(test::load_fixture("manual-drive.json"));
  auto second = test::load_fixture("manual-drive.json");
  second.macid = 0x12;
  sim::Drive b(std::move(second));
  {
    PtyLine line({&a, &b}, false);
    auto client = transport::open_serial({line.slave, 38400, transport::Parity::none, 1});
    REQUIRE(client.ok());
    auto& c = **client;
    // §10.1 read ROM of 13A2h, to each MACID and to one nobody has.
    REQUIRE(c.write(from_hex("01 11 05 02 00 05 A2 13 04").value()).ok());
    CHECK(read_frame(c, 2000) == from_hex("01 11 0A 02 50 00 00 A2 13 0A 00 00 00 04").value());
    REQUIRE(c.write(from_hex("01 12 05 02 00 05 A2 13 04").value()).ok());
    CHECK(read_frame(c, 2000) == from_hex("01 12 0A 02 50 00 00 A2 13 0A 00 00 00 04").value());
    REQUIRE(c.write(from_hex("01 13 05 02 00 05 A2 13 04").value()).ok());
    CHECK(read_frame(c, 200).empty());
  }  // the server has stopped: its drives' counters can be read
  CHECK(a.stats().answers == 1);
  CHECK(b.stats().answers == 1);
}

TEST_CASE("sim: a drive started in one fast connection answers at once in the next",
          "[sim][sim-server]") {
  sim::Drive drive(test::load_fixture("manual-drive.json"));
  {
    PtyLine line({&drive}, false);
    auto client = transport::open_serial({line.slave, 38400, transport::Parity::none, 1});
    REQUIRE(client.ok());
    // LinRS §13.4: start MC, answered after completion (ca. 3 s, skipped here).
    REQUIRE((*client)->write(from_hex("01 11 03 02 04 06 04").value()).ok());
    CHECK(read_frame(**client, 2000) == from_hex("01 11 04 02 60 00 00 04").value());
  }
  {
    PtyLine again({&drive}, false);
    auto client = transport::open_serial({again.slave, 38400, transport::Parity::none, 1});
    REQUIRE(client.ok());
    REQUIRE((*client)->write(from_hex("01 11 05 02 00 05 A2 13 04").value()).ok());
    CHECK(read_frame(**client, 200) ==
          from_hex("01 11 0A 02 50 00 00 A2 13 0A 00 00 00 04").value());
  }
  CHECK(drive.stats().ignored_busy == 0);
}

}  // namespace sim_test_server
