// Serial ports on Windows: COM1..COM256 through the Win32 communications API
// (CreateFileW on \\.\COMn, a DCB for rate, parity and stop bits, COMMTIMEOUTS
// for the answer deadlines). The same interface and messages as serial.cpp.
#include <algorithm>
#include <cctype>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "transport/port_lock.hpp"
#include "transport/ports.hpp"
#include "transport/win32_util.hpp"

namespace lmcfg::transport {

namespace {

using win32::UniqueHandle;

std::string serial_description(const SerialSettings& s) {
  return "serial " + s.device + " " + format_settings(s);
}

BYTE parity_code(Parity p) {
  return p == Parity::even ? EVENPARITY : p == Parity::odd ? ODDPARITY : NOPARITY;
}

// Applies `s` to an open port: 8 data bits, no flow control (LinRS has no
// handshake lines), DTR and RTS on as a USB-RS485 adapter expects.
Result<void> apply_line_settings(HANDLE h, const SerialSettings& s, const std::string& desc) {
  DCB dcb{};
  dcb.DCBlength = sizeof dcb;
  if (!::GetCommState(h, &dcb))
    return Error(Errc::io_error,
                 desc + ": GetCommState failed: " + win32::error_text(::GetLastError()));
  dcb.BaudRate = s.baud;
  dcb.ByteSize = 8;
  dcb.Parity = parity_code(s.parity);
  dcb.StopBits = s.stop_bits == 2 ? TWOSTOPBITS : ONESTOPBIT;
  dcb.fBinary = TRUE;
  dcb.fParity = s.parity == Parity::none ? FALSE : TRUE;
  dcb.fOutxCtsFlow = FALSE;
  dcb.fOutxDsrFlow = FALSE;
  dcb.fDtrControl = DTR_CONTROL_ENABLE;
  dcb.fDsrSensitivity = FALSE;
  dcb.fOutX = FALSE;
  dcb.fInX = FALSE;
  dcb.fErrorChar = FALSE;
  dcb.fNull = FALSE;
  dcb.fRtsControl = RTS_CONTROL_ENABLE;
  dcb.fAbortOnError = FALSE;
  if (!::SetCommState(h, &dcb))
    return Error(Errc::io_error, desc + ": the device did not accept the line settings (" +
                                     win32::error_text(::GetLastError()) + ")");
  DCB got{};
  got.DCBlength = sizeof got;
  // Rate, data bits and stop bits read back as on Linux; the parity is not
  // compared: Wine maps a COM port to a pseudo-terminal, which has no parity
  // bit (as serial.cpp allows for a pty).
  if (!::GetCommState(h, &got) || got.BaudRate != s.baud || got.ByteSize != 8 ||
      got.StopBits != dcb.StopBits)
    return Error(Errc::io_error, desc + ": the device did not accept the line settings");
  ::PurgeComm(h, PURGE_RXCLEAR | PURGE_TXCLEAR);  // what arrived before the settings applied
  return {};
}

// read_some's contract (what is there at once, else the first bytes to
// arrive, else nothing after the timeout: poll() on Linux) from two reads that
// Windows and Wine treat alike: a 1-byte ReadFile with only a total timeout
// returns with the first byte or after the timeout, then a ReadFile with
// ReadIntervalTimeout = MAXDWORD and no total timeout returns at once with
// what else is buffered (SetCommTimeouts, "Remarks"). The documented one-call
// form (ReadIntervalTimeout = ReadTotalTimeoutMultiplier = MAXDWORD, a
// constant C) is not used: Wine 8 keeps reading until C has passed even after
// bytes arrived (its NtReadFile takes MAXDWORD as "no interval"), so every
// exchange lasted its whole answer deadline.
class SerialTransport final : public Transport {
 public:
  SerialTransport(UniqueHandle h, SerialSettings s, std::unique_ptr<PortLock> lock)
      : h_(std::move(h)), settings_(std::move(s)), lock_(std::move(lock)) {
    update_description();
  }
  ~SerialTransport() override {
    h_.reset();  // the port first, then the lock (serial.cpp: the same order)
    lock_.reset();
  }

