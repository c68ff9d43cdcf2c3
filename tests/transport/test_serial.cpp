// Serial transport through a real pseudo-terminal, FdTransport on the master.
#include <poll.h>
#include <sys/ioctl.h>
#include <termios.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include "transport/pty.hpp"
#include "transport/transport.hpp"
#include "transport_test_support.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace transport_test_serial {

using namespace lmcfg;
using namespace lmcfg::transport;
using namespace std::chrono_literals;
using test::make_pty;

namespace {

speed_t expected_speed(unsigned baud) {
  switch (baud) {
    case 4800:
      return B4800;
    case 9600:
      return B9600;
    case 19200:
      return B19200;
    case 38400:
      return B38400;
    case 57600:
      return B57600;
    default:
      return B115200;
  }
}

using test::read_n;

Bytes all_byte_values() {
  Bytes b;
  for (unsigned i = 0; i < 256; ++i) b.push_back(static_cast<std::uint8_t>(i));
  return b;
}

}  // namespace

TEST_CASE("serial settings are applied to the terminal", "[transport]") {
  auto pty = make_pty();
  for (const unsigned baud : kSerialBaudRates) {
    for (const Parity parity : {Parity::none, Parity::even, Parity::odd}) {
      for (const unsigned stop : {1u, 2u}) {
        const SerialSettings s{pty.slave_path, baud, parity, stop};
        INFO(format_settings(s));
        auto r = open_serial(s);
        REQUIRE(r.ok());
        CHECK((*r)->describe() == "serial " + pty.slave_path + " " + format_settings(s));
        CHECK((*r)->byte_time_us() == Approx(1e6 * bits_per_byte(s) / baud));

        termios t{};
        REQUIRE(::tcgetattr(pty.slave.get(), &t) == 0);
        CHECK(::cfgetispeed(&t) == expected_speed(baud));
        CHECK(::cfgetospeed(&t) == expected_speed(baud));
        CHECK((t.c_cflag & CSIZE) == CS8);
        // Linux ptys clear PARENB whatever is asked (pty_set_termios); PARODD stays.
        CHECK(is_pty_slave(pty.slave.get()));
        CHECK(((t.c_cflag & PARODD) != 0) == (parity == Parity::odd));
        // What open_serial asks for, parity bit included:
        termios want = t;
        make_serial_termios(want, s);
        CHECK(((want.c_cflag & PARENB) != 0) == (parity != Parity::none));
        CHECK(((want.c_cflag & PARODD) != 0) == (parity == Parity::odd));
        CHECK(want.c_cflag == (t.c_cflag | (parity != Parity::none ? PARENB : 0u)));
        CHECK(((t.c_cflag & CSTOPB) != 0) == (stop == 2));
        CHECK((t.c_cflag & (CLOCAL | CREAD)) == (CLOCAL | CREAD));
        CHECK((t.c_cflag & CRTSCTS) == 0);
        CHECK((t.c_iflag & (IXON | IXOFF | IXANY | ICRNL | INLCR | IGNCR | ISTRIP)) == 0);
        CHECK((t.c_lflag & (ICANON | ECHO | ISIG | IEXTEN)) == 0);
        CHECK((t.c_oflag & OPOST) == 0);
        CHECK(t.c_cc[VMIN] == 0);
        CHECK(t.c_cc[VTIME] == 0);
#ifdef TIOCGEXCL
        int excl = 0;
        REQUIRE(::ioctl(pty.slave.get(), TIOCGEXCL, &excl) == 0);
        CHECK(excl == 1);
#endif
      }
    }
  }
#ifdef TIOCGEXCL
  int excl = 1;
  REQUIRE(::ioctl(pty.slave.get(), TIOCGEXCL, &excl) == 0);
  CHECK(excl == 0);  // released when the transport closed
#endif
}

TEST_CASE("serial port is opened for exclusive use", "[transport]") {
  auto pty = make_pty();
  auto first = open_serial({pty.slave_path, 57600, Parity::none, 1});
  REQUIRE(first.ok());
  if (::geteuid() == 0) {
    WARN(
        "running as root: TIOCEXCL does not refuse a second open (checked with TIOCGEXCL instead)");
    return;
  }
  auto second = open_serial({pty.slave_path, 57600, Parity::none, 1});
  REQUIRE_FALSE(second.ok());
  CHECK(second.error().code == Errc::io_error);
  CHECK(second.error().message == "cannot open serial port " + pty.slave_path +
                                      ": Device or resource busy; another program has it open "
                                      "(find it with fuser " +
                                      pty.slave_path + ")");
}

