#include "sim_ports.hpp"

#include "link/port.hpp"
#include "sim/state_file.hpp"

namespace lmcfg::test {

const bool kSimPortsRegistered = [] {
  link::register_scheme("sim", sim::state_file_link_factory());
  return true;
}();

}  // namespace lmcfg::test
