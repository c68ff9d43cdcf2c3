// RFC 2217 client: the pure Telnet codec, a scripted server in this process on
// 127.0.0.1 (refusals, garbled and missing confirmations), and the real
// ser2net serving a simulated drive on a pseudo-terminal.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>

#include <atomic>
#include <catch2/catch.hpp>
#include <functional>
#include <mutex>
#include <thread>

#include "client/client.hpp"
#include "codec/frame.hpp"
#include "ser2net_rig.hpp"
#include "sim/server.hpp"
#include "test_sim_harness.hpp"
#include "transport/pty.hpp"
#include "transport/rfc2217.hpp"
#include "transport_test_support.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace transport_test_rfc2217 {

using namespace lmcfg;
using namespace lmcfg::transport;
using namespace lmcfg::transport::rfc2217;
using namespace std::chrono_literals;

namespace {

Bytes hex(const char* text) { return from_hex(text).value(); }

// Feeds `stream` to a decoder in pieces of `piece` bytes.
std::pair<Bytes, std::vector<Event>> decode_in_pieces(const Bytes& stream, std::size_t piece) {
  Decoder d;
  Bytes data;
  std::vector<Event> events;
  for (std::size_t i = 0; i < stream.size(); i += piece) {
    const std::size_t n = std::min(piece, stream.size() - i);
    d.feed(ByteView(stream.data() + i, n), data, events);
  }
  CHECK_FALSE(d.in_command());
  return {data, events};
}

Event subneg(const char* payload) {
  return Event{Event::Kind::subnegotiation, kSB, kComPort, hex(payload)};
}

}  // namespace

// ---------------------------------------------------------------- pure codec

TEST_CASE("rfc2217: a 0xFF data byte is doubled on write and IAC IAC reads as one 0xFF (RFC 856)",
          "[rfc2217][transport]") {
  CHECK(escape_data(hex("01 FF 02 FF FF 03")) == hex("01 FF FF 02 FF FF FF FF 03"));
  CHECK(escape_data(hex("01 02")) == hex("01 02"));
  for (std::size_t piece : {1u, 2u, 3u, 100u}) {
    INFO("pieces of " << piece);
    auto [data, events] = decode_in_pieces(hex("01 FF FF 02 FF FF FF FF 03"), piece);
    CHECK(data == hex("01 FF 02 FF FF 03"));
    CHECK(events.empty());
  }
}

TEST_CASE("rfc2217: commands and subnegotiations are stripped from data across read boundaries",
          "[rfc2217][transport]") {
  // Data, NOTIFY-MODEMSTATE (107) with IAC IAC in its value, a NOP (241),
  // WILL ECHO, data, NOTIFY-LINESTATE (106), data.
  const Bytes stream = hex("05 FF FA 2C 6B FF FF FF F0 FF F1 FF FB 01 06 FF FA 2C 6A 60 FF F0 07");
  for (std::size_t piece : {1u, 2u, 5u, 7u, 100u}) {
    INFO("pieces of " << piece);
    auto [data, events] = decode_in_pieces(stream, piece);
    CHECK(data == hex("05 06 07"));
    REQUIRE(events.size() == 4);
    CHECK(events[0] == subneg("6B FF"));
    CHECK(events[1] == Event{Event::Kind::command, 241, 0, {}});
    CHECK(events[2] == Event{Event::Kind::negotiation, kWILL, kEcho, {}});
    CHECK(events[3] == subneg("6A 60"));
  }
  Decoder d;
  Bytes data;
  std::vector<Event> events;
  d.feed(hex("01 FF FA 2C 65 00"), data, events);
  CHECK(d.in_command());
  CHECK(data == hex("01"));
  CHECK(events.empty());
  d.feed(hex("00 E1 00 FF F0 02"), data, events);
  CHECK(data == hex("01 02"));
  REQUIRE(events.size() == 1);
  CHECK(events[0] == subneg("65 00 00 E1 00"));

  // A command inside a subnegotiation (not allowed, RFC 855) ends it and counts as itself.
  auto [rest, cut] = decode_in_pieces(hex("FF FA 2C 6B 30 FF FB 01 05"), 1);
  CHECK(rest == hex("05"));
  REQUIRE(cut.size() == 2);
  CHECK(cut[0] == subneg("6B 30"));
  CHECK(cut[1] == Event{Event::Kind::negotiation, kWILL, kEcho, {}});
}

