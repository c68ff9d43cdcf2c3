// The CAN links (lib/can/link.cpp, docs/can.md): an slcan adapter played on a
// real pseudo-terminal, the trace decorator, and SocketCAN's errors (a vcan
// loopback when LMCFG_TEST_VCAN names one).
#include <atomic>
#include <catch2/catch.hpp>
#include <cstdlib>
#include <mutex>
#include <thread>

#include "can/link.hpp"
#include "link/port.hpp"
#include "transport/pty.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace can_test_link {

using namespace lmcfg;

namespace {

Bytes bytes(std::string_view s) { return Bytes(s.begin(), s.end()); }

// An slcan adapter on the master side of a pty: acknowledges "Sn" and "O"
// with CR (or refuses the bit rate with BEL), answers "C" on a closed channel
// with BEL, acknowledges each transmitted frame with "z\r" and puts a reply
// frame (ID + 1, same data) on the "bus". no_transmit_ack: answers "V" with
// "V0100" and acknowledges no transmitted frame; silent: answers nothing, but
// still replies to frames.
struct FakeAdapter {
  enum class Mode { normal, refuse_bitrate, silent, no_transmit_ack };
  std::string slave;
  transport::UniqueFd slave_fd;  // held open: without it the master reads EIO until a client opens
  std::unique_ptr<transport::FdTransport> master;
  std::atomic<bool> stop{false};
  std::mutex heard_lock;
  std::vector<std::string> heard;
  std::vector<std::string> heard_so_far() {
    std::lock_guard<std::mutex> l(heard_lock);
    return heard;
  }
  std::thread thread;
  explicit FakeAdapter(Mode mode) {
    auto pty = transport::open_pty();
    REQUIRE(pty.ok());
    slave = pty->slave_path;
    slave_fd = std::move(pty->slave);
    master = std::make_unique<transport::FdTransport>(std::move(pty->master), "adapter");
    thread = std::thread([this, mode] {
      std::string line;
      bool open = false;
      while (!stop) {
        auto r = master->read_some(transport::Millis(10));
        if (!r.ok()) return;
        for (std::uint8_t b : *r) {
          if (b != '\r') {
            line.push_back(static_cast<char>(b));
            continue;
          }
          {
            std::lock_guard<std::mutex> l(heard_lock);
            heard.push_back(line);
          }
          std::string answer;
          if (mode == Mode::silent) {
            if (line == "O") open = true;
            if (line[0] == 't' && open) {
              if (auto f = can::slcan::parse_frame_line(line)) {
                f->id += 1;
                answer = can::slcan::encode(*f);
              }
            }
          } else if (line == "V" && mode == Mode::no_transmit_ack) {
            answer = "V0100\r";
          } else if (line == "C") {
            answer = open ? "\r" : "\a";
            open = false;
          } else if (line[0] == 'S') {
            answer = mode == Mode::refuse_bitrate ? "\a" : "\r";
          } else if (line == "O") {
            answer = "\r";
            open = true;
          } else if (line[0] == 't' && open) {
            auto f = can::slcan::parse_frame_line(line);
            answer = mode == Mode::no_transmit_ack ? "" : "z\r";
            if (f) {
              f->id += 1;
              answer += can::slcan::encode(*f);
            }
          } else {
            answer = "\a";
          }
          line.clear();
          if (!answer.empty()) (void)master->write(bytes(answer));
        }
      }
    });
  }
  ~FakeAdapter() {
    stop = true;
    thread.join();
  }
};

std::unique_ptr<transport::Transport> serial(const std::string& path) {
  auto s = transport::open_serial({path, 115200, transport::Parity::none, 1});
  REQUIRE(s.ok());
  return std::move(s).value();
}

}  // namespace

TEST_CASE("can: an slcan adapter on a pty: open, send with acknowledgement, receive",
          "[can][pty]") {
  FakeAdapter adapter(FakeAdapter::Mode::normal);
  std::vector<std::string> trace;
  auto link = can::open_slcan(serial(adapter.slave), {250000, true, transport::Millis(500)});
  REQUIRE(link.ok());
  can::TraceLink traced(
      std::move(link).value(), [&](const std::string& l) { trace.push_back(l); },
      [](const can::Frame& f, bool) {
        return f.id == 0x42F ? std::string("(reply)") : std::string();
      });
  const std::uint8_t alloc[] = {0x00, 0x4B, 0x03, 0x01, 0x03, 0x00};
  REQUIRE(traced.send(can::Frame::standard(0x42E, alloc)).ok());
  auto got = traced.receive(transport::Millis(1000));
  REQUIRE(got.ok());
  REQUIRE(*got);
  CHECK(**got == can::Frame::standard(0x42F, alloc));
  auto none = traced.receive(transport::Millis(50));
  REQUIRE(none.ok());
  CHECK_FALSE(*none);
  CHECK(trace == std::vector<std::string>{"TX 42E [6] 00 4B 03 01 03 00",
                                          "RX 42F [6] 00 4B 03 01 03 00  (reply)"});
  CHECK(traced.describe().rfind("slcan ", 0) == 0);
  CHECK(traced.describe().find("250 kbit/s") != std::string::npos);
  const std::vector<std::string> opening{"C", "V", "S5", "O", "t42E6004B03010300"};
  const auto heard = adapter.heard_so_far();
  REQUIRE(heard.size() >= 5);
  CHECK(std::vector<std::string>(heard.begin(), heard.begin() + 5) == opening);
}

