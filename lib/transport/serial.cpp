// Serial ports through POSIX termios: raw, 8 data bits, no flow control.
#include <errno.h>
#include <fcntl.h>
#include <linux/serial.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "transport/port_lock.hpp"
#include "transport/ports.hpp"
#include "transport/pty.hpp"

namespace lmcfg::transport {

namespace {

speed_t speed_constant(unsigned baud) {
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
    case 115200:
      return B115200;
    default:
      return B0;
  }
}

}  // namespace

std::optional<unsigned> line_baud(int fd) {
  termios tio{};
  if (::tcgetattr(fd, &tio) != 0) return std::nullopt;
  const speed_t speed = ::cfgetospeed(&tio);
  for (const unsigned b : kSerialBaudRates)
    if (speed_constant(b) == speed) return b;
  return std::nullopt;
}

void make_serial_termios(termios& tio, const SerialSettings& s) {
  ::cfmakeraw(&tio);
  tio.c_iflag &= ~static_cast<tcflag_t>(IXON | IXOFF | IXANY | INPCK);
  tio.c_cflag &= ~static_cast<tcflag_t>(CSIZE | PARENB | PARODD | CSTOPB | CRTSCTS | HUPCL);
  tio.c_cflag |= CS8 | CLOCAL | CREAD;
  if (s.parity == Parity::even) tio.c_cflag |= PARENB;
  if (s.parity == Parity::odd) tio.c_cflag |= PARENB | PARODD;
  if (s.stop_bits == 2) tio.c_cflag |= CSTOPB;
  tio.c_cc[VMIN] = 0;
  tio.c_cc[VTIME] = 0;
  const speed_t speed = speed_constant(s.baud);
  ::cfsetispeed(&tio, speed);
  ::cfsetospeed(&tio, speed);
}

bool is_pty_slave(int fd) {
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISCHR(st.st_mode)) return false;
  const unsigned maj = major(st.st_rdev);
  return maj >= 136 &&
         maj <= 143;  // UNIX98_PTY_SLAVE_MAJOR .. + 7 (Documentation/admin-guide/devices.txt)
}

std::vector<std::string> list_serial_ports() {
  std::vector<std::string> ports;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator("/dev/serial/by-id", ec))
    ports.push_back(e.path().string());
  if (ports.empty()) {
    for (const auto& e : std::filesystem::directory_iterator("/dev", ec)) {
      const std::string name = e.path().filename().string();
      if (name.rfind("ttyUSB", 0) == 0 || name.rfind("ttyACM", 0) == 0)
        ports.push_back(e.path().string());
    }
  }
  std::sort(ports.begin(), ports.end());
  return ports;
}

std::string latency_timer_path(const std::string& device, const std::string& sysfs_root) {
  std::error_code ec;
  auto real = std::filesystem::canonical(device, ec);  // /dev/serial/by-id/... -> /dev/ttyUSB0
  const std::string name = (ec ? std::filesystem::path(device) : real).filename().string();
  return sysfs_root + "/class/tty/" + name + "/device/latency_timer";
}

LowLatencyReport request_low_latency(int fd, const std::string& device,
                                     const std::string& sysfs_root) {
  LowLatencyReport r;
  serial_struct ss{};
  if (::ioctl(fd, TIOCGSERIAL, &ss) != 0) {
    r.ioctl_error = std::string("TIOCGSERIAL: ") + std::strerror(errno);
  } else {
    r.ioctl_supported = true;
    if ((ss.flags & ASYNC_LOW_LATENCY) == 0) {
      ss.flags |= ASYNC_LOW_LATENCY;
      if (::ioctl(fd, TIOCSSERIAL, &ss) != 0)
        r.ioctl_error = std::string("TIOCSSERIAL: ") + std::strerror(errno);
    }
    serial_struct got{};
    r.low_latency_set = ::ioctl(fd, TIOCGSERIAL, &got) == 0 && (got.flags & ASYNC_LOW_LATENCY) != 0;
  }
  const std::string path = latency_timer_path(device, sysfs_root);
  std::ifstream in(path);
  int ms = 0;
  if (in && (in >> ms)) {
    r.sysfs_path = path;
    r.latency_timer_ms = ms;
    if (ms > 2) {
      r.advice = device + ": the USB serial adapter holds received bytes for " +
                 std::to_string(ms) + " ms (" + path +
                 "), so every exchange takes that much longer; set it to 1 ms with the udev "
                 "rule in docs/transport.md (ACTION==\"add\", SUBSYSTEM==\"usb-serial\", "
                 "DRIVER==\"ftdi_sio\", ATTR{latency_timer}=\"1\") or, as root: echo 1 > " +
                 path;
    }
  }
  return r;
}

