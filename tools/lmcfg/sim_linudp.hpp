#pragma once
// `lmcfg sim --linudp --udp HOST:PORT`: the simulated drive (the same state
// as the LinRS simulator's) answering LinUDP V2 on a UDP port, with the field
// behaviours (C1250 notes, field reports) and the points LinUDP V2 leaves
// open as --linudp-field options.
// docs/linudp.md.
#include <CLI/CLI.hpp>
#include <functional>
#include <string>
#include <vector>

#include "sim/drive.hpp"

namespace lmcfg::cli {

struct LinudpSimArgs {
  std::string udp = "127.0.0.1:0";
  std::vector<std::string> fields;  // --linudp-field NAME[=VALUE]
};

void add_linudp_sim_options(CLI::App* sim, CLI::Option* linudp_flag, LinudpSimArgs& a);
// Serves `state` until should_stop(); the documented exit code. Prints the
// bound port (line 1) and the link options (line 2).
int run_linudp_sim(const LinudpSimArgs& a, sim::DriveState state, bool fast, bool verbose,
                   const std::function<bool()>& should_stop,
                   const std::function<void(const sim::DriveState&)>& on_exit);

}  // namespace lmcfg::cli
