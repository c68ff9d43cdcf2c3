#pragma once
// UDP datagrams as a transport (POSIX sockets): LinUDP V2 drives are reached
// over plain UDP/IPv4 between fixed ports (LinUDP V2 §4.3). One
// write() is one datagram; one read_some() returns at most one datagram,
// whole, so the framing above can rely on datagram boundaries.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "transport/transport.hpp"

namespace lmcfg::transport {

struct UdpOptions {
  // The local port the datagrams come from: LinUDP's master port 41136
  // (LinUDP V2 §4.3; whether a drive filters on it is open: a C1250 notes claim).
  // Bound with SO_REUSEADDR/SO_REUSEPORT: several connected sockets (one per
  // drive, fleet lines in parallel) share it, the kernel hands each the
  // datagrams of its own peer. 0: any free port.
  std::uint16_t local_port = 41136;
};

// A socket connected to host:port (IPv4 or a name resolving to one): it
// receives only that peer's datagrams. describe(): "udp 10.8.7.232:49360".
Result<std::unique_ptr<Transport>> open_udp(const std::string& host, std::uint16_t port,
                                            const UdpOptions& opt = {});

// The other end, for a simulated drive (`lmcfg sim --linudp --udp`): a socket
// bound to host:port (port 0: any) that answers whoever sent.
class UdpServer {
 public:
  static Result<UdpServer> bind(const std::string& host, std::uint16_t port);
  UdpServer(UdpServer&&) noexcept;
  UdpServer& operator=(UdpServer&&) noexcept;
  ~UdpServer();
  std::uint16_t port() const { return port_; }
  struct Datagram {
    Bytes bytes;
    std::string from;  // "127.0.0.1:41136"
    std::uint32_t from_ip = 0;
    std::uint16_t from_port = 0;
  };
  // Waits at most `timeout`; nullopt when nothing came.
  Result<std::optional<Datagram>> receive(Millis timeout);
  Result<void> send_to(const Datagram& peer, ByteView bytes);

 private:
  UdpServer(int fd, std::uint16_t port) : fd_(fd), port_(port) {}
  int fd_ = -1;
  std::uint16_t port_ = 0;
};

}  // namespace lmcfg::transport