namespace {

std::string serial_description(const SerialSettings& s) {
  return "serial " + s.device + " " + format_settings(s);
}

// Applies `s` to an open terminal and reads the settings back: tcsetattr
// succeeds when any one change was applied.
Result<void> apply_line_settings(int f, const SerialSettings& s, const std::string& desc) {
  auto fail = [&](const std::string& what, int err) {
    return Error(Errc::io_error, desc + ": " + what + ": " + std::strerror(err));
  };
  termios tio{};
  if (::tcgetattr(f, &tio) != 0) return fail("tcgetattr failed", errno);
  make_serial_termios(tio, s);
  if (::tcsetattr(f, TCSANOW, &tio) != 0) return fail("tcsetattr failed", errno);
  termios got{};
  if (::tcgetattr(f, &got) != 0) return fail("tcgetattr failed", errno);
  tcflag_t mask = CSIZE | PARENB | PARODD | CSTOPB | CRTSCTS | CLOCAL | CREAD;
  if (is_pty_slave(f)) mask &= ~static_cast<tcflag_t>(PARENB);  // no wire, no parity bit
  const speed_t speed = speed_constant(s.baud);
  if (::cfgetospeed(&got) != speed || ::cfgetispeed(&got) != speed ||
      (got.c_cflag & mask) != (tio.c_cflag & mask)) {
    return Error(Errc::io_error, desc + ": the device did not accept the line settings");
  }
  ::tcflush(f, TCIOFLUSH);  // drop whatever arrived before the settings applied
  return {};
}

// Removes the exclusive-use flag before the descriptor is closed, so the next
// open of the same device (also by this process) is not refused.
class SerialTransport final : public FdTransport {
 public:
  SerialTransport(UniqueFd fd, SerialSettings s, std::unique_ptr<PortLock> lock)
      : FdTransport(std::move(fd), serial_description(s),
                    1e6 * bits_per_byte(s) / static_cast<double>(s.baud)),
        settings_(std::move(s)),
        lock_(std::move(lock)) {}
  void set_receive_latency_ms(double ms) { latency_ms_ = ms; }
  double receive_latency_ms() const override { return latency_ms_; }
  ~SerialTransport() override {
    if (fd() >= 0) ::ioctl(fd(), TIOCNXCL);
  }

  Result<void> reconfigure(const SerialSettings& in) override {
    SerialSettings s = in;
    s.device = settings_.device;
    LMCFG_TRY(validate(s));
    LMCFG_TRY(apply_line_settings(fd(), s, serial_description(s)));
    settings_ = s;
    set_line_description(serial_description(s),
                         1e6 * bits_per_byte(s) / static_cast<double>(s.baud));
    return {};
  }

 private:
  SerialSettings settings_;
  double latency_ms_ = 0.0;
  // Destroyed before the descriptor closes: the lock-info file goes first,
  // then close(2) releases the flock.
  std::unique_ptr<PortLock> lock_;
};

}  // namespace

Result<std::unique_ptr<Transport>> open_serial(const SerialSettings& s, LowLatencyReport* report,
                                               const PortClaim& claim) {
  if (s.device.empty()) return Error(Errc::invalid_argument, "serial device path is empty");
  LMCFG_TRY(validate(s));
  // O_NONBLOCK so the open does not wait for carrier; it stays set (reads poll).
  UniqueFd fd(::open(s.device.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC));
  if (!fd) {
    const int err = errno;
    if (err == ENOENT || err == ENODEV || err == ENXIO)
      return Error(Errc::not_found,
                   "cannot open serial port " + s.device + ": " + std::strerror(err) +
                       "; check --port and that the adapter is plugged in (ls /dev/ttyUSB* "
                       "/dev/ttyACM* /dev/serial/by-id/)");
    if (err == EACCES || err == EPERM)
      return Error(Errc::io_error,
                   "cannot open serial port " + s.device + ": " + std::strerror(err) +
                       "; your user may not use serial ports: add it to the group that owns " +
                       s.device +
                       " (usually dialout: sudo usermod -aG dialout $USER, then log "
                       "in again)");
    // TIOCEXCL of another opener refuses the open (except to root): say who,
    // when that opener recorded itself.
    if (err == EBUSY && port_holder(s.device))
      return Error(Errc::io_error, port_in_use_message(s.device));
    if (err == EBUSY)
      return Error(Errc::io_error,
                   "cannot open serial port " + s.device + ": " + std::strerror(err) +
                       "; another program has it open (find it with fuser " + s.device + ")");
    return Error(Errc::io_error, "cannot open serial port " + s.device + ": " + std::strerror(err));
  }
  if (::isatty(fd.get()) != 1)
    return Error(Errc::invalid_argument,
                 "cannot use " + s.device + " as a serial port: not a terminal device");
  // The lock before TIOCEXCL and before any setting: a port in use is left
  // exactly as its holder set it, and nothing is sent on it.
  LMCFG_ASSIGN_OR_RETURN(auto lock, PortLock::take(fd.get(), s.device, claim));
  if (::ioctl(fd.get(), TIOCEXCL) != 0)
    return Error(Errc::io_error,
                 serial_description(s) +
                     ": cannot get exclusive access (TIOCEXCL): " + std::strerror(errno));
  // From here on the fd is owned by the transport, whose destructor clears TIOCEXCL.
  auto t = std::make_unique<SerialTransport>(std::move(fd), s, std::move(lock));
  LMCFG_TRY(apply_line_settings(t->fd(), s, serial_description(s)));
  LowLatencyReport lat = request_low_latency(t->fd(), s.device);
  if (lat.latency_timer_ms) t->set_receive_latency_ms(*lat.latency_timer_ms);
  if (report) *report = std::move(lat);
  return std::unique_ptr<Transport>(std::move(t));
}

}  // namespace lmcfg::transport
