#include <algorithm>
#include <cstdio>
#include <exception>
#include <vector>

#include "command.hpp"
#include "version_info.hpp"

namespace lmcfg::cli {
namespace {
std::vector<std::pair<int, Setup>>& registry() {
  static std::vector<std::pair<int, Setup>> r;
  return r;
}
}  // namespace
Register::Register(int order, Setup setup) { registry().emplace_back(order, std::move(setup)); }
}  // namespace lmcfg::cli

int main(int argc, char** argv) {
  using namespace lmcfg::cli;
  CLI::App app{"lmcfg: back up, diff, default and restore LinMot drive configurations over LinRS"};
  app.set_version_flag("--version", version_text,
                       "Print the program version, the git revision it was built from and the "
                       "UPID database it uses (path, fingerprint, profiles), then exit");
  app.require_subcommand(1);
  int exit_code = kOk;
  auto& reg = registry();
  std::stable_sort(reg.begin(), reg.end(), [](auto& a, auto& b) { return a.first < b.first; });
  for (auto& [order, setup] : reg) setup(app, exit_code);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    int rc = app.exit(e);
    return rc == 0 ? kOk : kInvalidInput;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "lmcfg: internal error: %s\n", e.what());
    return kInternal;
  }
  return exit_code;
}
