#pragma once
// A session with one drive: the link the user named, the optional wire trace,
// and the drive client. Ports are the byte-link rows of the one table of port
// schemes (link/port.hpp): a serial device, tcp://host:port (gateway),
// rfc2217://host:port, and SCHEME:ADDRESS registered with
// register_link_scheme(); the tools register sim:STATE.json, the built-in
// simulated drive, in-process; its state is loaded from and saved back to
// STATE.json on close(), so a sequence of commands acts on one persistent drive.
#include <memory>
#include <string>

#include "client/client.hpp"
#include "config/model.hpp"
#include "link/port.hpp"
#include "link/spec.hpp"
#include "transport/transport.hpp"

namespace lmcfg::link {

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

// One open link to one drive, with its client. Closing saves what the link's
// factory asked to be saved (a simulated drive's state).
class Session {
 public:
  // The client talks at `line` (the spec's, or the one a simulated drive
  // dictates) with the settings the spec gives.
  Session(LinkSpec spec, transport::SerialSettings line, transport::OpenedLink link,
          std::optional<transport::LowLatencyReport> latency);
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  // LinRS or LinUDP, as the port's row says (PortSpec::protocol).
  client::Client& client() { return *client_; }
  Result<void> close();
  std::string describe() const { return link_->describe(); }
  // Settings as recorded in a backup's identity.
  config::LinkSettings link_settings() const;
  // The line settings the tool talks with now (for sim: ports, the simulated
  // drive's settings at open; for tcp: ports, what --baud etc. said).
  transport::SerialSettings line() const { return line_; }
  // The specification the session was opened with, as given.
  const LinkSpec& spec() const { return spec_; }
  // The specification of the link as it is now: the opened one with the line
  // settings, MACID and checksum relink() moved to (to open it again later).
  LinkSpec current_spec() const;
  // Talks to the drive with other settings from now on: the serial line is
  // reconfigured (Errc::not_supported on a TCP gateway when `line` differs),
  // the client takes the new MACID and checksum.
  Result<void> relink(const transport::SerialSettings& line, std::uint8_t id,
                      const codec::ChecksumConfig& checksum);
  // What opening a serial port found about its receive latency (USB adapters'
  // latency timer); nullptr for TCP and registered-scheme ports.
  const transport::LowLatencyReport* low_latency() const { return latency_ ? &*latency_ : nullptr; }

 private:
  std::optional<transport::LowLatencyReport> latency_;
  const LinkSpec spec_;
  transport::SerialSettings line_;
  std::unique_ptr<transport::Transport> link_;
  std::function<Result<void>()> on_close_;
  std::unique_ptr<client::Client> client_;
};

// Opens the spec's port (link::open_byte_link) with its trace; the spec is
// not changed.
Result<std::unique_ptr<Session>> open_session(const LinkSpec& spec);

}  // namespace lmcfg::link
