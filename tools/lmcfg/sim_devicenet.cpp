#include "sim_devicenet.hpp"

#include <cstdio>
#include <memory>

#include "can/virtual_bus.hpp"
#include "command.hpp"
#include "common/bytes.hpp"
#include "devicenet/catalogue.hpp"
#include "sim/devicenet_controller.hpp"
#include "sim/slcan_adapter.hpp"
#include "sim_tcp.hpp"
#include "transport/pty.hpp"

namespace lmcfg::cli {
namespace {

Result<sim::DeviceNetControllerOptions> controller_options(const DevicenetSimArgs& a) {
  sim::DeviceNetControllerOptions o;
  LMCFG_ASSIGN_OR_RETURN(o.mac, devicenet::parse_mac_id("--devicenet-macid", a.macid));
  LMCFG_ASSIGN_OR_RETURN(o.motors, devicenet::parse_motor_list("--devicenet-motors", a.motors));
  if (!a.io_modules.empty()) {
    LMCFG_ASSIGN_OR_RETURN(o.layout, devicenet::parse_modules(a.io_modules));
  }
  o.encoder_module = a.encoder_module;
  if (a.lose_polls < 0 || a.lose_polls >= 1)
    return Error(Errc::invalid_argument, "--lose-polls must be a probability in 0..1 (e.g. 0.05)");
  o.lose_poll_responses = a.lose_polls;
  o.seed = a.seed;
  o.error_leaves_run = a.error_leaves_run;
  o.reset_after_sets = a.reset_after;
  const auto rule = sim::parse_toggle_rule(a.toggle);
  if (!rule) {
    return Error(Errc::invalid_argument, "--devicenet-toggle '" + a.toggle +
                                             "' is not one of seed, get-set-ignore, module");
  }
  o.toggle_rule = *rule;
  const auto absent = sim::parse_absent_motor(a.absent);
  if (!absent) {
    return Error(Errc::invalid_argument, "--devicenet-absent-motor '" + a.absent +
                                             "' is not one of " + sim::absent_motor_names());
  }
  o.absent_motor = *absent;
  return o;
}

}  // namespace

void add_devicenet_sim_options(CLI::App* sim, CLI::Option* devicenet_flag, DevicenetSimArgs& a) {
  sim->add_option("--devicenet-macid", a.macid, "with --devicenet: the controller's MAC ID (0..63)")
      ->capture_default_str();
  sim->add_option("--devicenet-motors", a.motors,
                  "with --devicenet: the motors configured on the controller, e.g. A,B")
      ->capture_default_str();
  sim->add_option("--can-bitrate", a.bus_bitrate,
                  "with --devicenet: the bus's bit rate; an adapter opened at another rate "
                  "hears nothing and reports bus errors")
      ->capture_default_str();
  sim->add_option("--io-modules", a.io_modules,
                  "with --devicenet: the controller's IO modules (default "
                  "control-in,addressed-in,status-out,addressed-out)");
  sim->add_flag("--encoder-module", a.encoder_module,
                "with --devicenet: a master encoder module is fitted (commands 60h..6Bh)");
  sim->add_flag("--factory", a.factory,
                "with --devicenet: values at zero or their range's low end (default: a "
                "commissioned controller)");
  sim->add_option("--lose-polls", a.lose_polls,
                  "with --devicenet: probability that a poll response is lost (fault injection)");
  sim->add_option("--seed", a.seed, "with --lose-polls: the fault sequence's seed")
      ->capture_default_str();
  sim->add_flag("--error-leaves-run", a.error_leaves_run,
                "with --devicenet: a coded error also takes the controller out of RUN (a "
                "firmware variant seed 000 leaves open)");
  sim->add_option("--reset-after-sets", a.reset_after,
                  "with --devicenet: the controller resets once right after this many Set commands "
                  "(the connection is dropped mid-session)");
  sim->add_option("--held-by", a.held_by,
                  "with --devicenet: another master (this MAC ID) holds the connection set");
  sim->add_option("--devicenet-toggle", a.toggle,
                  "with --devicenet: when a command executes (seed 000 leaves it open for all "
                  "but the motion commands): seed (each motor's Command Toggle, a controller "
                  "toggle for controller-level commands), get-set-ignore (Get/Set commands "
                  "run on any change of the Addressed In words), module (one toggle for the "
                  "whole module)")
      ->capture_default_str();
  sim->add_option("--devicenet-absent-motor", a.absent,
                  std::string("with --devicenet: what the controller does with a command for a "
                              "motor it does not have (seed 000 leaves it open): ") +
                      sim::absent_motor_names())
      ->capture_default_str();
  sim->add_flag("--slcan-silent", a.silent_adapter,
                "with --devicenet: the slcan adapter answers no command (no acknowledgement of "
                "transmitted frames, of C/Sn/O, no version or status), as some firmwares");
  for (const char* name : {"--devicenet-macid", "--devicenet-motors", "--can-bitrate",
                           "--io-modules", "--encoder-module", "--factory", "--lose-polls",
                           "--seed", "--error-leaves-run", "--reset-after-sets", "--held-by",
                           "--devicenet-toggle", "--devicenet-absent-motor", "--slcan-silent"})
    sim->get_option(name)->needs(devicenet_flag);
}

int run_devicenet_sim(const DevicenetSimArgs& a, const std::function<bool()>& should_stop) {
  auto opt = controller_options(a);
  if (!opt.ok()) {
    std::fprintf(stderr, "lmcfg sim: %s\n", opt.error().message.c_str());
    return kInvalidInput;
  }
  auto bus = std::make_shared<can::VirtualBus>();
  sim::DeviceNetController controller(*opt);
  if (!a.factory) controller.commission();
  if (!a.held_by.empty()) {
    const auto other = devicenet::parse_mac_id("--held-by", a.held_by);
    if (!other.ok()) {
      std::fprintf(stderr, "lmcfg sim: %s\n", other.error().message.c_str());
      return kInvalidInput;
    }
    controller.hold_for_other_master(*other);
  }
  controller.attach(*bus);
  sim::SlcanAdapterOptions o;
  o.should_stop = should_stop;
  o.bus_bitrate = a.bus_bitrate;
  o.silent = a.silent_adapter;
  // Line 1: where (the pty's path, or the TCP port); line 2: the link options.
  auto announce = [&](const std::string& where, const std::string& port) {
    std::printf("%s\n", where.c_str());
    std::printf("link options: --port %s --can-bitrate %u --devicenet-macid %u\n", port.c_str(),
                a.bus_bitrate, static_cast<unsigned>(opt->mac));
    std::fflush(stdout);
  };
  Result<void> r;
  if (!a.tcp.empty()) {
    // The adapter is reset for each client (its channel closed, as a USB
    // adapter is when plugged in again); the controller and the bus stay.
    const int rc = serve_tcp_clients(
        a.tcp, should_stop,
        [&](std::uint16_t port) {
          const std::string host = a.tcp.find(':') == std::string::npos
                                       ? std::string("127.0.0.1")
                                       : a.tcp.substr(0, a.tcp.rfind(':'));
          announce(std::to_string(port), "slcan:tcp://" + host + ":" + std::to_string(port));
        },
        [&](transport::Transport& t) { return sim::serve_slcan(*bus, t, o); });
    if (rc != kOk) return rc;
  } else {
    auto p = transport::open_pty();
    if (!p.ok()) {
      std::fprintf(stderr, "lmcfg sim: %s\n", p.error().message.c_str());
      return kCommFailure;
    }
    announce(p->slave_path, "slcan:" + p->slave_path);
    transport::FdTransport t(std::move(p->master), "pty " + p->slave_path);
    r = sim::serve_slcan(*bus, t, o);
  }
  std::fprintf(stderr, "lmcfg sim: %llu command(s) executed, %llu poll response(s) lost\n",
               static_cast<unsigned long long>(controller.commands_executed()),
               static_cast<unsigned long long>(controller.poll_responses_lost()));
  if (!r.ok()) {
    std::fprintf(stderr, "lmcfg sim: %s\n", r.error().message.c_str());
    return kCommFailure;
  }
  return kOk;
}

}  // namespace lmcfg::cli
