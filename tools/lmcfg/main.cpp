#include <cstdio>
#include <exception>

#include "command.hpp"
#include "link/session.hpp"
#include "sim/state_file.hpp"
#include "version_info.hpp"

namespace lmcfg::cli {
namespace {
// Every subcommand, in the order --help lists them.
constexpr void (*kSubcommands[])(CLI::App&, int&) = {
    add_backup,  add_diff, add_report, add_restore, add_default, add_undo,
    add_journal, add_get,  add_set,    add_db,      add_info,    add_convert,
    add_scan,    add_link, add_sim,    add_fleet,   add_serve,
};

// The first word that is not an option must name a subcommand: "lmcfg fleet
// backup" is an error naming 'fleet', never a backup. nullptr when it does.
const char* unknown_subcommand(const CLI::App& app, int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string word = argv[i];
    if (word.empty() || word[0] == '-') continue;  // --help, --version
    for (const auto* sub : app.get_subcommands({}))
      if (sub->check_name(word)) return nullptr;
    return argv[i];
  }
  return nullptr;
}
std::string subcommand_names(const CLI::App& app) {
  std::string names;
  for (const auto* sub : app.get_subcommands({}))
    names += (names.empty() ? "" : ", ") + sub->get_name();
  return names;
}
}  // namespace
}  // namespace lmcfg::cli

int main(int argc, char** argv) {
  using namespace lmcfg::cli;
  CLI::App app{"lmcfg: back up, diff, default and restore LinMot drive configurations over LinRS"};
  app.set_version_flag("--version", version_text,
                       "Print the program version, the git revision it was built from and the "
                       "UPID database it uses (path, fingerprint, profiles), then exit");
  app.require_subcommand(1);
  int exit_code = kOk;
  for (auto add : kSubcommands) add(app, exit_code);
  // The operations layer knows serial ports and TCP gateways; the simulated
  // drive's port scheme is the tools' to add.
  lmcfg::link::register_scheme("sim", lmcfg::sim::state_file_link_factory());
  if (const char* word = unknown_subcommand(app, argc, argv)) {
    std::fprintf(stderr, "lmcfg: unknown subcommand '%s' (one of: %s; see lmcfg --help)\n", word,
                 subcommand_names(app).c_str());
    return kInvalidInput;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ExtrasError& e) {
    // A stray word after the subcommand is an error naming it, never ignored.
    std::string words;
    for (const auto* sub : app.get_subcommands())
      for (const auto& w : sub->remaining()) words += (words.empty() ? "'" : ", '") + w + "'";
    for (const auto& w : app.remaining()) words += (words.empty() ? "'" : ", '") + w + "'";
    std::fprintf(stderr, "lmcfg: unexpected argument %s (see lmcfg SUBCOMMAND --help)\n",
                 words.empty() ? e.what() : words.c_str());
    return kInvalidInput;
  } catch (const CLI::ParseError& e) {
    int rc = app.exit(e);
    return rc == 0 ? kOk : kInvalidInput;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "lmcfg: internal error: %s\n", e.what());
    return kInternal;
  }
  return exit_code;
}