  Result<void> write(ByteView bytes) override {
    if (!h_.valid()) return Error(Errc::link_closed, description_ + ": closed");
    // max(5 s, twice the wire time), as FdTransport on Linux.
    const double wire_ms = byte_time_us_ * static_cast<double>(bytes.size()) / 1000.0;
    const DWORD limit = static_cast<DWORD>(std::max(5000.0, 2.0 * wire_ms));
    LMCFG_TRY(set_timeouts(MAXDWORD, 0, limit));
    std::size_t off = 0;
    while (off < bytes.size()) {
      DWORD n = 0;
      if (!::WriteFile(h_.get(), bytes.data() + off, static_cast<DWORD>(bytes.size() - off), &n,
                       nullptr))
        return os_error("write failed", ::GetLastError());
      if (n == 0)
        return Error(Errc::timeout,
                     description_ + ": write timed out after " + std::to_string(limit) + " ms");
      off += n;
    }
    return {};
  }

  Result<Bytes> read_some(Millis timeout) override {
    if (!h_.valid()) return Error(Errc::link_closed, description_ + ": closed");
    LMCFG_ASSIGN_OR_RETURN(Bytes out, read_available());
    // Waits of at most an hour per call: Wine counts the deadline in an int of
    // milliseconds from its tick count.
    long long left = std::max<long long>(timeout.count(), 0);
    while (out.empty() && left > 0) {
      const DWORD slice = static_cast<DWORD>(std::min<long long>(left, 3'600'000));
      LMCFG_TRY(set_timeouts(0, slice, 0));
      std::uint8_t first = 0;
      DWORD n = 0;
      if (!::ReadFile(h_.get(), &first, 1, &n, nullptr))
        return os_error("read failed", ::GetLastError());
      left -= slice;
      if (n == 0) continue;  // the whole slice without a byte
      out.push_back(first);
      LMCFG_ASSIGN_OR_RETURN(Bytes rest, read_available());
      out.insert(out.end(), rest.begin(), rest.end());
    }
    return out;
  }

  void discard_input() override {
    if (h_.valid()) ::PurgeComm(h_.get(), PURGE_RXCLEAR);
  }
  std::string describe() const override { return description_; }
  double byte_time_us() const override { return byte_time_us_; }

  Result<void> reconfigure(const SerialSettings& in) override {
    SerialSettings s = in;
    s.device = settings_.device;
    LMCFG_TRY(validate(s));
    LMCFG_TRY(apply_line_settings(h_.get(), s, serial_description(s)));
    settings_ = s;
    update_description();
    return {};
  }

 private:
  void update_description() {
    description_ = serial_description(settings_);
    byte_time_us_ = 1e6 * bits_per_byte(settings_) / static_cast<double>(settings_.baud);
  }
  // What the driver has buffered now, without waiting (up to 1 MiB, as
  // FdTransport drains).
  Result<Bytes> read_available() {
    LMCFG_TRY(set_timeouts(MAXDWORD, 0, 0));
    Bytes out;
    std::uint8_t buf[4096];
    while (out.size() < (1u << 20)) {
      DWORD n = 0;
      if (!::ReadFile(h_.get(), buf, sizeof buf, &n, nullptr))
        return os_error("read failed", ::GetLastError());
      out.insert(out.end(), buf, buf + n);
      if (n < sizeof buf) break;
    }
    return out;
  }
  // ReadIntervalTimeout, ReadTotalTimeoutConstant and WriteTotalTimeoutConstant
  // (no multipliers); SetCommTimeouts only when they change.
  Result<void> set_timeouts(DWORD interval_ms, DWORD read_ms, DWORD write_ms) {
    if (interval_ms == timeouts_.ReadIntervalTimeout &&
        read_ms == timeouts_.ReadTotalTimeoutConstant &&
        write_ms == timeouts_.WriteTotalTimeoutConstant && timeouts_set_)
      return {};
    COMMTIMEOUTS t{};
    t.ReadIntervalTimeout = interval_ms;
    t.ReadTotalTimeoutConstant = read_ms;
    t.WriteTotalTimeoutConstant = write_ms;
    if (!::SetCommTimeouts(h_.get(), &t))
      return os_error("SetCommTimeouts failed", ::GetLastError());
    timeouts_ = t;
    timeouts_set_ = true;
    return {};
  }
  Error os_error(const char* what, DWORD err) const {
    const Errc code = err == ERROR_INVALID_HANDLE || err == ERROR_DEVICE_NOT_CONNECTED ||
                              err == ERROR_BAD_COMMAND || err == ERROR_OPERATION_ABORTED
                          ? Errc::link_closed
                          : Errc::io_error;
    return Error(code, description_ + ": " + what + ": " + win32::error_text(err));
  }

