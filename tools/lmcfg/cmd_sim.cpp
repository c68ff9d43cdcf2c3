// `lmcfg sim`: serve a simulated drive (lib/sim) on a pseudo-terminal or a
// loopback TCP port, in real time, until SIGINT/SIGTERM (or stdin EOF).
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "command.hpp"
#include "common/bytes.hpp"
#include "link/port.hpp"
#include "link/session.hpp"
#include "sim/drive.hpp"
#include "sim/server.hpp"
#include "sim/state_file.hpp"
#include "sim_devicenet.hpp"
#include "sim_linudp.hpp"
#include "sim_platform.hpp"
#include "sim_tcp.hpp"
#include "transport/pty.hpp"

namespace lmcfg::cli {
namespace {

struct SimArgs {
  std::vector<std::string> states;
  bool pty = false;
  std::string tcp;
  bool save_on_exit = false;
  bool until_stdin_eof = false;
  bool fast = false;
  bool verbose = false;
  bool devicenet = false;
  DevicenetSimArgs dn;
  bool linudp = false;
  LinudpSimArgs udp;
};

// The README demo axis (tests/fixtures/sim/commissioned-axis.json), embedded.
constexpr const char kDemoAxis[] =
#include "demo_axis.inc"
    ;

Result<sim::DriveState> demo_axis() {
  auto j = nlohmann::json::parse(kDemoAxis, nullptr, false);
  if (j.is_discarded()) return Error(Errc::parse_error, "embedded demo axis is not JSON");
  return sim::from_json(j);
}

// "--port /dev/pts/3 --baud 57600 --id 0x11 --checksum none": what to give the tools.
std::string link_options_for(const std::string& port, const sim::DriveState& s) {
  char id[8];
  std::snprintf(id, sizeof id, "0x%02X", s.macid);
  std::string o = "--port " + port + " --baud " + std::to_string(s.link.baud);
  if (s.link.parity != transport::Parity::none)
    o += " --parity " + std::string(transport::parity_name(s.link.parity));
  if (s.link.stop_bits != 1) o += " --stop-bits " + std::to_string(s.link.stop_bits);
  return o + " --id " + id + " " + link::checksum_options(s.checksum);
}

// The drives on the served line: the demo axis, or one per --state file
// (several: an RS485 line with distinct MACIDs).
Result<std::vector<std::unique_ptr<sim::Drive>>> load_drives(
    const std::vector<std::string>& states) {
  std::vector<std::unique_ptr<sim::Drive>> drives;
  if (states.empty()) {
    LMCFG_ASSIGN_OR_RETURN(auto st, demo_axis());
    drives.push_back(std::make_unique<sim::Drive>(std::move(st)));
    return drives;
  }
  LMCFG_ASSIGN_OR_RETURN(auto line, sim::load_line(states));
  for (auto& st : line) drives.push_back(std::make_unique<sim::Drive>(std::move(st)));
  return drives;
}

// --linudp: one drive per UDP address (LinUDP V2 §3.2: addressing by IP).
int run_linudp(const SimArgs& a, const std::vector<sim::Drive*>& line) {
  if (line.size() > 1) {
    std::fprintf(stderr, "lmcfg sim: --linudp serves one drive (one --state)\n");
    return kInvalidInput;
  }
  int rc = run_linudp_sim(
      a.udp, line.front()->state(), a.fast, a.verbose,
      [&] { return sim_stop_requested() || (a.until_stdin_eof && stdin_at_eof()); },
      [&](const sim::DriveState& s) {
        if (!a.save_on_exit) return;
        if (auto r = sim::save_state(s, a.states.front()); !r.ok())
          std::fprintf(stderr, "lmcfg sim: %s\n", r.error().message.c_str());
      });
  return rc;
}

// Windows has no pseudo-terminals: without --tcp or --linudp there is no line to serve.
bool pty_missing(const SimArgs& a) {
  if (sim_has_pty() || !a.tcp.empty() || a.linudp) return false;
  std::fprintf(stderr,
               "lmcfg sim: not available on Windows: no pseudo-terminals; serve on TCP with "
               "--tcp HOST:PORT (or LinUDP with --linudp), or use --port sim:FILE for a "
               "simulated drive inside lmcfg (docs/windows.md)\n");
  return true;
}

int run(const SimArgs& a) {
  if (pty_missing(a)) return kInvalidInput;
  if (a.devicenet) {
    if (!a.states.empty()) {
      std::fprintf(stderr,
                   "lmcfg sim: --devicenet simulates a controller of its own, without --state\n");
      return kInvalidInput;
    }
    install_sim_stop_handlers();
    DevicenetSimArgs dn = a.dn;
    dn.tcp = a.tcp;
    return run_devicenet_sim(
        dn, [&] { return sim_stop_requested() || (a.until_stdin_eof && stdin_at_eof()); });
  }
  if (a.states.empty() && a.save_on_exit) {
    std::fprintf(stderr, "lmcfg sim: --save-on-exit needs --state FILE to save to\n");
    return kInvalidInput;
  }
  auto loaded = load_drives(a.states);
  if (!loaded.ok()) {
    std::fprintf(stderr, "lmcfg sim: %s\n", loaded.error().message.c_str());
    return kInvalidInput;
  }
  std::vector<sim::Drive*> line;
  for (auto& d : *loaded) line.push_back(d.get());
  sim::Drive& drive = *line.front();

  install_sim_stop_handlers();
  if (a.linudp) return run_linudp(a, line);

  sim::ServeOptions opt;
  opt.real_time = !a.fast;
  opt.should_stop = [&] { return sim_stop_requested() || (a.until_stdin_eof && stdin_at_eof()); };
  if (a.verbose) {
    opt.trace = [](bool tx, ByteView b) {
      std::fprintf(stderr, "%s %s\n", tx ? "TX" : "RX", to_hex(b).c_str());
    };
  }

  int rc = kOk;
  if (!a.tcp.empty()) {
    rc = serve_tcp_clients(
        a.tcp, opt.should_stop,
        [](std::uint16_t port) {
          std::printf("%u\n", static_cast<unsigned>(port));
          std::fflush(stdout);
        },
        [&](transport::Transport& t) { return sim::serve_bus(line, t, opt); });
    if (rc != kOk) return rc;
  } else {
    auto p = transport::open_pty();
    if (!p.ok()) {
      std::fprintf(stderr, "lmcfg sim: %s\n", p.error().message.c_str());
      return kCommFailure;
    }
    // Line 1: the path (scripts read it); line 2: the link options to use.
    std::printf("%s\n", p->slave_path.c_str());
    std::printf("link options: %s\n", link_options_for(p->slave_path, drive.state()).c_str());
    std::fflush(stdout);
    if (a.states.empty()) {
      std::fprintf(stderr,
                   "lmcfg sim: serving the README demo axis on %s (Ctrl-C stops); try:\n"
                   "  lmcfg info %s\n  lmcfg backup %s -o axis.json\n",
                   p->slave_path.c_str(), link_options_for(p->slave_path, drive.state()).c_str(),
                   link_options_for(p->slave_path, drive.state()).c_str());
    }
    transport::FdTransport t(std::move(p->master), "pty " + p->slave_path);
    // The drive hears only a master at its own baud rate; say so once per change.
    opt.master_baud = [&t, &drive, told = 0u]() mutable -> std::optional<unsigned> {
      auto b = transport::line_baud(t.fd());
      if (b && *b != drive.state().link.baud && told != *b) {
        std::fprintf(
            stderr,
            "lmcfg sim: the master talks at %u Bd; the drive listens at %u Bd and hears nothing\n",
            *b, drive.state().link.baud);
        told = *b;
      }
      return b;
    };
    auto r = sim::serve_bus(line, t, opt);
    if (!r.ok()) {
      std::fprintf(stderr, "lmcfg sim: %s\n", r.error().message.c_str());
      rc = kCommFailure;
    }
  }
  if (a.save_on_exit) {
    for (std::size_t i = 0; i < line.size(); ++i) {
      if (auto s = sim::save_state(line[i]->state(), a.states[i]); !s.ok()) {
        std::fprintf(stderr, "lmcfg sim: %s\n", s.error().message.c_str());
        return kInternal;
      }
    }
  }
  return rc;
}

}  // namespace

int serve_tcp_clients(const std::string& tcp, const std::function<bool()>& should_stop,
                      const std::function<void(std::uint16_t port)>& announce,
                      const std::function<Result<void>(transport::Transport&)>& serve) {
  auto hp = link::split_host_port(tcp.find(':') == std::string::npos ? "127.0.0.1:" + tcp : tcp);
  if (!hp) {
    std::fprintf(stderr, "lmcfg sim: --tcp expects HOST:PORT, got '%s'\n", tcp.c_str());
    return kInvalidInput;
  }
  std::uint16_t bound = 0;
  auto lfd = sim::listen_tcp(hp->host, hp->port, bound);
  if (!lfd.ok()) {
    std::fprintf(stderr, "lmcfg sim: %s\n", lfd.error().message.c_str());
    return kCommFailure;
  }
  announce(bound);
  while (!should_stop()) {
    auto c = sim::accept_client(lfd->get(), transport::Millis(100));
    if (!c.ok()) {
      std::fprintf(stderr, "lmcfg sim: %s\n", c.error().message.c_str());
      return kCommFailure;
    }
    if (!c->valid()) continue;
    transport::FdTransport t(std::move(c).value(), "tcp client of lmcfg sim");
    auto r = serve(t);
    if (!r.ok() && r.error().code != make_error_code(Errc::link_closed))
      std::fprintf(stderr, "lmcfg sim: %s\n", r.error().message.c_str());
  }
  return kOk;
}

void add_sim(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<SimArgs>();
  auto* cmd = app.add_subcommand(
      "sim", sim_has_pty()
                 ? "Serve a simulated LinMot drive (LinRS) on a pseudo-terminal or TCP port"
                 : "Serve a simulated LinMot drive (LinRS) on a TCP port (Windows: no "
                   "pseudo-terminals)");
  cmd->add_option("--state", args->states,
                  "Sim state file (JSON, see docs/simulator.md); default: the README demo axis. "
                  "Repeat for several drives on one RS485 line (distinct MACIDs)");
  auto* pty = cmd->add_flag("--pty", args->pty,
                            sim_has_pty()
                                ? "Serve on a new pseudo-terminal; prints its slave path (default)"
                                : "Serve on a new pseudo-terminal (not available on Windows: "
                                  "use --tcp)");
  cmd->add_option("--tcp", args->tcp,
                  "Listen on HOST:PORT (loopback; port 0 = any); prints the port")
      ->excludes(pty);
  cmd->add_flag("--save-on-exit", args->save_on_exit,
                "Write the drive state back to --state on exit");
  cmd->add_flag("--until-stdin-eof", args->until_stdin_eof,
                "Also stop when stdin reaches end of file");
  cmd->add_flag("--fast", args->fast, "Answer at once instead of after the modelled delays");
  cmd->add_flag("-v,--verbose", args->verbose, "Trace every chunk to stderr");
  auto* devicenet =
      cmd->add_flag("--devicenet", args->devicenet,
                    "Serve a simulated DeviceNet LinMot controller (seed 000) behind a simulated "
                    "slcan CAN adapter on a pty, or with --tcp on TCP (--port "
                    "slcan:tcp://HOST:PORT)");
  add_devicenet_sim_options(cmd, devicenet, args->dn);
  auto* linudp = cmd->add_flag("--linudp", args->linudp,
                               "Serve the drive over LinUDP V2 on a UDP port (--udp; --port "
                               "linudp://HOST:PORT), docs/linudp.md")
                     ->excludes(devicenet)
                     ->excludes(pty);
  add_linudp_sim_options(cmd, linudp, args->udp);
  cmd->callback([args, &exit_code] { exit_code = run(*args); });
}
}  // namespace lmcfg::cli
