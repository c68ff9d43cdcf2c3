#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "command.hpp"
#include "console.hpp"
#include "link/session.hpp"
#include "sim/state_file.hpp"
#include "version_info.hpp"

namespace lmcfg::cli {
namespace {
// Every subcommand, in the order --help lists them.
constexpr void (*kSubcommands[])(CLI::App&, int&) = {
    add_backup,  add_diff, add_report, add_restore, add_default, add_undo,
    add_journal, add_get,  add_set,    add_db,      add_info,    add_convert,
    add_scan,    add_link, add_sim,    add_fleet,   add_serve,   add_ui,
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
// What `lmcfg` alone (on stderr, exit 2) and `lmcfg help` (on stdout, exit 0)
// print: one line per subcommand, from the table above and each subcommand's
// own description, so it cannot drift from --help; then where to start.
std::string overview(const CLI::App& app) {
  std::string text = app.get_description() +
                     "\n\nUsage: lmcfg SUBCOMMAND [OPTIONS]\n"
                     "       lmcfg help SUBCOMMAND   (the same as lmcfg SUBCOMMAND --help)\n\n"
                     "Subcommands:\n";
  for (const auto* sub : app.get_subcommands({})) {
    std::string name = "  " + sub->get_name();
    name.resize(12, ' ');
    text += name + sub->get_description() + "\n";
  }
  text +=
      "\nFirst commands to try, on a drive at its factory link (README \"Your first real "
      "drive\"):\n"
      "  lmcfg scan --port /dev/ttyUSB0\n"
      "      finds the drives on the port and prints the link options of each\n"
      "  lmcfg backup --port /dev/ttyUSB0 --baud 57600 --id 0x11 -o axis.json\n"
      "      backs one up, with the link options scan printed\n"
      "No drive at hand: 'lmcfg sim' serves a simulated one and prints its --port.\n"
      "Every subcommand has --help with examples; all of them: 'man lmcfg', docs/cli.md.\n";
  return text;
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
  init_console();
  CLI::App app{"lmcfg: back up, diff, default and restore LinMot drive configurations over LinRS"};
  app.set_version_flag("--version", version_text,
                       "Print the program version, the git revision it was built from and the "
                       "UPID database it uses (path, fingerprint, profiles), then exit");
  app.require_subcommand(1);
  // Options are "--name" and "-n" on every platform: CLI11's Windows build
  // would read "/work/axis.json" as an option "/work" (subcommands copy this
  // setting when they are added, below).
  app.allow_windows_style_options(false);
  int exit_code = kOk;
  for (auto add : kSubcommands) add(app, exit_code);
  // The operations layer knows serial ports and TCP gateways; the simulated
  // drive's port scheme is the tools' to add.
  lmcfg::link::register_scheme("sim", lmcfg::sim::state_file_link_factory());
  // `lmcfg help SUBCOMMAND...` is `lmcfg SUBCOMMAND... --help`.
  std::vector<char*> args(argv, argv + argc);
  static char help_flag[] = "--help";
  static char ui_word[] = "ui";
  if (argc == 1 && started_by_double_click()) {
    // A double-click on lmcfg.exe opens the page (docs/ui.md "Windows").
    args.push_back(ui_word);
    argc = static_cast<int>(args.size());
    argv = args.data();
  } else if (argc == 1) {
    std::fputs(overview(app).c_str(), stderr);
    return kInvalidInput;  // a subcommand is required, as before
  }
  if (std::string(argv[1]) == "help") {
    if (argc == 2) {
      std::fputs(overview(app).c_str(), stdout);
      return kOk;
    }
    args.erase(args.begin() + 1);
    args.push_back(help_flag);
    argc = static_cast<int>(args.size());
    argv = args.data();
  }
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