TEST_CASE("rfc2217: commands encode as IAC SB COM-PORT-OPTION code value IAC SE (RFC 2217)",
          "[rfc2217][transport]") {
  // SET-BAUDRATE: "four octets ... network standard format"; 57600 = 0000E100h.
  CHECK(encode_command(Command::set_baudrate, baud_value(57600)) ==
        hex("FF FA 2C 01 00 00 E1 00 FF F0"));
  CHECK(encode_command(Command::set_parity, Bytes{parity_value(Parity::even)}) ==
        hex("FF FA 2C 03 03 FF F0"));
  CHECK(parity_value(Parity::none) == 1);
  CHECK(parity_value(Parity::odd) == 2);
  CHECK(stopsize_value(1) == 1);
  CHECK(stopsize_value(2) == 2);
  // A 255 inside a value is doubled (RFC 855): 16777215 = 00FFFFFFh.
  CHECK(encode_command(Command::set_baudrate, baud_value(0xFFFFFF)) ==
        hex("FF FA 2C 01 00 FF FF FF FF FF FF FF F0"));
  CHECK(encode_negotiation(kWILL, kComPort) == hex("FF FB 2C"));
}

TEST_CASE("rfc2217: confirmations are code + 100 with the asked value (RFC 2217)",
          "[rfc2217][transport]") {
  CHECK(check_confirmation(Command::set_baudrate, baud_value(57600), hex("65 00 00 E1 00")).ok());
  CHECK(check_confirmation(Command::set_datasize, Bytes{8}, hex("66 08")).ok());
  CHECK(check_confirmation(Command::set_parity, Bytes{1}, hex("67 01")).ok());
  CHECK(check_confirmation(Command::set_stopsize, Bytes{1}, hex("68 01")).ok());
  CHECK(check_confirmation(Command::set_control, Bytes{1}, hex("69 01")).ok());

  auto wrong = check_confirmation(Command::set_baudrate, baud_value(57600), hex("65 00 00 25 80"));
  REQUIRE_FALSE(wrong.ok());
  CHECK(wrong.error().code == make_error_code(Errc::unexpected_response));
  CHECK(wrong.error().message == "the server confirmed SET-BAUDRATE 9600, asked 57600");
  CHECK(check_confirmation(Command::set_parity, Bytes{1}, hex("67 03")).error().message ==
        "the server confirmed SET-PARITY even, asked none");
  CHECK(check_confirmation(Command::set_stopsize, Bytes{2}, hex("68 03")).error().message ==
        "the server confirmed SET-STOPSIZE 1.5 stop bits, asked 2 stop bits");
  CHECK(check_confirmation(Command::set_control, Bytes{1}, hex("69 03")).error().message ==
        "the server confirmed SET-CONTROL hardware flow control, asked no flow control");
  CHECK(check_confirmation(Command::set_baudrate, baud_value(57600), hex("65 E1 00"))
            .error()
            .message == "the server confirmed SET-BAUDRATE with 2 value bytes, expected 4");
  CHECK(check_confirmation(Command::set_parity, Bytes{1}, hex("66 01")).error().message ==
        "the server answered SET-PARITY with code 102, expected code 103");
  CHECK(check_confirmation(Command::set_parity, Bytes{1}, Bytes{}).error().message ==
        "the server answered SET-PARITY with an empty subnegotiation, expected code 103");
}

TEST_CASE("rfc2217: option negotiation accepts BINARY, SGA and COM-PORT-OPTION, refuses others",
          "[rfc2217][transport]") {
  Negotiator n;
  CHECK(n.start() == hex("FF FB 2C FF FB 00 FF FB 03 FF FD 00 FF FD 03"));
  CHECK(n.ours(kComPort) == Negotiator::Side::asked);
  // Answers to our requests are not acknowledged (RFC 854).
  CHECK(n.answer(kDO, kComPort).empty());
  CHECK(n.ours(kComPort) == Negotiator::Side::on);
  CHECK(n.answer(kWILL, kBinary).empty());
  CHECK(n.answer(kDO, kBinary).empty());
  CHECK(n.theirs(kBinary) == Negotiator::Side::on);
  // Nor a request for a mode already in effect.
  CHECK(n.answer(kDO, kComPort).empty());
  // Unknown options are refused politely: ser2net offers ECHO; TERMINAL-TYPE (24).
  CHECK(n.answer(kWILL, kEcho) == hex("FF FE 01"));
  CHECK(n.answer(kDO, 24) == hex("FF FC 18"));
  CHECK(n.answer(kDONT, kEcho).empty());
  CHECK(n.answer(kWONT, 24).empty());
  // The server turning an enabled option off is acknowledged.
  CHECK(n.answer(kWONT, kBinary) == hex("FF FE 00"));
  CHECK(n.theirs(kBinary) == Negotiator::Side::off);
  // And turning it on again (it is our option as well).
  CHECK(n.answer(kWILL, kBinary) == hex("FF FD 00"));
  // A refusal of an asked option.
  Negotiator m;
  (void)m.start();
  CHECK(m.answer(kDONT, kComPort).empty());
  CHECK(m.ours(kComPort) == Negotiator::Side::refused);
}

