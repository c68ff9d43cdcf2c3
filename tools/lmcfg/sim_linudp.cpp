#include "sim_linudp.hpp"

#include <cstdio>
#include <memory>

#include "command.hpp"
#include "common/bytes.hpp"
#include "link/port.hpp"
#include "sim/linudp_server.hpp"

namespace lmcfg::cli {

void add_linudp_sim_options(CLI::App* sim, CLI::Option* linudp_flag, LinudpSimArgs& a) {
  sim->add_option("--udp", a.udp,
                  "With --linudp: the UDP HOST:PORT to answer on (port 0 = any; default "
                  "127.0.0.1:0); prints the port")
      ->needs(linudp_flag);
  sim->add_option("--linudp-field", a.fields,
                  "With --linudp: a field behaviour or a reading LinUDP V2 leaves open, "
                  "NAME[=VALUE] (repeat; docs/linudp.md lists them):\n" +
                      sim::field_names())
      ->needs(linudp_flag);
}

int run_linudp_sim(const LinudpSimArgs& a, sim::DriveState state, bool fast, bool verbose,
                   const std::function<bool()>& should_stop,
                   const std::function<void(const sim::DriveState&)>& on_exit) {
  sim::LinudpField field;
  for (const auto& f : a.fields) {
    if (auto r = sim::set_field(field, f); !r.ok()) {
      std::fprintf(stderr, "lmcfg sim: %s\n", r.error().message.c_str());
      return kInvalidInput;
    }
  }
  const std::string where = a.udp.find(':') == std::string::npos ? "127.0.0.1:" + a.udp : a.udp;
  auto hp = link::split_host_port(where);
  if (!hp || hp->host.empty()) {
    std::fprintf(stderr, "lmcfg sim: --udp expects HOST:PORT, got '%s'\n", a.udp.c_str());
    return kInvalidInput;
  }
  auto socket = transport::UdpServer::bind(hp->host, hp->port);
  if (!socket.ok()) {
    std::fprintf(stderr, "lmcfg sim: %s\n", socket.error().message.c_str());
    return kCommFailure;
  }
  auto drive = std::make_shared<sim::Drive>(std::move(state));
  sim::LinudpDrive udp(drive, field);
  // Line 1: the port (scripts read it); line 2: the link options to use.
  std::printf("%u\n", static_cast<unsigned>(socket->port()));
  std::string options = "--port linudp://" + hp->host + ":" + std::to_string(socket->port());
  std::printf("link options: %s\n", options.c_str());
  const auto words = sim::field_words(field);
  if (!words.empty()) {
    std::string w;
    for (const auto& x : words) w += " " + x;
    std::printf("simulated field behaviours:%s\n", w.c_str());
  }
  std::fflush(stdout);
  sim::LinudpServeOptions opt;
  opt.should_stop = should_stop;
  opt.real_time = !fast;
  if (verbose) {
    opt.trace = [](bool tx, ByteView b) {
      std::fprintf(stderr, "%s %s\n", tx ? "TX" : "RX", to_hex(b).c_str());
    };
  }
  auto r = sim::serve_linudp(udp, *socket, opt);
  if (on_exit) on_exit(drive->state());
  if (!r.ok()) {
    std::fprintf(stderr, "lmcfg sim: %s\n", r.error().message.c_str());
    return kCommFailure;
  }
  if (udp.stats().motion_telegrams > 0) {
    std::fprintf(stderr, "lmcfg sim: %llu datagrams carried a control word or MC command\n",
                 static_cast<unsigned long long>(udp.stats().motion_telegrams));
  }
  return kOk;
}

}  // namespace lmcfg::cli
