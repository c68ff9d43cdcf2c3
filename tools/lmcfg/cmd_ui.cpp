// lmcfg ui: the technician's page for one drive at a time (docs/ui.md), a
// thin main over lib/ui: a loopback address, a token in the printed address,
// the default browser opened; Ctrl-C or the page's Quit ends it.
#include <atomic>
#include <chrono>
#include <cstdio>
#include <mutex>
#include <thread>

#include "audit_flow.hpp"
#include "command.hpp"
#include "link_options.hpp"
#include "ops/interrupt.hpp"
#include "serve/http.hpp"
#include "ui/desk.hpp"
#include "ui/server.hpp"
#include "ui_platform.hpp"

namespace lmcfg::cli {
namespace {

// The README demo axis (tests/fixtures/sim/commissioned-axis.json): the
// practice drive of the connect page.
constexpr const char* kPracticeAxis =
#include "demo_axis.inc"
    ;

struct UiCli {
  CommonOptions common;  // --db, --quiet
  std::string listen = "127.0.0.1:0";
  std::string folder;
  bool no_browser = false, no_practice = false;
};

void ui_log(const std::string& what) {
  static std::mutex mu;
  std::lock_guard<std::mutex> lock(mu);
  std::fprintf(stderr, "lmcfg ui: %s\n", what.c_str());
}

int run_ui(const UiCli& o) {
  auto listen = serve::parse_listen(o.listen);
  if (!listen.ok()) return fail("ui", listen.error());
  if (!serve::is_loopback(listen->host))
    return fail("ui", Error(Errc::invalid_argument,
                            "--listen " + o.listen +
                                ": lmcfg ui serves this computer only; give a loopback address "
                                "(127.0.0.1:PORT, [::1]:PORT or localhost:PORT)"));
  const db::Database db = load_database(o.common);
  ui::DeskOptions dopt;
  dopt.folder = o.folder.empty() ? default_ui_folder() : o.folder;
  dopt.db = db;
  if (!o.no_practice) dopt.practice_state = kPracticeAxis;
  dopt.exit_code = exit_code_for;
  dopt.exit_category = [](int code) { return std::string(exit_category(code)); };
  auto desk = ui::Desk::create(std::move(dopt));
  if (!desk.ok()) return fail("ui", desk.error());
  ops::install_interrupt_handlers();
  std::atomic<bool> quit{false};
  ui::UiOptions uo;
  uo.host = listen->host;
  uo.port = listen->port;
  uo.exit_code = exit_code_for;
  if (!o.common.quiet) uo.log = ui_log;
  uo.on_quit = [&quit] { quit = true; };
  ui::UiServer server(**desk, uo);
  auto port = server.bind();
  if (!port.ok()) return fail("ui", port.error());
  // The address on stdout (scripts read it), the rest on stderr.
  std::printf("%s\n", server.url().c_str());
  std::fflush(stdout);
  std::fprintf(stderr,
               "lmcfg ui: open %s in a browser of this computer (Ctrl-C or the page's Quit "
               "ends it); backups go to %s\n",
               server.url().c_str(), (*desk)->folder().string().c_str());
  if (!o.no_browser && !open_browser(server.url()))
    std::fprintf(stderr, "lmcfg ui: no browser could be opened: open the address above by hand\n");
  std::thread http([&server] { server.serve(); });
  while (!quit.load() && !ops::interrupt_flag().load())
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  const bool interrupted = ops::interrupt_flag().load() && (*desk)->busy();
  if (interrupted) ui_log("stopping: the operation running stops after the telegram in flight");
  (*desk)->stop();
  (*desk)->wait_idle();
  // The Quit page is answered before the server stops.
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  server.stop();
  http.join();
  return interrupted ? kInterrupted : kOk;
}

}  // namespace

void add_ui(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<UiCli>();
  auto* sub = app.add_subcommand(
      "ui", "Open the technician's page in a browser: find, back up, compare, restore, undo");
  sub->add_option("--listen", o->listen,
                  "HOST:PORT to serve on, a loopback address only (port 0: a free one)")
      ->capture_default_str();
  sub->add_option("--folder", o->folder,
                  "where backups go and files to restore are found (default: ~/lmcfg; "
                  "Windows: %USERPROFILE%\\Documents\\lmcfg)");
  sub->add_flag("--no-browser", o->no_browser,
                "do not open a browser: print the address only (with its token)");
  sub->add_flag("--no-practice", o->no_practice,
                "do not offer the simulated practice drive on the connect page");
  sub->add_option("--db", o->common.db_path, "UPID database (default: the installed one)");
  sub->add_flag("-q,--quiet", o->common.quiet, "do not log each request on stderr");
  sub->footer(
      "Examples:\n"
      "  lmcfg ui\n"
      "  lmcfg ui --no-browser --listen 127.0.0.1:8480 --folder /media/stick/axes\n"
      "The page is served on this computer only, with a random token in the address it\n"
      "prints (the first load exchanges it for a cookie). docs/ui.md has the pages and checks.\n"
      "Exit status: 0 stopped (Quit, or Ctrl-C with nothing running); 2 bad option (an\n"
      "address that is not loopback, a folder that cannot be created); 4 the address cannot\n"
      "be bound; 130 Ctrl-C stopped a running operation between two telegrams.");
  sub->callback([o, &exit_code] { exit_code = run_ui(*o); });
}

}  // namespace lmcfg::cli
