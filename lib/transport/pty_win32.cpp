// Windows has no pseudo-terminals: `lmcfg sim --pty` and the tests that use
// one run on Linux (docs/windows.md).
#include "transport/pty.hpp"

namespace lmcfg::transport {

Result<PtyPair> open_pty() {
  return Error(Errc::not_supported,
               "pseudo-terminals do not exist on Windows: serve the simulated drive with lmcfg "
               "sim --tcp on Linux, or lmcfg sim --pty there (docs/windows.md)");
}

}  // namespace lmcfg::transport
