#pragma once
// `lmcfg sim --devicenet`: a simulated DeviceNet LinMot controller (seed 000)
// behind a simulated slcan adapter on a pseudo-terminal or a TCP listener,
// with its fault options. docs/devicenet.md.
#include <CLI/CLI.hpp>
#include <functional>
#include <string>

namespace lmcfg::cli {

struct DevicenetSimArgs {
  std::string macid = "63";
  std::string motors = "A";
  unsigned bus_bitrate = 125000;
  std::string io_modules;  // "" = the default layout
  bool encoder_module = false;
  bool factory = false;  // not commissioned: every value at zero or its range's low end
  double lose_polls = 0;
  unsigned seed = 1;
  std::string held_by;  // another master's MAC ID holding the connection
  bool error_leaves_run = false;
  unsigned reset_after = 0;
  std::string toggle = "seed";         // seed | get-set-ignore | module
  std::string absent = "coded-error";  // sim::parse_absent_motor
  bool silent_adapter = false;         // the slcan adapter answers nothing but frames
  std::string tcp;                     // --tcp HOST:PORT; "" = a new pty
};

// The options of `lmcfg sim --devicenet`; each needs `devicenet_flag`.
void add_devicenet_sim_options(CLI::App* sim, CLI::Option* devicenet_flag, DevicenetSimArgs& a);
// Serves until should_stop(); the documented exit code.
int run_devicenet_sim(const DevicenetSimArgs& a, const std::function<bool()>& should_stop);

}  // namespace lmcfg::cli
