#include "sim/slcan_adapter.hpp"

#include <string>

#include "can/frame.hpp"

namespace lmcfg::sim {
Result<void> serve_slcan(can::VirtualBus& bus, transport::Transport& serial,
                         const SlcanAdapterOptions& opt) {
  auto endpoint = bus.open("slcan adapter");
  can::slcan::Decoder decoder;
  bool open = false;
  while (!(opt.should_stop && opt.should_stop())) {
    LMCFG_ASSIGN_OR_RETURN(auto bytes, serial.read_some(opt.poll));
    std::string out;
    for (auto& e : decoder.feed(bytes)) {
      if (auto* f = std::get_if<can::Frame>(&e)) {
        if (!open) {
          out += '\a';
          continue;
        }
        if (opt.transmit_ack) out += f->extended ? "Z\r" : "z\r";
        LMCFG_TRY(endpoint->send(*f));
      } else if (auto* u = std::get_if<can::slcan::Unknown>(&e)) {
        const std::string& line = u->line;
        if (line == "O") {
          out += open ? "\a" : "\r";
          open = true;
        } else if (line == "C") {
          out += open ? "\r" : "\a";
          open = false;
        } else if (line.size() == 2 && line[0] == 'S' && line[1] >= '0' && line[1] <= '8') {
          out += open ? "\a" : "\r";
        } else {
          out += '\a';
        }
      } else if (std::holds_alternative<can::slcan::Ack>(e)) {
        out += '\r';  // an empty command line: acknowledged, as adapters do
      }
    }
    // Whatever the bus's nodes answered goes back to the master.
    for (;;) {
      LMCFG_ASSIGN_OR_RETURN(auto f, endpoint->receive(transport::Millis(0)));
      if (!f) break;
      if (open) out += can::slcan::encode(*f);
    }
    if (!out.empty()) LMCFG_TRY(serial.write(as_bytes(out)));
  }
  return {};
}

}  // namespace lmcfg::sim
