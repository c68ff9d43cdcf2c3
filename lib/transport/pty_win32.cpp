// Windows has no pseudo-terminals: `lmcfg sim --pty` and the tests that use
// one run on Linux (docs/windows.md).
#include "transport/pty.hpp"

namespace lmcfg::transport {

Result<PtyPair> open_pty() {
  return Error(Errc::not_supported,
               "pseudo-terminals do not exist on Windows: serve the simulated drive with lmcfg "
               "sim --tcp HOST:PORT, or lmcfg sim --pty on Linux (docs/windows.md)");
}

// No terminals to ask: the simulator's baud check is a pty's (sim/server.hpp).
std::optional<unsigned> line_baud(int) { return std::nullopt; }

}  // namespace lmcfg::transport
