// Windows: the plant service needs OpenSSL (HTTPS, its console's sessions),
// which Debian does not build for MinGW-w64 (docs/windows.md).
#include "command.hpp"
#include "unavailable.hpp"

namespace lmcfg::cli {

void add_serve(CLI::App& app, int& exit_code) {
  add_unavailable(app, exit_code, "serve",
                  "Run the plant service: scheduled fleet backups and drift checks, REST API, "
                  "metrics",
                  "the service runs on Linux; this build has no OpenSSL for its HTTPS");
}

}  // namespace lmcfg::cli