TEST_CASE("can: an adapter that refuses the bit rate is named", "[can][pty]") {
  {
    FakeAdapter adapter(FakeAdapter::Mode::refuse_bitrate);
    auto link = can::open_slcan(serial(adapter.slave), {125000, true, transport::Millis(500)});
    REQUIRE_FALSE(link.ok());
    CHECK(link.error().message.find(": the slcan adapter refused 'S4' (BEL)") != std::string::npos);
  }
}

namespace {

// Sends an Allocate and receives the adapter's reply frame, ID + 1.
void send_and_receive(can::Link& link) {
  const std::uint8_t alloc[] = {0x00, 0x4B, 0x03, 0x01, 0x03, 0x00};
  REQUIRE(link.send(can::Frame::standard(0x42E, alloc)).ok());
  auto got = link.receive(transport::Millis(1000));
  REQUIRE(got.ok());
  REQUIRE(*got);
  CHECK(**got == can::Frame::standard(0x42F, alloc));
}

}  // namespace

TEST_CASE(
    "can: slcan adapters that do not acknowledge transmitted frames, or answer "
    "nothing at all, carry frames, the version is used when given",
    "[can][pty]") {
  {
    // Answers its commands and "V", never a transmitted frame: not waited
    // for by default (as the Linux slcan driver and python-can).
    FakeAdapter adapter(FakeAdapter::Mode::no_transmit_ack);
    auto link = can::open_slcan(serial(adapter.slave), {125000, false, transport::Millis(100)});
    REQUIRE(link.ok());
    send_and_receive(**link);
    CHECK((*link)->describe().find(" 125 kbit/s (adapter version 0100)") != std::string::npos);
    auto flags = (*link)->status_flags();  // "F" refused with BEL: not known, not an error
    REQUIRE(flags.ok());
    CHECK_FALSE(*flags);
  }
  {
    // Asked to wait for each acknowledgement, it names the frame it missed.
    FakeAdapter adapter(FakeAdapter::Mode::no_transmit_ack);
    auto link = can::open_slcan(serial(adapter.slave), {125000, true, transport::Millis(100)});
    REQUIRE(link.ok());
    const std::uint8_t one[] = {0x01};
    auto sent = (*link)->send(can::Frame::standard(0x42E, one));
    REQUIRE_FALSE(sent.ok());
    CHECK(sent.error().message.find(": the slcan adapter did not answer 't42E101' within 100 ms") !=
          std::string::npos);
  }
  {
    // Answers nothing, not even "C" or "V": opened without waiting for
    // acknowledgements (even when asked to), and said so.
    FakeAdapter adapter(FakeAdapter::Mode::silent);
    auto link = can::open_slcan(serial(adapter.slave), {125000, true, transport::Millis(100)});
    REQUIRE(link.ok());
    send_and_receive(**link);
    CHECK((*link)->describe().find(" 125 kbit/s (an adapter that answers no command)") !=
          std::string::npos);
    auto flags = (*link)->status_flags();
    REQUIRE(flags.ok());
    CHECK_FALSE(*flags);
    const auto heard = adapter.heard_so_far();
    REQUIRE(heard.size() >= 4);
    CHECK(std::vector<std::string>(heard.begin(), heard.begin() + 4) ==
          std::vector<std::string>{"C", "V", "S4", "O"});
  }
}

TEST_CASE("can: SocketCAN names a missing interface, a vcan loopback when one is given", "[can]") {
  auto missing = link::open_can_link("lmcfgnone0", {});
  REQUIRE_FALSE(missing.ok());
  CHECK(missing.error().message.rfind("CAN interface lmcfgnone0: ", 0) == 0);
  CHECK(missing.error().message.find("slcan:/dev/ttyACM0") != std::string::npos);
  const char* vcan = std::getenv("LMCFG_TEST_VCAN");  // e.g. vcan0, made by the caller
  if (!vcan) return;
  auto a = can::open_socketcan(vcan);
  auto b = can::open_socketcan(vcan);
  REQUIRE(a.ok());
  REQUIRE(b.ok());
  const std::uint8_t data[] = {1, 2, 3};
  REQUIRE((*a)->send(can::Frame::standard(0x123, data)).ok());
  auto got = (*b)->receive(transport::Millis(500));
  REQUIRE(got.ok());
  REQUIRE(*got);
  CHECK(**got == can::Frame::standard(0x123, data));
}

}  // namespace can_test_link
