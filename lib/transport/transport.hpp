#pragma once
// One small byte interface for every link (libmodbus backend table, lely
// io_can_chan_vtbl): serial port, TCP gateway, in-process simulated drive.
// Framing and checksums stay in the codec; a transport only moves bytes.
#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/bytes.hpp"
#include "common/result.hpp"

namespace lmcfg::transport {

using Clock = std::chrono::steady_clock;
using Millis = std::chrono::milliseconds;

struct SerialSettings;

class Transport {
 public:
  virtual ~Transport() = default;
  // Writes all bytes (blocking until handed to the OS / peer).
  virtual Result<void> write(ByteView bytes) = 0;
  // Reads what is available, waiting at most `timeout` for the first byte.
  // Returns an empty vector on timeout; link_closed / io_error on failure.
  virtual Result<Bytes> read_some(Millis timeout) = 0;
  // Discards bytes already received but not read (before a retry).
  virtual void discard_input() = 0;
  // "serial /dev/ttyUSB0 57600 8N1", "tcp 10.0.0.5:4001", "sim"...
  virtual std::string describe() const = 0;
  // Wire time of one byte in microseconds for this link's settings, if it has one
  // (serial and simulated links); 0 when unknown (TCP).
  virtual double byte_time_us() const { return 0.0; }
  // Changes the line settings (baud, parity, stop bits; `device` is ignored) of
  // an open link, e.g. to follow a drive whose restored LinRS parameters became
  // active at its reset. Errc::not_supported where the transport has no line of
  // its own (a TCP gateway's serial side is configured in the gateway).
  virtual Result<void> reconfigure(const SerialSettings& s);
  // How long the link may hold received bytes before handing them over (a USB
  // serial adapter's latency timer), in milliseconds; 0 when there is no such
  // buffering or it is unknown (pty, TCP, simulated link).
  virtual double receive_latency_ms() const { return 0.0; }
  // The link's time in nanoseconds (monotonic): the steady clock, or the
  // simulated drive's virtual clock, so that round-trip times measured by the
  // client follow the time the link models.
  virtual std::int64_t now_ns() const {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch())
        .count();
  }
};

// What opening a serial port found about receive latency (USB serial adapters
// hold received bytes for their latency timer, 16 ms by default with ftdi_sio).
struct LowLatencyReport {
  // TIOCGSERIAL/TIOCSSERIAL exist for this device (real UARTs and USB serial
  // drivers; not pseudo-terminals, sockets or pipes).
  bool ioctl_supported = false;
  bool low_latency_set = false;  // ASYNC_LOW_LATENCY is on after the open
  std::string ioctl_error;       // why the ioctl was not available ("" when it was)
  // The adapter's latency_timer from sysfs (ftdi_sio and relatives), ms.
  std::optional<int> latency_timer_ms;
  std::string sysfs_path;  // where it was read ("" when there is none)
  // One line for the user when the timer stays above 2 ms after the request,
  // naming the udev rule of docs/transport.md; "" otherwise.
  std::string advice;
};
// Asks for low latency on an open terminal (TIOCSSERIAL with ASYNC_LOW_LATENCY;
// the Linux ftdi_sio driver maps it to a 1 ms latency timer) and reads the
// adapter's latency_timer from `sysfs_root`/class/tty/NAME/device/latency_timer
// (`sysfs_root` is "/sys" outside tests). Never fails: where the ioctl does not
// exist (pty, socket) the report says so and nothing changes.
LowLatencyReport request_low_latency(int fd, const std::string& device,
                                     const std::string& sysfs_root = "/sys");
// The sysfs latency_timer file of a tty device ("/dev/ttyUSB0" ->
// "<root>/class/tty/ttyUSB0/device/latency_timer"), whether or not it exists.
std::string latency_timer_path(const std::string& device, const std::string& sysfs_root);

enum class Parity : std::uint8_t { none, even, odd };

struct SerialSettings {
  std::string device;
  unsigned baud = 57600;  // LinRS §15 factory default
  Parity parity = Parity::none;
  unsigned stop_bits = 1;
  friend bool operator==(const SerialSettings&, const SerialSettings&) = default;
};
// "none", "even", "odd".
std::string_view parity_name(Parity p) noexcept;
// "none"/"even"/"odd" or the letters N/E/O (either case).
std::optional<Parity> parity_from_name(std::string_view text) noexcept;

// Bits on the wire per byte: start + 8 data + parity + stop.
unsigned bits_per_byte(const SerialSettings& s);
// Validates baud (4800..115200, one of the S1 table rates of §3.2.1), stop bits 1|2.
Result<void> validate(const SerialSettings& s);
// The S1 table rates of LinRS §3.2.1, ascending; the only bauds validate() accepts.
inline constexpr std::array<unsigned, 6> kSerialBaudRates{4800, 9600, 19200, 38400, 57600, 115200};
// "57600 8N1", "19200 8E2" (no device).
std::string format_settings(const SerialSettings& s);

