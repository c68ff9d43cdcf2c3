// Finding LinUDP V2 drives in an address range (linudp_scan.hpp). Sources by
// the short names of docs/references.md.
#include "link/linudp_scan.hpp"

#include <algorithm>
#include <cstdlib>

#include "client/linudp_client.hpp"

namespace lmcfg::link {
namespace {

const char* kSyntax =
    "linudp://HOST[:PORT], linudp://A.B.C.D/N[:PORT], linudp://A.B.C.D-A.B.C.E[:PORT] or "
    "linudp://A.B.C.D-E[:PORT]";

std::optional<std::uint32_t> parse_ipv4(const std::string& s) {
  std::uint32_t ip = 0;
  std::size_t pos = 0;
  for (int k = 0; k < 4; ++k) {
    if (pos >= s.size() || s[pos] < '0' || s[pos] > '9') return std::nullopt;
    std::size_t end = pos;
    while (end < s.size() && s[end] >= '0' && s[end] <= '9' && end - pos < 4) ++end;
    const unsigned long v = std::strtoul(s.substr(pos, end - pos).c_str(), nullptr, 10);
    if (end - pos > 3 || v > 255) return std::nullopt;
    ip = (ip << 8) | static_cast<std::uint32_t>(v);
    pos = end;
    if (k < 3) {
      if (pos >= s.size() || s[pos] != '.') return std::nullopt;
      ++pos;
    }
  }
  if (pos != s.size()) return std::nullopt;
  return ip;
}

std::string ipv4_text(std::uint32_t ip) {
  return std::to_string(ip >> 24) + "." + std::to_string((ip >> 16) & 0xFF) + "." +
         std::to_string((ip >> 8) & 0xFF) + "." + std::to_string(ip & 0xFF);
}

std::optional<unsigned> parse_small(const std::string& s, unsigned max) {
  if (s.empty() || s.size() > 5 || s.find_first_not_of("0123456789") != std::string::npos)
    return std::nullopt;
  const unsigned long v = std::strtoul(s.c_str(), nullptr, 10);
  if (v > max) return std::nullopt;
  return static_cast<unsigned>(v);
}

Error bad(const std::string& address, const std::string& why) {
  return Error(Errc::invalid_argument,
               "--port linudp://" + address + ": " + why + " (expected " + kSyntax + ")");
}

}  // namespace

std::size_t LinudpScanReport::count(LinudpAnswer a) const {
  return static_cast<std::size_t>(std::count_if(
      addresses.begin(), addresses.end(), [a](const LinudpScanned& s) { return s.answer == a; }));
}

Result<LinudpRange> parse_linudp_range(const std::string& address) {
  LinudpRange r;
  std::string hosts = address;
  // The port follows the last ':' (IPv4 only: no ':' inside the range).
  if (auto colon = address.rfind(':'); colon != std::string::npos) {
    auto p = parse_small(address.substr(colon + 1), 65535);
    if (!p || *p == 0 || address.find(':') != colon) return bad(address, "bad port");
    r.port = static_cast<std::uint16_t>(*p);
    hosts = address.substr(0, colon);
  }
  if (hosts.empty()) return bad(address, "no address");
  std::uint32_t first = 0, last = 0;
  bool skip_ends = false;
  if (auto slash = hosts.find('/'); slash != std::string::npos) {
    auto base = parse_ipv4(hosts.substr(0, slash));
    auto bits = parse_small(hosts.substr(slash + 1), 32);
    if (!base || !bits) return bad(address, "not an IPv4 network A.B.C.D/N with N 0..32");
    const std::uint32_t mask = *bits == 0 ? 0 : ~std::uint32_t{0} << (32 - *bits);
    first = *base & mask;
    last = first | ~mask;
    skip_ends = *bits <= 30;  // network and broadcast addresses are no drive's
  } else if (auto dash = hosts.find('-');
             dash != std::string::npos && parse_ipv4(hosts.substr(0, dash))) {
    auto a = parse_ipv4(hosts.substr(0, dash));
    const std::string rest = hosts.substr(dash + 1);
    std::optional<std::uint32_t> b = parse_ipv4(rest);
    if (!b && a) {
      if (auto octet = parse_small(rest, 255)) b = (*a & 0xFFFFFF00u) | *octet;
    }
    if (!a || !b) return bad(address, "not an IPv4 range A.B.C.D-A.B.C.E or A.B.C.D-E");
    if (*b < *a) return bad(address, "the range ends before it starts");
    first = *a;
    last = *b;
  } else {
    r.hosts.push_back(hosts);  // one address or name: open_udp resolves it
    return r;
  }
  const std::uint64_t n = std::uint64_t{last} - first + 1 - (skip_ends ? 2 : 0);
  if (n > kMaxScanAddresses) {
    return Error(Errc::invalid_argument,
                 "--port linudp://" + address + ": " + std::to_string(n) +
                     " addresses, more than the " + std::to_string(kMaxScanAddresses) +
                     " a LinUDP scan probes (one /24); name a smaller range");
  }
  for (std::uint64_t ip = std::uint64_t{first} + (skip_ends ? 1 : 0);
       ip <= std::uint64_t{last} - (skip_ends ? 1 : 0); ++ip)
    r.hosts.push_back(ipv4_text(static_cast<std::uint32_t>(ip)));
  return r;
}

Result<LinudpScanReport> scan_linudp(const LinudpRange& range, const UdpOpener& open,
                                     const LinudpScanOptions& o) {
  LinudpScanReport rep;
  rep.port = range.port;
  std::int64_t total_ns = 0;
  std::size_t done = 0;
  for (const auto& host : range.hosts) {
    if (o.progress) o.progress("probing " + host, done, range.hosts.size());
    LMCFG_ASSIGN_OR_RETURN(auto link, open(host, range.port));
    client::ClientOptions copt;
    copt.timeout = o.deadline;
    client::LinudpClient c(*link, copt);
    LinudpScanned s;
    s.host = host;
    const std::int64_t start = link->now_ns();
    auto reply = c.probe(o.deadline, o.attempts);
    if (reply.ok()) {
      s.answer = LinudpAnswer::answered;
      s.status_word = reply->response.status_word;
      s.state_var = reply->response.state_var;
      s.error_code = reply->response.error_code;
      // LinUDP DLL: firmware version = (RAM 0034h << 8) + RAM 0035h.
      auto hi = c.read_ram(0x0034);
      auto lo = hi.ok() ? c.read_ram(0x0035) : hi;
      if (hi.ok() && lo.ok()) {
        s.firmware = (*hi << 8) + *lo;
      } else {
        const Error& e = hi.ok() ? lo.error() : hi.error();
        s.firmware_note = e.code == make_error_code(Errc::drive_refused)
                              ? "firmware version not readable (RAM 0034h/0035h refused)"
                              : "firmware version not read: " + e.message;
      }
    } else if (reply.error().code == make_error_code(Errc::io_error) &&
               reply.error().message == client::held_by_other_master_message(link->describe())) {
      s.answer = LinudpAnswer::held;
    } else if (reply.error().code != make_error_code(Errc::timeout)) {
      return std::move(reply).error();
    }
    // The rate bound: probes start at least `gap` apart.
    const std::int64_t gap_ns = static_cast<std::int64_t>(o.gap.count()) * 1'000'000;
    if (link->now_ns() - start < gap_ns) {
      const std::int64_t left = gap_ns - (link->now_ns() - start);
      (void)link->read_some(std::chrono::milliseconds((left + 999'999) / 1'000'000));
    }
    const std::int64_t spent = link->now_ns() - start;
    s.ms = static_cast<double>(spent) / 1e6;
    s.datagrams = static_cast<int>(c.stats().requests + c.stats().retries);
    total_ns += spent;
    rep.datagrams += static_cast<std::uint64_t>(s.datagrams);
    rep.addresses.push_back(std::move(s));
    ++done;
  }
  if (o.progress) o.progress("done", done, range.hosts.size());
  rep.seconds = static_cast<double>(total_ns) / 1e9;
  return rep;
}

}  // namespace lmcfg::link
