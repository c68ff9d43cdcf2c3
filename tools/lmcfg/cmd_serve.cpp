// lmcfg serve INVENTORY --archive DIR: the plant service (docs/serve.md), a
// thin main over lib/serve: scheduled backups and drift checks, events, the
// REST API and /metrics. lmcfg serve token add: a bearer token for the API.
#include <chrono>
#include <cstdio>
#include <mutex>
#include <thread>

#include "command.hpp"
#include "common/text.hpp"
#include "fleet_cli.hpp"
#include "ops/interrupt.hpp"
#include "serve/http.hpp"
#include "serve/notify.hpp"
#include "serve/service.hpp"
#include "serve/task_limit.hpp"
#include "serve/tokens.hpp"

namespace lmcfg::cli {
namespace {

struct ServeCli {
  CommonOptions common;  // --db, --quiet; link settings come per line from the inventory
  std::string inventory, archive, listen = "127.0.0.1:8470", tokens, tls_cert, tls_key;
  bool no_curves = false, no_ct = false, full = false;
  std::string token_name, role;
  std::vector<std::string> allow_hosts;
};

// One line per event on stderr, with the time (several threads log); every
// control character and invalid byte escaped (log_text), whoever wrote it.
void log_line(const std::string& what) {
  static std::mutex mu;
  const std::string line = log_text(what);
  std::lock_guard<std::mutex> lock(mu);
  std::fprintf(stderr, "%s lmcfg serve: %s\n", serve::iso_time(serve::Clock::now()).c_str(),
               line.c_str());
}

int run_serve(const ServeCli& o) {
  if (o.inventory.empty() || o.archive.empty())
    return fail("serve", Error(Errc::invalid_argument,
                               "INVENTORY and --archive DIR are needed (see lmcfg serve --help)"));
  auto listen = serve::parse_listen(o.listen);
  if (!listen.ok()) return fail("serve", listen.error());
  serve::HttpOptions http;
  http.listen = *listen;
  http.log = log_line;
  http.exit_code = exit_code_for;
  http.tls_cert = o.tls_cert;
  http.tls_key = o.tls_key;
  http.allowed_hosts = o.allow_hosts;
  if (!o.tokens.empty()) {
    auto tokens = serve::load_tokens(o.tokens);
    if (!tokens.ok()) return fail("serve", tokens.error());
    if (tokens->empty())
      return fail("serve", Error(Errc::invalid_argument,
                                 o.tokens + ": no tokens (add one with lmcfg serve token add)"));
    http.tokens = std::move(tokens).value();
  }
  if (auto exposed = serve::check_exposure(http, o.listen); !exposed.ok())
    return fail("serve", exposed.error());
  if (auto tls = serve::check_tls_files(http); !tls.ok()) return fail("serve", tls.error());
  auto inv = load_checked_inventory(o.inventory, o.common);
  if (!inv.ok()) return fail("serve", inv.error());
  if (auto hook = serve::check_webhook(inv->notify.webhook); !hook.ok())
    return fail("serve", hook.error());
  // Under systemd (TasksMax=) or another cgroup's pids.max: every thread fits.
  if (auto tasks = serve::check_task_limit(*inv, http.server.workers, serve::own_task_limit());
      !tasks.ok())
    return fail("serve", tasks.error());
  ops::install_interrupt_handlers();
  serve::ServiceOptions so;
  so.inventory = *inv;
  so.archive = o.archive;
  // Each line's port, while the service uses it, is locked as "lmcfg serve":
  // a CLI user meets "port ... is in use by lmcfg serve (PID n)".
  CommonOptions common = o.common;
  common.holder = "lmcfg serve";
  // SIGTERM/SIGINT: the telegram in flight completes, the line stops there.
  // (DeviceNet lines: the master checks the same flag, devicenet_link_options.)
  so.links = *line_links(*inv, common, &ops::interrupt_flag());
  const db::Database db = load_database(o.common);
  so.db = db;
  so.backup.curves = !o.no_curves;
  so.backup.command_table = !o.no_ct;
  so.backup.full = o.full;
  so.exit_code = exit_code_for;
  so.log = log_line;
  serve::NotifyOptions no;
  no.webhook = inv->notify.webhook;
  no.command = inv->notify.command;
  no.log = log_line;
  serve::Notifier notifier(no);
  // Events quote drives' and peers' messages: a byte that is not UTF-8 becomes
  // U+FFFD instead of an exception on a line's worker.
  so.notify = [&notifier](const serve::Json& event) {
    notifier.send(event.dump(-1, ' ', false, serve::Json::error_handler_t::replace));
  };
  auto service = serve::Service::create(std::move(so));
  if (!service.ok()) return fail("serve", service.error());
  serve::HttpServer server(**service, http);
  auto port = server.bind();
  if (!port.ok()) return fail("serve", port.error());
  const std::string host =
      listen->host.find(':') != std::string::npos ? "[" + listen->host + "]" : listen->host;
  // The address on stdout (scripts and tests started with port 0 read it), the rest on stderr.
  const std::string scheme = o.tls_cert.empty() ? "http" : "https";
  std::printf("%s://%s:%d\n", scheme.c_str(), host.c_str(), *port);
  (*service)->set_base_url(scheme + "://" + host + ":" + std::to_string(*port));
  std::fflush(stdout);
  log_line("listening on " + scheme + "://" + host + ":" + std::to_string(*port) + " for " +
           o.inventory + " (" + std::to_string(inv->lines.size()) + " line(s), " +
           std::to_string(inv->drive_count()) + " drive(s)), archive " + o.archive);
  if (!http.tokens)
    log_line("no --tokens: every local user is an operator (GET and POST); loopback only");
  if (!inv->archive.push.empty())
    log_line("every commit is pushed to " + inv->archive.push + " ([archive] push)");
  std::thread http_thread([&server] { server.serve(); });
  while (!ops::interrupt_flag().load()) {
    (*service)->tick(serve::Clock::now());
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  log_line("stopping: finishing the telegram in flight on each line");
  server.stop();
  http_thread.join();
  (*service)->stop();
  service->reset();  // waits for the lines' workers
  log_line("stopped");
  return kOk;
}

int run_token_add(const ServeCli& o) {
  auto role = serve::parse_role(o.role);
  if (!role.ok()) return fail("serve token add", role.error());
  auto token = serve::add_token(o.tokens, o.token_name, *role);
  if (!token.ok()) return fail("serve token add", token.error());
  std::printf("%s\n", token->c_str());
  std::fprintf(stderr,
               "lmcfg serve token add: token '%s' (%s) added to %s; it is shown only now, "
               "the file keeps its SHA-256\n",
               o.token_name.c_str(), o.role.c_str(), o.tokens.c_str());
  return kOk;
}

}  // namespace

void add_serve(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<ServeCli>();
  auto* serve = app.add_subcommand(
      "serve",
      "Run the plant service: scheduled fleet backups and drift checks, REST API, metrics");
  serve->add_option("INVENTORY", o->inventory,
                    "inventory file (TOML, docs/fleet.md, docs/serve.md)");
  serve->add_option("--archive", o->archive, "the archive: a git repository (created when new)");
  serve
      ->add_option(
          "--listen", o->listen,
          "HOST:PORT to serve on; other than loopback needs --tokens and --tls-cert/--tls-key")
      ->capture_default_str();
  serve->add_option("--tokens", o->tokens, "bearer tokens file (lmcfg serve token add)");
  serve->add_option("--allow-host", o->allow_hosts,
                    "without --tokens, also serve requests whose Host is HOST:PORT (an ssh "
                    "tunnel's localhost:9000); only the listen address's names otherwise");
  serve->add_option("--tls-cert", o->tls_cert,
                    "serve HTTPS with this PEM certificate (chain); needs --tls-key");
  serve->add_option("--tls-key", o->tls_key, "the PEM private key of --tls-cert");
  serve->add_flag("--no-curves", o->no_curves, "do not read curves");
  serve->add_flag("--no-ct", o->no_ct, "do not read the command table");
  serve->add_flag("--full", o->full, "read every ROM-writable UPID");
  serve->add_option("--db", o->common.db_path, "UPID database (default: the installed one)");
  serve->footer(
      "Examples:\n"
      "  lmcfg serve plant.toml --archive /var/lib/lmcfg/plant\n"
      "  curl -s http://127.0.0.1:8470/api/v1/drives\n"
      "  lmcfg serve plant.toml --archive /var/lib/lmcfg/plant --listen 0.0.0.0:8470 \\\n"
      "      --tokens /etc/lmcfg/tokens --tls-cert /etc/lmcfg/cert.pem --tls-key "
      "/etc/lmcfg/key.pem\n"
      "  lmcfg serve token add grafana --role viewer --tokens /etc/lmcfg/tokens\n"
      "The schedule, notifications and archive push come from the inventory's [schedule],\n"
      "[notify] and [archive];\n"
      "docs/serve.md has the API, the events, the metrics and the security model.");
  auto* token = serve->add_subcommand("token", "Manage the API's bearer tokens");
  token->require_subcommand(1);
  auto* add = token->add_subcommand("add", "Add a token: prints it once, stores its SHA-256");
  add->add_option("NAME", o->token_name, "the token's name (who uses it)")->required();
  add->add_option("--role", o->role, "viewer (GET) or operator (GET and POST)")->required();
  add->add_option("--tokens", o->tokens,
                  "the tokens file (created readable and writable by its owner only)")
      ->required();
  add->callback([o, &exit_code] { exit_code = run_token_add(*o); });
  serve->callback([o, &exit_code, serve] {
    if (serve->got_subcommand("token")) return;
    exit_code = run_serve(*o);
  });
}

}  // namespace lmcfg::cli