TEST_CASE("serial moves bytes both ways through a pty", "[transport]") {
  auto pty = make_pty();
  auto serial = open_serial({pty.slave_path, 115200, Parity::even, 1});
  REQUIRE(serial.ok());
  FdTransport master(std::move(pty.master), "pty master");
  const Bytes payload = all_byte_values();  // raw: no CR/LF mapping, XON/XOFF pass through

  REQUIRE((*serial)->write(payload).ok());
  CHECK(read_n(master, payload.size()) == payload);

  REQUIRE(master.write(payload).ok());
  CHECK(read_n(**serial, payload.size()) == payload);

  // Nothing echoed back to the master.
  auto echo = master.read_some(50ms);
  REQUIRE(echo.ok());
  CHECK(echo->empty());
}

TEST_CASE("serial read_some times out with no bytes", "[transport]") {
  auto pty = make_pty();
  auto serial = open_serial({pty.slave_path, 9600, Parity::none, 2});
  REQUIRE(serial.ok());
  const auto t0 = Clock::now();
  auto r = (*serial)->read_some(150ms);
  const auto elapsed = Clock::now() - t0;
  REQUIRE(r.ok());
  CHECK(r->empty());
  CHECK(elapsed >= 145ms);
  CHECK(elapsed < 1500ms);

  auto zero = (*serial)->read_some(0ms);
  REQUIRE(zero.ok());
  CHECK(zero->empty());
}

TEST_CASE("serial discard_input drops received bytes", "[transport]") {
  auto pty = make_pty();
  auto serial = open_serial({pty.slave_path, 57600, Parity::none, 1});
  REQUIRE(serial.ok());
  FdTransport master(std::move(pty.master), "pty master");
  REQUIRE(master.write(Bytes{0x01, 0x11, 0x05, 0x02, 0x00, 0x03, 0x04}).ok());
  pollfd pfd{pty.slave.get(), POLLIN, 0};
  REQUIRE(::poll(&pfd, 1, 2000) == 1);
  std::this_thread::sleep_for(20ms);
  (*serial)->discard_input();
  auto r = (*serial)->read_some(100ms);
  REQUIRE(r.ok());
  CHECK(r->empty());
}

TEST_CASE("closing the pty master ends the serial link without a hang", "[transport]") {
  auto pty = make_pty();
  auto serial = open_serial({pty.slave_path, 57600, Parity::none, 1});
  REQUIRE(serial.ok());
  pty.master.reset();
  const auto t0 = Clock::now();
  auto r = (*serial)->read_some(3000ms);
  CHECK(Clock::now() - t0 < 1500ms);
  REQUIRE_FALSE(r.ok());
  CHECK((r.error().code == Errc::link_closed || r.error().code == Errc::io_error));
  CHECK(r.error().message.find(pty.slave_path) != std::string::npos);

  auto w = (*serial)->write(Bytes{0x01, 0x02});
  REQUIRE_FALSE(w.ok());
  CHECK((w.error().code == Errc::link_closed || w.error().code == Errc::io_error));
}

TEST_CASE("serial settings validation messages", "[transport]") {
  SerialSettings s{"/dev/ttyUSB0", 57600, Parity::none, 1};
  CHECK(validate(s).ok());
  for (const unsigned b : kSerialBaudRates) {
    s.baud = b;
    CHECK(validate(s).ok());
  }

  s.baud = 12345;
  auto r = validate(s);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == Errc::invalid_argument);
  CHECK(r.error().message ==
        "unsupported baud rate 12345 (allowed: 4800, 9600, 19200, 38400, 57600, 115200)");
  s.baud = 230400;
  CHECK(validate(s).error().message ==
        "unsupported baud rate 230400 (allowed: 4800, 9600, 19200, 38400, 57600, 115200)");

  s.baud = 57600;
  s.stop_bits = 3;
  CHECK(validate(s).error().message == "unsupported stop bits 3 (allowed: 1, 2)");
  s.stop_bits = 0;
  CHECK(validate(s).error().message == "unsupported stop bits 0 (allowed: 1, 2)");

  s.stop_bits = 1;
  s.parity = static_cast<Parity>(7);
  CHECK(validate(s).error().message == "unsupported parity value 7 (allowed: none, even, odd)");

  // open_serial validates before touching the device.
  auto o = open_serial({"/dev/ttyUSB0", 1200, Parity::none, 1});
  REQUIRE_FALSE(o.ok());
  CHECK(o.error().message ==
        "unsupported baud rate 1200 (allowed: 4800, 9600, 19200, 38400, 57600, 115200)");

  auto empty = open_serial({"", 57600, Parity::none, 1});
  REQUIRE_FALSE(empty.ok());
  CHECK(empty.error().code == Errc::invalid_argument);
  CHECK(empty.error().message == "serial device path is empty");
}

