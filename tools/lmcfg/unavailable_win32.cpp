#include "common/result.hpp"
#include "link_options.hpp"
#include "unavailable.hpp"

namespace lmcfg::cli {

void add_unavailable(CLI::App& app, int& exit_code, const std::string& name,
                     const std::string& what, const std::string& why) {
  auto* cmd = app.add_subcommand(name, what + " (not available on Windows: " + why + ")");
  cmd->allow_extras();
  cmd->footer("Not available on Windows: " + why + ". See docs/windows.md.");
  cmd->callback([&exit_code, name, why] {
    exit_code = fail(name.c_str(), Error(Errc::not_supported, "not available on Windows: " + why +
                                                                  " (docs/windows.md)"));
  });
}

}  // namespace lmcfg::cli
