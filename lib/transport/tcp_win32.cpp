// Windows: TCP gateways and RFC 2217 need a Winsock transport, not written
// yet; opening one says so (docs/windows.md).
#include "transport/pty.hpp"

namespace lmcfg::transport {

Result<TcpConnection> connect_tcp(const std::string& host, std::uint16_t port, Millis,
                                  const std::string& scheme) {
  return Error(Errc::not_supported, scheme + " " + host + ":" + std::to_string(port) +
                                        ": TCP links are not available in the Windows build of "
                                        "lmcfg yet; use a COM port (docs/windows.md)");
}

Result<std::unique_ptr<Transport>> open_tcp(const std::string& host, std::uint16_t port,
                                            Millis connect_timeout) {
  LMCFG_ASSIGN_OR_RETURN(auto c, connect_tcp(host, port, connect_timeout, "tcp"));
  (void)c;
  return Error(Errc::not_supported, "tcp: not available");
}

}  // namespace lmcfg::transport
