// The platform-neutral half of the TCP client (tcp_common.hpp), and open_tcp,
// which is connect_tcp (tcp.cpp, tcp_win32.cpp) under an FdTransport.
#include "transport/tcp_common.hpp"

#include <algorithm>
#include <chrono>
#include <memory>

#include "transport/pty.hpp"

namespace lmcfg::transport {

namespace detail {

int ms_left(Clock::time_point deadline) {
  const auto now = Clock::now();
  if (now >= deadline) return 0;
  const auto left = std::chrono::ceil<Millis>(deadline - now).count();
  return static_cast<int>(std::min<long long>(left, 1'000'000'000LL));
}

Result<TcpTarget> tcp_target(const std::string& host, std::uint16_t port,
                             const std::string& scheme) {
  if (host.empty()) return Error(Errc::invalid_argument, scheme + ": host is empty");
  // "[::1]" is accepted as well as "::1".
  std::string name = host;
  if (name.size() >= 2 && name.front() == '[' && name.back() == ']')
    name = name.substr(1, name.size() - 2);
  const bool v6 = name.find(':') != std::string::npos && name.front() != '[';
  std::string where = (v6 ? "[" + name + "]" : name) + ":" + std::to_string(port);
  if (port == 0)
    return Error(Errc::invalid_argument, scheme + " " + where + ": port 0 is not a valid port");
  return TcpTarget{std::move(name), std::move(where)};
}

}  // namespace detail

Result<std::unique_ptr<Transport>> open_tcp(const std::string& host, std::uint16_t port,
                                            Millis connect_timeout) {
  LMCFG_ASSIGN_OR_RETURN(auto c, connect_tcp(host, port, connect_timeout, "tcp"));
  return std::unique_ptr<Transport>(
      std::make_unique<FdTransport>(std::move(c.fd), "tcp " + c.where));
}

}  // namespace lmcfg::transport