// ------------------------------------------------- scripted server in-process

namespace {

// One RFC 2217 server connection on 127.0.0.1, scripted by `confirm`: for each
// COM-PORT-OPTION command (payload = code + value) it returns the payload of
// the answer, or nullopt for none. Echoes data back, escaped, with a
// NOTIFY-MODEMSTATE split over two sends in the middle. Records what it got.
struct ScriptedServer {
  UniqueFd listener;
  std::uint16_t port = 0;
  bool accept_com_port = true;
  bool silent = false;  // a raw TCP port: says nothing at all
  std::function<std::optional<Bytes>(const Bytes&)> confirm = [](const Bytes& p) {
    Bytes a = p;
    a[0] = static_cast<std::uint8_t>(a[0] + kServerOffset);
    return std::optional<Bytes>(a);
  };
  std::mutex mu;
  std::vector<Bytes> commands;  // COM-PORT-OPTION payloads received
  Bytes data;                   // data received
  std::atomic<bool> stop{false};
  std::thread thread;

  ScriptedServer() {
    listener.reset(::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0));
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t len = sizeof a;
    REQUIRE(::bind(listener.get(), reinterpret_cast<sockaddr*>(&a), sizeof a) == 0);
    REQUIRE(::listen(listener.get(), 2) == 0);
    ::getsockname(listener.get(), reinterpret_cast<sockaddr*>(&a), &len);
    port = ntohs(a.sin_port);
  }
  void start() {
    thread = std::thread([this] { run(); });
  }
  ~ScriptedServer() {
    stop = true;
    if (thread.joinable()) thread.join();
  }
  std::vector<Bytes> got_commands() {
    std::lock_guard<std::mutex> l(mu);
    return commands;
  }

 private:
  static void send_all(int fd, const Bytes& b) {
    if (!b.empty()) (void)::send(fd, b.data(), b.size(), MSG_NOSIGNAL);
  }
  void run() {
    pollfd lp{listener.get(), POLLIN, 0};
    if (::poll(&lp, 1, 3000) != 1) return;
    UniqueFd c(::accept4(listener.get(), nullptr, nullptr, SOCK_CLOEXEC));
    if (!c) return;
    Decoder dec;
    while (!stop) {
      pollfd p{c.get(), POLLIN, 0};
      if (::poll(&p, 1, 20) != 1) continue;
      std::uint8_t buf[512];
      const ssize_t n = ::recv(c.get(), buf, sizeof buf, 0);
      if (n <= 0) return;
      if (silent) continue;
      Bytes in;
      std::vector<Event> events;
      dec.feed(ByteView(buf, static_cast<std::size_t>(n)), in, events);
      for (const Event& e : events) {
        if (e.kind == Event::Kind::negotiation && e.verb == kWILL && e.option == kComPort) {
          send_all(c.get(), encode_negotiation(accept_com_port ? kDO : kDONT, kComPort));
        } else if (e.kind == Event::Kind::negotiation && e.verb == kWILL) {
          send_all(c.get(), encode_negotiation(kDO, e.option));
        } else if (e.kind == Event::Kind::negotiation && e.verb == kDO) {
          send_all(c.get(), encode_negotiation(kWILL, e.option));
        } else if (e.kind == Event::Kind::subnegotiation && e.option == kComPort) {
          {
            std::lock_guard<std::mutex> l(mu);
            commands.push_back(e.payload);
          }
          if (auto a = confirm(e.payload)) {
            Bytes out{kIAC, kSB, kComPort};
            const Bytes v = escape_data(*a);
            out.insert(out.end(), v.begin(), v.end());
            out.push_back(kIAC);
            out.push_back(kSE);
            send_all(c.get(), out);
          }
        }
      }
      if (!in.empty()) {
        {
          std::lock_guard<std::mutex> l(mu);
          data.insert(data.end(), in.begin(), in.end());
        }
        // The echo, with NOTIFY-MODEMSTATE split between two segments after its first byte.
        const Bytes esc = escape_data(in);
        Bytes first(esc.begin(), esc.begin() + 1);
        const Bytes notify = hex("FF FA 2C 6B 30 FF F0");
        first.insert(first.end(), notify.begin(), notify.begin() + 3);
        send_all(c.get(), first);
        std::this_thread::sleep_for(5ms);
        Bytes second(notify.begin() + 3, notify.end());
        second.insert(second.end(), esc.begin() + 1, esc.end());
        send_all(c.get(), second);
      }
    }
  }
};

