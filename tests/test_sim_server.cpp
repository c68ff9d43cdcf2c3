// End to end: a simulated drive served on a pseudo-terminal in a thread, a
// client talking to it through the serial transport.
#include <atomic>
#include <thread>

#include "sim/server.hpp"
#include "test_sim_harness.hpp"
#include "transport/pty.hpp"

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