// One program per port (docs/transport.md): who opens a serial device, as the
// caller describes itself ("lmcfg backup", "lmcfg serve"). The open takes
// flock(LOCK_EX|LOCK_NB) on the device and records the holder and this
// process's PID in a lock-info file (port_lock_dirs()) until the port closes,
// so that a second opener can say who has it. An empty holder locks the port
// but records nothing: others then see "another program".
struct PortClaim {
  std::string holder;
};
// Who holds a port, from its lock-info file; only a file whose PID is alive.
struct PortHolder {
  std::string holder;  // "lmcfg backup"
  long pid = 0;
};
// The lock-info file of `device` (keyed by its canonical path) in the first
// of port_lock_dirs() that has one of a living process; nullopt otherwise.
std::optional<PortHolder> port_holder(const std::string& device);
// Where lock-info files are written (the first usable) and looked for (all):
// /run/lock/lmcfg, $XDG_RUNTIME_DIR/lmcfg, /tmp/lmcfg-lock.
std::vector<std::string> port_lock_dirs();
// "port /dev/ttyUSB0 is in use by lmcfg backup (PID 4242)", or "... by another
// program" when no living holder is recorded.
std::string port_in_use_message(const std::string& device);

// POSIX termios, raw mode, 8 data bits. Works on ttys and pseudo-terminals.
// Asks for low latency (request_low_latency); `report`, when given, receives
// what that found, and receive_latency_ms() of the link is the adapter's timer.
// The port is locked for `claim` while the transport lives; a port locked by
// another opener (also in this process) gives Errc::io_error with
// port_in_use_message() before a byte is sent.
Result<std::unique_ptr<Transport>> open_serial(const SerialSettings& s,
                                               LowLatencyReport* report = nullptr,
                                               const PortClaim& claim = {});

// TCP client for serial-to-Ethernet gateways ("host:port").
Result<std::unique_ptr<Transport>> open_tcp(const std::string& host, std::uint16_t port,
                                            Millis connect_timeout);

// Wraps another transport and writes every chunk as a timestamped hex line
// ("12.345678 TX 01 11 05 02 00 03 A2 13 04") to `sink`; for bug reports (--trace).
class TraceSink {
 public:
  virtual ~TraceSink() = default;
  virtual void record(bool tx, ByteView bytes) = 0;
};
// One line per chunk, "<seconds since the sink was opened, 6 decimals> TX|RX <hex>",
// written with one write(2) per line so a trace survives a crash of the process.
// The file is truncated. nullptr when it cannot be opened (open_file_trace says why).
std::unique_ptr<TraceSink> make_file_trace(const std::string& path);
Result<std::unique_ptr<TraceSink>> open_file_trace(const std::string& path);
// TX chunks are recorded before they are handed to `inner` (an attempted write counts),
// RX chunks when read_some returns bytes; empty chunks are not recorded.
// A null sink returns `inner` unchanged. describe()/byte_time_us() are forwarded.
std::unique_ptr<Transport> make_traced(std::unique_ptr<Transport> inner,
                                       std::shared_ptr<TraceSink> sink);

// In-memory sink for tests ("zero write telegrams on the wire"). Thread-safe.
struct TraceRecord {
  bool tx = false;
  Bytes bytes;
  friend bool operator==(const TraceRecord&, const TraceRecord&) = default;
};
class MemoryTrace : public TraceSink {
 public:
  void record(bool tx, ByteView bytes) override;
  std::vector<TraceRecord> records() const;  // a copy, in order
  std::size_t count(bool tx) const;          // number of TX (true) or RX (false) chunks
  Bytes all_bytes(bool tx) const;            // every TX (or RX) chunk concatenated
  void clear();

 private:
  mutable std::mutex mu_;
  std::vector<TraceRecord> records_;
};

// A link opened by a port scheme the operations layer does not know itself
// (link::register_scheme): the tools register "sim:" this way, so the
// operations never depend on the simulator.
struct OpenedLink {
  std::unique_ptr<Transport> link;
  // The line's settings when the far end dictates them (a simulated drive is
  // wired at its own settings); nullopt keeps what the options said.
  std::optional<SerialSettings> line;
  // Run by a clean close (a simulated drive saves its state); may be empty.
  std::function<Result<void>()> on_close;
  // What opening a serial port found about its receive latency; nullopt for
  // other links.
  std::optional<LowLatencyReport> latency{};
};
struct LinkRequest {
  std::string address;          // the port without its scheme: "axis.json" of "sim:axis.json"
  bool real_time_peer = false;  // a simulated peer sleeps for the modelled wire time
  SerialSettings line{};        // the line settings asked for (device empty)
  std::string holder{};         // who opens the port (PortClaim::holder)
};
using LinkFactory = std::function<Result<OpenedLink>(const LinkRequest&)>;

}  // namespace lmcfg::transport
