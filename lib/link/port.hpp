#pragma once
// One table of port schemes: every kind of --port (and inventory `port`) the
// tools know, each row with its prefix, the kind of link it gives, its one
// parser (located messages), whether the client sets the line's rate, and how
// it opens. A new transport is one row here (docs/architecture.md "Adding a
// transport"); the session, the DeviceNet session, the tools' options, the
// fleet inventory check and `lmcfg sim --tcp` all ask this table.
//
//   /dev/ttyUSB0           serial device (termios), LinRS
//   tcp://HOST:PORT        serial-to-Ethernet gateway (raw TCP), LinRS
//   rfc2217://HOST:PORT    RFC 2217 gateway, LinRS (the client sets the line)
//   sim:STATE.json         registered at start-up (the simulated drive), LinRS
//   linudp://HOST[:PORT]   a LinUDP V2 drive over UDP/IPv4 (port 49360 unless
//                          given; LinUDP V2 §4.3), LinUDP
//   slcan:/dev/ttyACM0     serial-line CAN adapter (slcan/Lawicel), CAN
//   slcan:tcp://HOST:PORT  the same adapter protocol over TCP (a gateway, or
//                          `lmcfg sim --devicenet --tcp`), CAN
//   can0, vcan0, slcan0    SocketCAN interface, CAN
//   OTHER:ADDRESS          a scheme registered with register_scheme(), LinRS
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "can/link.hpp"
#include "common/result.hpp"
#include "transport/transport.hpp"

namespace lmcfg::link {

enum class Kind : std::uint8_t {
  byte_link,  // a byte stream carrying LinRS telegrams (transport::Transport)
  can_link,   // CAN frames (can::Link), for DeviceNet controllers
};

// The drive protocol a byte link carries: which client the session builds.
enum class Protocol : std::uint8_t {
  linrs,   // LinRS telegrams over a byte stream (client::LinrsClient)
  linudp,  // LinUDP V2 datagrams, one per write (client::LinudpClient)
};

struct Scheme;

// A port parsed once: which row it belongs to and its parts. Immutable once
// built; opening it never rewrites the caller's options.
struct PortSpec {
  std::string text;     // as given: "tcp://10.0.0.5:4001"
  std::string address;  // without the prefix: "10.0.0.5:4001", "/dev/ttyUSB0", "axis.json"
  std::string host;     // tcp:// and rfc2217:// (IPv6 without brackets)
  std::uint16_t tcp_port = 0;
  const Scheme* scheme = nullptr;

  Kind kind() const;
  // The client sets the line's baud rate, parity and stop bits (serial,
  // rfc2217, sim); false where the far end sets them (a raw TCP gateway is
  // configured in the gateway; a SocketCAN interface has its bit rate from
  // `ip link`).
  bool sets_line_rate() const;
  // "serial", "tcp", "rfc2217", "sim", "slcan-tcp", "slcan", "socketcan" or a
  // registered name.
  const std::string& scheme_name() const;
  Protocol protocol() const;
};

// What opening a port needs besides the port itself.
struct OpenRequest {
  transport::SerialSettings line;  // baud, parity, stop bits (device: from the spec)
  std::string holder;              // who opens it ("lmcfg backup"), recorded in the port's lock
  bool real_time_peer = false;     // a simulated peer sleeps for the modelled wire time
  transport::Millis connect_timeout{3000};  // TCP gateways
  can::SlcanOptions can;                    // CAN rows: bit rate, adapter acknowledgements
};

struct Scheme {
  std::string name;    // "tcp"
  std::string prefix;  // "tcp://"; "" for rows matched by their form (serial, socketcan)
  Kind kind = Kind::byte_link;
  bool line_rate = true;  // PortSpec::sets_line_rate
  Protocol protocol = Protocol::linrs;
  std::string syntax;  // "tcp://HOST:PORT", for messages and --help
  // Rows without a prefix: whether `port` has this row's form.
  std::function<bool(std::string_view port)> matches;
  // Checks `spec.address` and fills host/tcp_port; the message names the port
  // and the form expected.
  std::function<Result<void>(PortSpec& spec)> parse;
  // Byte links: the transport. CAN rows leave it empty.
  std::function<Result<transport::OpenedLink>(const PortSpec&, const OpenRequest&)> open_bytes;
  // CAN links: the frame link. Byte rows leave it empty.
  std::function<Result<std::unique_ptr<can::Link>>(const PortSpec&, const OpenRequest&)> open_can;
  // Whether the port can be reached before a run starts (the fleet inventory
  // check): a device path exists. Empty: nothing to check up front.
  std::function<Result<void>(const PortSpec&)> check_present;
};

// The rows, in the order they are tried: prefixed rows, then SocketCAN names,
// then serial device paths (anything else).
std::vector<const Scheme*> schemes();
// The row `port` belongs to, by prefix or form, without validating it.
const Scheme& scheme_of(std::string_view port);
// The row and its parts; Errc::invalid_argument with a located message
// ("port 'tcp://x' is not tcp://HOST:PORT with PORT 1..65535").
Result<PortSpec> parse_port(std::string_view port);
// True for CAN ports: slcan:DEVICE, slcan:tcp://HOST:PORT or a SocketCAN
// interface name.
bool is_can_port(std::string_view port);

// Opens a byte link (serial, tcp, sim ...). A CAN port gives
// Errc::invalid_argument naming it.
Result<transport::OpenedLink> open_byte_link(const PortSpec& spec, const OpenRequest& req);
// Opens a CAN link (slcan:, SocketCAN). A plain name without '/' that no row
// claims is taken as a SocketCAN interface (interfaces may be renamed); other
// byte ports give Errc::invalid_argument.
Result<std::unique_ptr<can::Link>> open_can_link(const PortSpec& spec, const OpenRequest& req);
// parse_port + open_can_link.
Result<std::unique_ptr<can::Link>> open_can_link(std::string_view port,
                                                 const can::SlcanOptions& can,
                                                 const std::string& holder = "");

// Registers the factory for ports "NAME:ADDRESS" (a byte link whose line rate
// the client sets), replacing an earlier one; "sim" fills the table's sim row.
// Not thread-safe: register at start-up.
void register_scheme(std::string name, transport::LinkFactory factory);

// "HOST:PORT" split at its last colon, "[::1]:80" without the brackets; the
// port in decimal 0..65535 (callers decide whether 0 or an empty host is
// allowed); nullopt when there is no colon or the port is not a number.
struct HostPort {
  std::string host;
  std::uint16_t port = 0;
};
std::optional<HostPort> split_host_port(std::string_view text);

}  // namespace lmcfg::link