std::string where(const ScriptedServer& s) { return "127.0.0.1:" + std::to_string(s.port); }

SerialSettings line(unsigned baud, Parity p = Parity::none, unsigned stop = 1) {
  SerialSettings s;
  s.baud = baud;
  s.parity = p;
  s.stop_bits = stop;
  return s;
}

}  // namespace

TEST_CASE("rfc2217: opens, sets the line, moves data with 0xFF and notifications, purges",
          "[rfc2217][transport]") {
  ScriptedServer server;
  server.start();
  auto t = open_rfc2217("127.0.0.1", server.port, line(57600), 2000ms);
  REQUIRE(t.ok());
  auto& link = **t;
  CHECK(link.describe() == "rfc2217 " + where(server) + " 57600 8N1");
  CHECK(link.byte_time_us() == Approx(1e6 * 10 / 57600));
  const auto cmds = server.got_commands();
  REQUIRE(cmds.size() == 5);
  CHECK(cmds[0] == hex("01 00 00 E1 00"));  // SET-BAUDRATE 57600
  CHECK(cmds[1] == hex("02 08"));           // SET-DATASIZE 8
  CHECK(cmds[2] == hex("03 01"));           // SET-PARITY NONE
  CHECK(cmds[3] == hex("04 01"));           // SET-STOPSIZE 1
  CHECK(cmds[4] == hex("05 01"));           // SET-CONTROL no flow control

  const Bytes telegram = hex("01 11 05 02 FF 03 A2 13 04");
  REQUIRE(link.write(telegram).ok());
  CHECK(test::read_n(link, telegram.size()) == telegram);
  {
    std::lock_guard<std::mutex> l(server.mu);
    CHECK(server.data == telegram);
  }

  link.discard_input();
  std::this_thread::sleep_for(50ms);
  CHECK(server.got_commands().back() == hex("0C 01"));  // PURGE-DATA receive buffer

  REQUIRE(link.reconfigure(line(19200, Parity::even, 2)).ok());
  CHECK(link.describe() == "rfc2217 " + where(server) + " 19200 8E2");
  CHECK(link.byte_time_us() == Approx(1e6 * 12 / 19200));
  const auto after = server.got_commands();
  REQUIRE(after.size() == 11);
  CHECK(after[6] == hex("01 00 00 4B 00"));
  CHECK(after[8] == hex("03 03"));
  CHECK(after[9] == hex("04 02"));
  // A rate outside the S1 table is refused before anything is sent.
  auto bad = link.reconfigure(line(12345));
  REQUIRE_FALSE(bad.ok());
  CHECK(bad.error().message.rfind("unsupported baud rate 12345", 0) == 0);
  CHECK(server.got_commands().size() == 11);
}

TEST_CASE("rfc2217: a server confirming another rate than asked is refused, naming both",
          "[rfc2217][transport]") {
  ScriptedServer server;
  server.confirm = [](const Bytes& p) {
    Bytes a = p;
    a[0] = static_cast<std::uint8_t>(a[0] + kServerOffset);
    if (p[0] == 1) a = hex("65 00 00 25 80");  // 9600
    return std::optional<Bytes>(a);
  };
  server.start();
  auto t = open_rfc2217("127.0.0.1", server.port, line(57600), 2000ms);
  REQUIRE_FALSE(t.ok());
  CHECK(t.error().code == make_error_code(Errc::unexpected_response));
  CHECK(t.error().message == "rfc2217 " + where(server) +
                                 " 57600 8N1: the server confirmed SET-BAUDRATE 9600, asked 57600");
}

