// Windows: the simulator serves a drive on a pseudo-terminal or a TCP port;
// Windows has no pseudo-terminals and this build no TCP transport yet. The
// in-process simulated drive (--port sim:FILE) works (docs/windows.md).
#include "command.hpp"
#include "unavailable.hpp"

namespace lmcfg::cli {

void add_sim(CLI::App& app, int& exit_code) {
  add_unavailable(app, exit_code, "sim",
                  "Serve a simulated LinMot drive (LinRS) on a pseudo-terminal or TCP port",
                  "no pseudo-terminals on Windows; run lmcfg sim on Linux, or use --port "
                  "sim:FILE for a simulated drive inside lmcfg");
}

}  // namespace lmcfg::cli