  UniqueHandle h_;
  SerialSettings settings_;
  std::unique_ptr<PortLock> lock_;
  std::string description_;
  double byte_time_us_ = 0.0;
  COMMTIMEOUTS timeouts_{};
  bool timeouts_set_ = false;
};

}  // namespace

std::optional<std::string> com_port_path(const std::string& device) {
  std::string d = device;
  if (d.rfind("\\\\.\\", 0) == 0) d = d.substr(4);
  if (d.size() < 4) return std::nullopt;
  std::string head = d.substr(0, 3);
  std::transform(head.begin(), head.end(), head.begin(),
                 [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
  if (head != "COM") return std::nullopt;
  const std::string digits = d.substr(3);
  if (digits.empty() || digits.size() > 3 || digits[0] == '0' ||
      !std::all_of(digits.begin(), digits.end(), [](unsigned char c) { return std::isdigit(c); }))
    return std::nullopt;
  const int n = std::stoi(digits);
  if (n < 1 || n > 256) return std::nullopt;
  return "\\\\.\\COM" + digits;  // also COM1..COM9: the device namespace always works
}

std::vector<std::string> list_serial_ports() {
  // QueryDosDeviceW(nullptr) lists every MS-DOS device name, NUL-separated;
  // the buffer grows until the list fits.
  std::vector<wchar_t> buf(1 << 16);
  DWORD n = 0;
  while ((n = ::QueryDosDeviceW(nullptr, buf.data(), static_cast<DWORD>(buf.size()))) == 0 &&
         ::GetLastError() == ERROR_INSUFFICIENT_BUFFER && buf.size() < (1u << 24))
    buf.resize(buf.size() * 2);
  std::vector<std::pair<int, std::string>> found;
  for (std::size_t i = 0; i < n && buf[i];) {
    const std::wstring name(&buf[i]);
    i += name.size() + 1;
    const std::string utf8 = win32::narrow(name);
    if (com_port_path(utf8)) found.emplace_back(std::stoi(utf8.substr(3)), utf8);
  }
  std::sort(found.begin(), found.end());  // COM2 before COM10
  std::vector<std::string> ports;
  for (auto& f : found)
    if (ports.empty() || ports.back() != f.second) ports.push_back(std::move(f.second));
  return ports;
}

std::string latency_timer_path(const std::string&, const std::string&) { return {}; }

LowLatencyReport request_low_latency(int, const std::string&, const std::string&) {
  LowLatencyReport r;
  r.ioctl_error =
      "not available on Windows: a USB serial adapter's latency timer is set in the Device "
      "Manager (the port's Properties, Port Settings, Advanced, Latency Timer)";
  return r;
}

Result<std::unique_ptr<Transport>> open_serial(const SerialSettings& s, LowLatencyReport* report,
                                               const PortClaim& claim) {
  if (s.device.empty()) return Error(Errc::invalid_argument, "serial device path is empty");
  LMCFG_TRY(validate(s));
  const auto path = com_port_path(s.device);
  if (!path)
    return Error(Errc::invalid_argument,
                 "cannot use " + s.device +
                     " as a serial port: expected a COM port name (COM1..COM256 or \\\\.\\COMn); "
                     "lmcfg scan lists the COM ports of this computer");
  // The named lock first: Windows refuses a second open of a COM port, but
  // Wine does not, and the lock says who has it either way.
  LMCFG_ASSIGN_OR_RETURN(auto lock, PortLock::take(-1, s.device, claim));
  UniqueHandle h(::CreateFileW(win32::widen(*path).c_str(), GENERIC_READ | GENERIC_WRITE, 0,
                               nullptr, OPEN_EXISTING, 0, nullptr));
  if (!h.valid()) {
    const DWORD err = ::GetLastError();
    if (err == ERROR_FILE_NOT_FOUND || err == ERROR_PATH_NOT_FOUND)
      return Error(Errc::not_found,
                   "cannot open serial port " + s.device + ": " + win32::error_text(err) +
                       "; check --port and that the adapter is plugged in (lmcfg scan lists the "
                       "COM ports, as does the Device Manager under Ports (COM & LPT))");
    if (err == ERROR_ACCESS_DENIED || err == ERROR_SHARING_VIOLATION)
      return Error(Errc::io_error, port_in_use_message(s.device));
    return Error(Errc::io_error,
                 "cannot open serial port " + s.device + ": " + win32::error_text(err));
  }
  auto t = std::make_unique<SerialTransport>(std::move(h), s, std::move(lock));
  // Settings through the transport's reconfigure: the same checks.
  LMCFG_TRY(t->reconfigure(s));
  if (report) *report = request_low_latency(-1, s.device, {});
  return std::unique_ptr<Transport>(std::move(t));
}

}  // namespace lmcfg::transport