TEST_CASE("rfc2217: a missing confirmation is a timeout naming the option",
          "[rfc2217][transport]") {
  ScriptedServer server;
  server.confirm = [](const Bytes& p) -> std::optional<Bytes> {
    if (p[0] == 4) return std::nullopt;  // SET-STOPSIZE never confirmed
    Bytes a = p;
    a[0] = static_cast<std::uint8_t>(a[0] + kServerOffset);
    return a;
  };
  server.start();
  auto t = open_rfc2217("127.0.0.1", server.port, line(57600), 300ms);
  REQUIRE_FALSE(t.ok());
  CHECK(t.error().code == make_error_code(Errc::timeout));
  CHECK(t.error().message ==
        "rfc2217 " + where(server) +
            " 57600 8N1: no confirmation of SET-STOPSIZE 1 stop bit (code 104) from the server "
            "within 300 ms");
}

TEST_CASE("rfc2217: a server refusing COM-PORT-OPTION, and a silent raw TCP port",
          "[rfc2217][transport]") {
  {
    ScriptedServer server;
    server.accept_com_port = false;
    server.start();
    auto t = open_rfc2217("127.0.0.1", server.port, line(57600), 1000ms);
    REQUIRE_FALSE(t.ok());
    CHECK(t.error().code == make_error_code(Errc::not_supported));
    CHECK(t.error().message ==
          "rfc2217 " + where(server) +
              " 57600 8N1: the server refused COM-PORT-OPTION (IAC DONT 44): it does not speak "
              "RFC 2217, so the serial line's settings cannot be set from here");
  }
  {
    ScriptedServer server;
    server.silent = true;
    server.start();
    auto t = open_rfc2217("127.0.0.1", server.port, line(57600), 300ms);
    REQUIRE_FALSE(t.ok());
    CHECK(t.error().code == make_error_code(Errc::timeout));
    CHECK(t.error().message == "rfc2217 " + where(server) +
                                   " 57600 8N1: the server did not accept COM-PORT-OPTION (no "
                                   "IAC DO 44) within 300 ms; is it a raw TCP port rather than "
                                   "RFC 2217?");
  }
  auto bad = open_rfc2217("127.0.0.1", 0, line(57600), 300ms);
  REQUIRE_FALSE(bad.ok());
  CHECK(bad.error().message == "rfc2217 127.0.0.1:0: port 0 is not a valid port");
  auto rate = open_rfc2217("127.0.0.1", 4001, line(1200), 300ms);
  REQUIRE_FALSE(rate.ok());
  CHECK(rate.error().message.rfind("unsupported baud rate 1200", 0) == 0);
}

// ------------------------------------------------------------- real ser2net

namespace {

// Two simulated drives on one pseudo-terminal line: 11h listening at 57600 Bd,
// 12h at 19200 Bd. Each hears only a master whose line (the pty's termios,
// which ser2net sets on RFC 2217 requests) runs at its own rate.
struct TwoRateLine {
  sim::Drive fast, slow;
  std::string slave;
  UniqueFd slave_fd;  // held open: without it the master reads EIO between ser2net's opens
  std::unique_ptr<FdTransport> master;
  std::atomic<bool> stop{false};
  std::thread server;