TEST_CASE("serial open errors name the device", "[transport]") {
  auto missing = open_serial({"/dev/lmcfg-no-such-tty", 57600, Parity::none, 1});
  REQUIRE_FALSE(missing.ok());
  CHECK(missing.error().code == Errc::not_found);
  CHECK(missing.error().message ==
        "cannot open serial port /dev/lmcfg-no-such-tty: No such file or directory; check --port "
        "and that the adapter is plugged in (ls /dev/ttyUSB* /dev/ttyACM* /dev/serial/by-id/)");

  auto not_tty = open_serial({"/dev/null", 57600, Parity::none, 1});
  REQUIRE_FALSE(not_tty.ok());
  CHECK(not_tty.error().code == Errc::invalid_argument);
  CHECK(not_tty.error().message == "cannot use /dev/null as a serial port: not a terminal device");
}

TEST_CASE("bits per byte and settings text", "[transport]") {
  CHECK(bits_per_byte({"x", 57600, Parity::none, 1}) == 10);
  CHECK(bits_per_byte({"x", 57600, Parity::even, 1}) == 11);
  CHECK(bits_per_byte({"x", 57600, Parity::none, 2}) == 11);
  CHECK(bits_per_byte({"x", 57600, Parity::odd, 2}) == 12);
  CHECK(format_settings({"x", 57600, Parity::none, 1}) == "57600 8N1");
  CHECK(format_settings({"x", 19200, Parity::even, 2}) == "19200 8E2");
  CHECK(format_settings({"x", 4800, Parity::odd, 1}) == "4800 8O1");
}

TEST_CASE("low latency: a pty has no TIOCSSERIAL, the open degrades gracefully",
          "[transport][latency]") {
  auto pty = make_pty();
  LowLatencyReport rep;
  auto serial = open_serial({pty.slave_path, 115200, Parity::none, 1}, &rep);
  REQUIRE(serial.ok());
  CHECK_FALSE(rep.ioctl_supported);
  CHECK_FALSE(rep.low_latency_set);
  CHECK(rep.ioctl_error == "TIOCGSERIAL: Inappropriate ioctl for device");
  CHECK_FALSE(rep.latency_timer_ms.has_value());
  CHECK(rep.advice.empty());
  CHECK((*serial)->receive_latency_ms() == 0.0);
}

TEST_CASE("low latency: the adapter's latency_timer is read from sysfs and a slow one is reported",
          "[transport][latency]") {
  namespace fs = std::filesystem;
  auto pty = make_pty();
  const fs::path root = fs::temp_directory_path() / ("lmcfg-sysfs-" + std::to_string(::getpid()));
  const std::string name = fs::path(pty.slave_path).filename().string();
  fs::create_directories(root / "class/tty" / name / "device");
  const std::string timer = (root / "class/tty" / name / "device/latency_timer").string();
  CHECK(latency_timer_path(pty.slave_path, root.string()) == timer);
  std::ofstream(timer) << "16\n";
  auto slow = request_low_latency(pty.slave.get(), pty.slave_path, root.string());
  REQUIRE(slow.latency_timer_ms == 16);
  CHECK(slow.sysfs_path == timer);
  CHECK(slow.advice ==
        pty.slave_path + ": the USB serial adapter holds received bytes for 16 ms (" + timer +
            "), so every exchange takes that much longer; set it to 1 ms with the udev rule in "
            "docs/transport.md (ACTION==\"add\", SUBSYSTEM==\"usb-serial\", DRIVER==\"ftdi_sio\", "
            "ATTR{latency_timer}=\"1\") or, as root: echo 1 > " +
            timer);
  std::ofstream(timer, std::ios::trunc) << "1\n";
  auto fast = request_low_latency(pty.slave.get(), pty.slave_path, root.string());
  CHECK(fast.latency_timer_ms == 1);
  CHECK(fast.advice.empty());
  fs::remove_all(root);
}

}  // namespace transport_test_serial
