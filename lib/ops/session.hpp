#pragma once
// A session with one drive: the link the user named, the optional wire trace,
// and the drive client. Ports:
//   /dev/ttyUSB0        real serial port (termios)
//   tcp://host:port     serial-to-Ethernet gateway
//   sim:STATE.json      the built-in simulated drive, in-process; its state is
//                       loaded from and saved back to STATE.json on close(), so
//                       a sequence of commands acts on one persistent drive.
#include <memory>
#include <string>

#include "client/client.hpp"
#include "config/model.hpp"
#include "transport/transport.hpp"

namespace lmcfg::sim {
class SimLink;
}

namespace lmcfg::ops {

struct LinkOptions {
  std::string port;
  transport::SerialSettings serial;  // device filled from port for serial links
  client::ClientOptions client;      // MACID, checksum, timeouts, retries
  std::string trace_path;            // "" = no trace
  bool real_time_sim = false;        // sim: sleep for the modelled wire time
  // open_session switches the client's adaptive answer deadline on (capped by
  // client.timeout) and, unless fixed_settle, the adaptive settle (capped by
  // client.settle). fixed_settle: every settle waits client.settle (--settle-ms).
  bool fixed_settle = false;
};

// "none", "add", "crc" (0xFFFF init), "crc-ffff", "crc-0000", "crc-kermit"
// (reflected, init 0). The coverage stays the default (ID through last data byte).
Result<codec::ChecksumConfig> parse_checksum(std::string_view text);
// "id" (ID through last data byte, default), "start" (01 through last data
// byte), "data" (02 through last data byte): codec::ChecksumCoverage.
Result<codec::ChecksumCoverage> parse_checksum_coverage(std::string_view text);
std::string_view coverage_name(codec::ChecksumCoverage c);
// The mode's option name ("crc-ffff"); with a coverage other than the default
// " coverage=start" is appended (the form a backup's link settings record).
std::string checksum_name(const codec::ChecksumConfig& c);
// The command-line options that select `c`: "--checksum crc-ffff", plus
// " --checksum-coverage start" when the coverage is not the default.
std::string checksum_options(const codec::ChecksumConfig& c);
Result<transport::Parity> parse_parity(std::string_view text);

class Session {
 public:
  virtual ~Session() = default;
  virtual client::Client& client() = 0;
  // The in-process simulated link (sim: ports), else nullptr.
  virtual sim::SimLink* sim_link() = 0;
  // Saves the simulated drive's state (sim: ports); closes the link.
  virtual Result<void> close() = 0;
  virtual std::string describe() const = 0;
  // Settings as recorded in a backup's identity.
  virtual config::LinkSettings link_settings() const = 0;
  // The line settings the tool talks with now (for sim: ports, the simulated
  // drive's settings at open; for tcp: ports, what --baud etc. said).
  virtual transport::SerialSettings line() const = 0;
  // Talks to the drive with other settings from now on: the serial line is
  // reconfigured (Errc::not_supported on a TCP gateway when `line` differs),
  // the client takes the new MACID and checksum.
  virtual Result<void> relink(const transport::SerialSettings& line, std::uint8_t id,
                              const codec::ChecksumConfig& checksum) = 0;
  // What opening a serial port found about its receive latency (USB adapters'
  // latency timer); nullptr for TCP and sim: ports.
  virtual const transport::LowLatencyReport* low_latency() const { return nullptr; }
};

Result<std::unique_ptr<Session>> open_session(const LinkOptions& opt);

}  // namespace lmcfg::ops
