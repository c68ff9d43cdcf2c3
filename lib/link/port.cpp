#include "link/port.hpp"

#include <algorithm>
#include <deque>
#include <filesystem>

#include "transport/rfc2217.hpp"
#include "transport/udp.hpp"

namespace lmcfg::link {

namespace {

Error bad_port(const PortSpec& spec, const std::string& expected) {
  return Error(Errc::invalid_argument, "port '" + spec.text + "' is not " + expected);
}

// tcp:// and rfc2217://: a host and a TCP port 1..65535.
Result<void> parse_gateway(PortSpec& spec) {
  const std::string expected = spec.scheme->syntax + " with PORT 1..65535";
  auto hp = split_host_port(spec.address);
  if (!hp || hp->host.empty() || hp->port == 0) return bad_port(spec, expected);
  spec.host = hp->host;
  spec.tcp_port = hp->port;
  return {};
}

Result<void> parse_nonempty(PortSpec& spec) {
  if (spec.address.empty()) return bad_port(spec, spec.scheme->syntax);
  return {};
}

Result<void> device_exists(const std::string& device) {
  std::error_code ec;
  if (!std::filesystem::exists(device, ec))
    return Error(Errc::not_found,
                 "port " + device + " does not exist (is the adapter plugged in?)");
  return {};
}

// SocketCAN interfaces: can0, vcan0, slcan0 (a kernel slcan line discipline)...
bool socketcan_name(std::string_view port) {
  for (std::string_view p : {"can", "vcan", "slcan"}) {
    if (port.size() > p.size() && port.substr(0, p.size()) == p &&
        std::all_of(port.begin() + static_cast<std::ptrdiff_t>(p.size()), port.end(),
                    [](char c) { return c >= '0' && c <= '9'; }))
      return true;
  }
  return false;
}

Result<transport::OpenedLink> open_serial_row(const PortSpec& spec, const OpenRequest& req) {
  transport::SerialSettings s = req.line;
  s.device = spec.address;
  LMCFG_TRY(transport::validate(s));
  std::error_code ec;
  if (std::filesystem::is_directory(spec.address, ec))
    return Error(Errc::invalid_argument,
                 "port '" + spec.text + "' is a directory, not a serial device");
  transport::OpenedLink opened;
  transport::LowLatencyReport report;
  LMCFG_ASSIGN_OR_RETURN(opened.link,
                         transport::open_serial(s, &report, transport::PortClaim{req.holder}));
  opened.latency = std::move(report);
  return opened;
}

// linudp://HOST[:PORT]: the drive port 49360 unless given (LinUDP V2 §4.3).
Result<void> parse_linudp(PortSpec& spec) {
  const std::string expected = "linudp://HOST[:PORT] (an IPv4 address or name, PORT 1..65535)";
  const std::string_view a = spec.address;
  std::string host(a);
  std::uint16_t port = 49360;
  if (a.find(':') != std::string_view::npos) {
    auto hp = split_host_port(a);
    if (!hp || hp->port == 0 || a.find(':') != a.rfind(':')) return bad_port(spec, expected);
    host = hp->host;
    port = hp->port;
  }
  if (host.empty() || host.find_first_of("/[]") != std::string::npos)
    return bad_port(spec, expected);
  spec.host = host;
  spec.tcp_port = port;
  return {};
}

Result<transport::OpenedLink> open_linudp_row(const PortSpec& spec, const OpenRequest&) {
  transport::OpenedLink opened;
  LMCFG_ASSIGN_OR_RETURN(opened.link, transport::open_udp(spec.host, spec.tcp_port));
  return opened;
}

Result<transport::OpenedLink> open_tcp_row(const PortSpec& spec, const OpenRequest& req) {
  transport::OpenedLink opened;
  LMCFG_ASSIGN_OR_RETURN(opened.link,
                         transport::open_tcp(spec.host, spec.tcp_port, req.connect_timeout));
  return opened;
}

// rfc2217://: the gateway's serial side is set from the client (RFC 2217
// SET-BAUDRATE, SET-DATASIZE, SET-PARITY, SET-STOPSIZE, each confirmed), so
// the line settings of the options reach the drive's line as on a local port,
// and reconfigure() follows a drive to another rate.
Result<transport::OpenedLink> open_rfc2217_row(const PortSpec& spec, const OpenRequest& req) {
  transport::OpenedLink opened;
  LMCFG_ASSIGN_OR_RETURN(opened.link, transport::open_rfc2217(spec.host, spec.tcp_port, req.line,
                                                              req.connect_timeout));
  return opened;
}

Result<std::unique_ptr<can::Link>> open_slcan_row(const PortSpec& spec, const OpenRequest& req) {
  // The adapter's own serial line; USB adapters ignore its rate.
  transport::SerialSettings s;
  s.device = spec.address;
  s.baud = 115200;
  LMCFG_ASSIGN_OR_RETURN(auto serial,
                         transport::open_serial(s, nullptr, transport::PortClaim{req.holder}));
  return can::open_slcan(std::move(serial), req.can);
}

// slcan:tcp://: the adapter's slcan byte stream over TCP (a serial-to-Ethernet
// gateway in front of a serial CAN adapter, or `lmcfg sim --devicenet --tcp`).
// The adapter's own serial rate is the gateway's; the CAN bit rate is still
// sent to the adapter ("Sn").
Result<std::unique_ptr<can::Link>> open_slcan_tcp_row(const PortSpec& spec,
                                                      const OpenRequest& req) {
  LMCFG_ASSIGN_OR_RETURN(auto stream,
                         transport::open_tcp(spec.host, spec.tcp_port, req.connect_timeout));
  return can::open_slcan(std::move(stream), req.can);
}

Result<std::unique_ptr<can::Link>> open_socketcan_row(const PortSpec& spec, const OpenRequest&) {
  return can::open_socketcan(spec.address);
}

// A byte link served by a factory registered at start-up (sim:).
Scheme factory_row(std::string name, transport::LinkFactory factory, std::string syntax) {
  Scheme s;
  s.prefix = name + ":";
  s.name = std::move(name);
  s.kind = Kind::byte_link;
  s.line_rate = true;  // the far end may dictate it (OpenedLink::line)
  s.syntax = std::move(syntax);
  s.parse = [](PortSpec&) -> Result<void> { return {}; };  // the factory checks its address
  s.open_bytes = [factory = std::move(factory)](
                     const PortSpec& spec,
                     const OpenRequest& req) -> Result<transport::OpenedLink> {
    if (!factory)
      return Error(Errc::not_supported, "port '" + spec.text + "': " + spec.scheme->name +
                                            ": ports are not built into this program");
    transport::LinkRequest r;
    r.address = spec.address;
    r.real_time_peer = req.real_time_peer;
    r.line = req.line;
    r.line.device.clear();
    r.holder = req.holder;
    return factory(r);
  };
  return s;
}

// The table. A deque: registering a scheme appends without moving the rows
// PortSpecs point to.
std::deque<Scheme>& table() {
  static std::deque<Scheme> rows = [] {
    std::deque<Scheme> t;
    Scheme tcp;
    tcp.name = "tcp";
    tcp.prefix = "tcp://";
    tcp.line_rate = false;  // the gateway's serial side is configured in the gateway
    tcp.syntax = "tcp://HOST:PORT";
    tcp.parse = parse_gateway;
    tcp.open_bytes = open_tcp_row;
    t.push_back(std::move(tcp));

    Scheme rfc;
    rfc.name = "rfc2217";
    rfc.prefix = "rfc2217://";
    rfc.line_rate = true;  // RFC 2217 carries the line settings to the gateway
    rfc.syntax = "rfc2217://HOST:PORT";
    rfc.parse = parse_gateway;
    rfc.open_bytes = open_rfc2217_row;
    t.push_back(std::move(rfc));

    t.push_back(factory_row("sim", nullptr, "sim:STATE.json"));

    Scheme udp;
    udp.name = "linudp";
    udp.prefix = "linudp://";
    udp.line_rate = false;  // no serial line
    udp.protocol = Protocol::linudp;
    udp.syntax = "linudp://HOST[:PORT]";
    udp.parse = parse_linudp;
    udp.open_bytes = open_linudp_row;
    t.push_back(std::move(udp));

    // Before slcan: its prefix is the longer one (rows are tried in order).
    Scheme slcan_tcp;
    slcan_tcp.name = "slcan-tcp";
    slcan_tcp.prefix = "slcan:tcp://";
    slcan_tcp.kind = Kind::can_link;
    slcan_tcp.line_rate = false;  // the CAN bit rate is --can-bitrate, sent to the adapter
    slcan_tcp.syntax = "slcan:tcp://HOST:PORT";
    slcan_tcp.parse = parse_gateway;
    slcan_tcp.open_can = open_slcan_tcp_row;
    t.push_back(std::move(slcan_tcp));

    Scheme slcan;
    slcan.name = "slcan";
    slcan.prefix = "slcan:";
    slcan.kind = Kind::can_link;
    slcan.line_rate = false;  // the CAN bit rate is --can-bitrate, sent to the adapter
    slcan.syntax = "slcan:DEVICE";
    slcan.parse = parse_nonempty;
    slcan.open_can = open_slcan_row;
    slcan.check_present = [](const PortSpec& p) { return device_exists(p.address); };
    t.push_back(std::move(slcan));

    Scheme socketcan;
    socketcan.name = "socketcan";
    socketcan.kind = Kind::can_link;
    socketcan.line_rate = false;  // the interface's bit rate (ip link set can0 ...)
    socketcan.syntax = "a SocketCAN interface (can0, vcan0)";
    socketcan.matches = socketcan_name;
    socketcan.parse = [](PortSpec&) -> Result<void> { return {}; };
    socketcan.open_can = open_socketcan_row;
    t.push_back(std::move(socketcan));

    Scheme serial;
    serial.name = "serial";
    serial.syntax = "a serial device (/dev/ttyUSB0)";
    serial.matches = [](std::string_view) { return true; };
    serial.parse = parse_nonempty;
    serial.open_bytes = open_serial_row;
    serial.check_present = [](const PortSpec& p) -> Result<void> {
      // Only paths: a relative name is the serial row's fallback, checked when opened.
      if (p.address.empty() || p.address.front() != '/') return {};
      return device_exists(p.address);
    };
    t.push_back(std::move(serial));
    return t;
  }();
  return rows;
}

}  // namespace

Kind PortSpec::kind() const { return scheme->kind; }
bool PortSpec::sets_line_rate() const { return scheme->line_rate; }
const std::string& PortSpec::scheme_name() const { return scheme->name; }
Protocol PortSpec::protocol() const { return scheme->protocol; }

std::vector<const Scheme*> schemes() {
  std::vector<const Scheme*> prefixed, formed;
  for (const auto& row : table()) (row.prefix.empty() ? formed : prefixed).push_back(&row);
  prefixed.insert(prefixed.end(), formed.begin(), formed.end());
  return prefixed;
}

const Scheme& scheme_of(std::string_view port) {
  const auto rows = schemes();
  for (const Scheme* row : rows) {
    if (row->prefix.empty() ? row->matches(port)
                            : port.substr(0, row->prefix.size()) == row->prefix)
      return *row;
  }
  return *rows.back();  // serial matches everything; never reached
}

Result<PortSpec> parse_port(std::string_view port) {
  PortSpec spec;
  spec.text = std::string(port);
  spec.scheme = &scheme_of(port);
  spec.address = spec.text.substr(spec.scheme->prefix.size());
  LMCFG_TRY(spec.scheme->parse(spec));
  return spec;
}

bool is_can_port(std::string_view port) { return scheme_of(port).kind == Kind::can_link; }

Result<transport::OpenedLink> open_byte_link(const PortSpec& spec, const OpenRequest& req) {
  if (!spec.scheme->open_bytes)
    return Error(Errc::invalid_argument, "port '" + spec.text +
                                             "' is a CAN link (DeviceNet controllers), not a "
                                             "LinRS serial line");
  return spec.scheme->open_bytes(spec, req);
}

Result<std::unique_ptr<can::Link>> open_can_link(const PortSpec& spec, const OpenRequest& req) {
  // SocketCAN interfaces may have any name (ip link set ... name press3can):
  // where a CAN link is wanted, a plain name that is no device path is one.
  if (spec.scheme_name() == "serial" && spec.address.find('/') == std::string::npos)
    return open_socketcan_row(spec, req);
  if (!spec.scheme->open_can)
    return Error(Errc::invalid_argument,
                 "port '" + spec.text +
                     "' is not a CAN link: slcan:DEVICE, slcan:tcp://HOST:PORT or a SocketCAN "
                     "interface (can0)");
  return spec.scheme->open_can(spec, req);
}

Result<std::unique_ptr<can::Link>> open_can_link(std::string_view port,
                                                 const can::SlcanOptions& can,
                                                 const std::string& holder) {
  LMCFG_ASSIGN_OR_RETURN(const auto spec, parse_port(port));
  OpenRequest req;
  req.can = can;
  req.holder = holder;
  return open_can_link(spec, req);
}

void register_scheme(std::string name, transport::LinkFactory factory) {
  auto& rows = table();
  const std::string syntax = name == "sim" ? "sim:STATE.json" : name + ":ADDRESS";
  for (auto& row : rows) {
    if (row.prefix == name + ":") {
      row = factory_row(std::move(name), std::move(factory), syntax);
      return;
    }
  }
  rows.push_front(factory_row(std::move(name), std::move(factory), syntax));
}

std::optional<HostPort> split_host_port(std::string_view text) {
  const auto colon = text.rfind(':');
  if (colon == std::string_view::npos) return std::nullopt;
  const auto digits = text.substr(colon + 1);
  if (digits.empty() || digits.size() > 5 ||
      digits.find_first_not_of("0123456789") != std::string_view::npos)
    return std::nullopt;
  const unsigned long n = std::stoul(std::string(digits));
  if (n > 65535) return std::nullopt;
  std::string host(text.substr(0, colon));
  if (host.size() > 2 && host.front() == '[' && host.back() == ']')
    host = host.substr(1, host.size() - 2);
  return HostPort{host, static_cast<std::uint16_t>(n)};
}

}  // namespace lmcfg::link