  static sim::DriveState at(std::uint8_t id, unsigned baud) {
    auto s = test::load_fixture("manual-drive.json");
    s.macid = id;
    s.link.baud = baud;
    return s;
  }
  TwoRateLine() : fast(at(0x11, 57600)), slow(at(0x12, 19200)) {
    auto pty = open_pty();
    REQUIRE(pty.ok());
    slave = pty->slave_path;
    slave_fd = std::move(pty->slave);
    master = std::make_unique<FdTransport>(std::move(pty->master), "pty " + slave);
    server = std::thread([this] {
      sim::ServeOptions o;
      o.real_time = true;
      o.poll = Millis(10);
      o.should_stop = [this] { return stop.load(); };
      o.master_baud = [this] { return line_baud(master->fd()); };
      (void)sim::serve_bus({&fast, &slow}, *master, o);
    });
  }
  ~TwoRateLine() {
    stop = true;
    server.join();
  }
};

// Reads one frame (or nothing) within `ms`.
Bytes read_frame(Transport& t, int ms) {
  Bytes out;
  codec::StreamDecoder dec;
  const auto until = Clock::now() + Millis(ms);
  while (Clock::now() < until) {
    auto r = t.read_some(Millis(20));
    REQUIRE(r.ok());
    out.insert(out.end(), r->begin(), r->end());
    dec.feed(*r);
    if (auto f = dec.next(); f && f->ok()) return out;
  }
  return out;
}

// Skips (prints why) when ser2net is missing, unless LMCFG_REQUIRE_SER2NET=1.
bool have_ser2net() {
  const std::string why = test::ser2net_missing();
  if (why.empty()) return true;
  if (test::ser2net_required()) FAIL(why + ", and LMCFG_REQUIRE_SER2NET=1");
  WARN("SKIP: " << why);
  return false;
}

// LinRS §10.1: read ROM of 13A2h, to drive `id`, and the manual's answer.
Bytes read_rom_13a2(std::uint8_t id) {
  Bytes b = hex("01 11 05 02 00 05 A2 13 04");
  b[1] = id;
  return b;
}
Bytes answer_13a2(std::uint8_t id) {
  Bytes b = hex("01 11 0A 02 50 00 00 A2 13 0A 00 00 00 04");
  b[1] = id;
  return b;
}

}  // namespace

TEST_CASE(
    "rfc2217: LinRS exchanges (seed003 §10.1) through ser2net at 57600 Bd while its port is "
    "configured at 9600, then at 19200 after reconfigure",
    "[rfc2217][transport][ser2net]") {
  if (!have_ser2net()) return;
  TwoRateLine bus;
  test::Ser2netRig rig(bus.slave, 9600);
  REQUIRE(rig.error == "");
  auto t = open_rfc2217("127.0.0.1", rig.port, line(57600), 3000ms);
  REQUIRE(t.ok());
  auto& link = **t;
  CHECK(link.describe() == "rfc2217 127.0.0.1:" + std::to_string(rig.port) + " 57600 8N1");
  // ser2net applied the rate to the pty's line settings.
  CHECK(line_baud(bus.master->fd()) == 57600u);

  REQUIRE(link.write(read_rom_13a2(0x11)).ok());
  CHECK(read_frame(link, 2000) == answer_13a2(0x11));
  REQUIRE(link.write(read_rom_13a2(0x12)).ok());  // listens at 19200: hears nothing
  CHECK(read_frame(link, 300).empty());

  REQUIRE(link.reconfigure(line(19200)).ok());
  CHECK(link.describe() == "rfc2217 127.0.0.1:" + std::to_string(rig.port) + " 19200 8N1");
  CHECK(line_baud(bus.master->fd()) == 19200u);
  link.discard_input();
  REQUIRE(link.write(read_rom_13a2(0x12)).ok());
  CHECK(read_frame(link, 2000) == answer_13a2(0x12));
  REQUIRE(link.write(read_rom_13a2(0x11)).ok());
  CHECK(read_frame(link, 300).empty());

  // Many exchanges through the client, with purges between them.
  client::ClientOptions o;
  o.id = 0x12;
  client::LinrsClient c(link, o);
  for (int i = 0; i < 20; ++i) {
    auto v = c.read_rom(0x13A2);
    REQUIRE(v.ok());
    CHECK(*v == 0x0000000Au);
    link.discard_input();
  }
}

TEST_CASE("rfc2217: through ser2net at a rate no drive listens at, the client times out",
          "[rfc2217][transport][ser2net]") {
  if (!have_ser2net()) return;
  TwoRateLine bus;
  test::Ser2netRig rig(bus.slave, 57600);
  REQUIRE(rig.error == "");
  auto t = open_rfc2217("127.0.0.1", rig.port, line(38400), 3000ms);
  REQUIRE(t.ok());
  CHECK(line_baud(bus.master->fd()) == 38400u);
  client::ClientOptions o;
  o.id = 0x11;
  o.timeout = Millis(150);
  o.read_retries = 1;
  client::LinrsClient c(**t, o);
  auto v = c.read_rom(0x13A2);
  REQUIRE_FALSE(v.ok());
  CHECK(v.error().code == make_error_code(Errc::timeout));
  CHECK(v.error().message ==
        "no answer from drive 11h within 150 ms to ID 11h parameter configuration (main 05h sub "
        "00h), 2 data byte(s) (after 2 attempts)");
}

}  // namespace transport_test_rfc2217
