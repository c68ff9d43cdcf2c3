#pragma once
// What the POSIX and Windows socket code (fd_transport*, tcp*, udp*) share:
// the deadline arithmetic of their waits and the checks and naming of a TCP
// destination, so both builds wait and word their messages alike. Private to
// the transport layer: not an installed header.
#include <cstdint>
#include <string>

#include "common/result.hpp"
#include "transport/transport.hpp"

namespace lmcfg::transport::detail {

// Milliseconds left until `deadline` for poll() or select(), rounded up so a
// wait never wakes early; 0 once it has passed, at most 10^9.
int ms_left(Clock::time_point deadline);

// A TCP destination: `name` for the resolver ("[::1]" given as "::1") and
// `where` as messages name it ("[::1]:4001").
struct TcpTarget {
  std::string name;
  std::string where;
};
// Errc::invalid_argument for an empty host or port 0, the message starting
// with `scheme` as connect_tcp's do.
Result<TcpTarget> tcp_target(const std::string& host, std::uint16_t port,
                             const std::string& scheme);

}  // namespace lmcfg::transport::detail
