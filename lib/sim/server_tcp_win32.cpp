// Windows: the simulator's TCP listener needs Winsock, not written yet
// (docs/windows.md); the simulator runs on Linux for the Windows tests.
#include "sim/server.hpp"

namespace lmcfg::sim {

Result<transport::UniqueFd> listen_tcp(const std::string& host, std::uint16_t port,
                                       std::uint16_t&) {
  return Error(Errc::not_supported, "tcp " + host + ":" + std::to_string(port) +
                                        ": lmcfg sim --tcp is not available in the Windows "
                                        "build of lmcfg yet (docs/windows.md)");
}

Result<transport::UniqueFd> accept_client(int, transport::Millis) {
  return Error(Errc::not_supported, "lmcfg sim --tcp is not available in the Windows build");
}

}  // namespace lmcfg::sim
