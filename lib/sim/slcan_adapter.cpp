#include "sim/slcan_adapter.hpp"

#include <string>

#include "can/frame.hpp"

namespace lmcfg::sim {
Result<void> serve_slcan(can::VirtualBus& bus, transport::Transport& serial,
                         const SlcanAdapterOptions& opt) {
  auto endpoint = bus.open("slcan adapter");
  can::slcan::Decoder decoder;
  bool open = false;
  unsigned bitrate = 0;  // none set yet
  bool bus_errors = false;
  while (!(opt.should_stop && opt.should_stop())) {
    LMCFG_ASSIGN_OR_RETURN(auto bytes, serial.read_some(opt.poll));
    std::string out;
    for (auto& e : decoder.feed(bytes)) {
      if (auto* f = std::get_if<can::Frame>(&e)) {
        if (!open) {
          out += '\a';
          continue;
        }
        if (opt.transmit_ack && !opt.silent) out += f->extended ? "Z\r" : "z\r";
        if (bitrate != opt.bus_bitrate) {
          bus_errors = true;  // no node can acknowledge a frame at the wrong rate
          continue;
        }
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
          auto rate = can::slcan::bitrate_of(line[1]);
          if (!open && rate) bitrate = *rate;
          out += open ? "\a" : "\r";
        } else if (line == "F") {
          out += bus_errors ? "FA0\r" : "F00\r";
          bus_errors = false;  // reading the flags clears them
        } else if (line == "V") {
          out += "V" + opt.version + "\r";
        } else {
          out += '\a';
        }
      } else if (std::holds_alternative<can::slcan::Ack>(e)) {
        out += '\r';  // an empty command line: acknowledged, as adapters do
      }
    }
    if (opt.silent) out.clear();  // took the commands, answers none
    // Whatever the bus's nodes answered goes back to the master.
    for (;;) {
      LMCFG_ASSIGN_OR_RETURN(auto f, endpoint->receive(transport::Millis(0)));
      if (!f) break;
      if (open && bitrate == opt.bus_bitrate) out += can::slcan::encode(*f);
    }
    if (!out.empty()) LMCFG_TRY(serial.write(as_bytes(out)));
  }
  return {};
}

}  // namespace lmcfg::sim
