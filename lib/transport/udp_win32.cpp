// Windows: LinUDP needs a Winsock UDP transport, not written yet; opening a
// linudp:// port or a LinUDP simulator says so (docs/windows.md).
#include "transport/udp.hpp"

namespace lmcfg::transport {

namespace {

Error udp_not_available(const std::string& host, std::uint16_t port) {
  return Error(Errc::not_supported, "udp " + host + ":" + std::to_string(port) +
                                        ": LinUDP is not available in the Windows build of "
                                        "lmcfg yet; use the Linux build (docs/windows.md)");
}

}  // namespace

Result<std::unique_ptr<Transport>> open_udp(const std::string& host, std::uint16_t port,
                                            const UdpOptions&) {
  return udp_not_available(host, port);
}

Result<UdpServer> UdpServer::bind(const std::string& host, std::uint16_t port) {
  return udp_not_available(host, port);
}
UdpServer::UdpServer(UdpServer&& o) noexcept : fd_(o.fd_), port_(o.port_) { o.fd_ = -1; }
UdpServer& UdpServer::operator=(UdpServer&& o) noexcept {
  fd_ = o.fd_;
  port_ = o.port_;
  o.fd_ = -1;
  return *this;
}
UdpServer::~UdpServer() = default;
Result<std::optional<UdpServer::Datagram>> UdpServer::receive(Millis) {
  return Error(Errc::not_supported, "LinUDP is not available in the Windows build of lmcfg yet");
}
Result<void> UdpServer::send_to(const Datagram&, ByteView) {
  return Error(Errc::not_supported, "LinUDP is not available in the Windows build of lmcfg yet");
}

}  // namespace lmcfg::transport
