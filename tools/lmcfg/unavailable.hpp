#pragma once
// A subcommand that the Windows build does not have (docs/windows.md): it is
// listed in --help as such, and running it says why and what to use instead,
// with the exit code of Errc::not_supported (2, like any refused input).
#include <CLI/CLI.hpp>
#include <string>

namespace lmcfg::cli {

void add_unavailable(CLI::App& app, int& exit_code, const std::string& name,
                     const std::string& what, const std::string& why);

}  // namespace lmcfg::cli
