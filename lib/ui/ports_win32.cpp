// Windows: the COM ports Windows knows (transport::list_serial_ports,
// QueryDosDevice). The adapter's friendly name (SetupAPI's
// SPDRP_FRIENDLYNAME) is not read yet: each port is listed by its name only
// (docs/ui.md "Not done yet"), and a port another program holds says so
// when it is opened ("port COM3 is in use by ...").
#include "transport/ports.hpp"
#include "transport/transport.hpp"
#include "ui/ports.hpp"

namespace lmcfg::ui {

std::string port_user(const std::string& device, const PortRoots&) {
  if (auto h = transport::port_holder(device))
    return (h->holder.empty() ? "a program" : h->holder) + " (PID " + std::to_string(h->pid) + ")";
  return "";
}

std::vector<SerialPortInfo> list_ports(const PortRoots& roots) {
  std::vector<SerialPortInfo> out;
  for (const auto& name : transport::list_serial_ports()) {
    SerialPortInfo p;
    p.port = name;
    p.held_by = port_user(name, roots);
    out.push_back(std::move(p));
  }
  return out;
}

}  // namespace lmcfg::ui
