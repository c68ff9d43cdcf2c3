#pragma once
// Serving a simulated LinUDP drive on a real UDP socket (`lmcfg sim --linudp
// --udp HOST:PORT`), in real time: each reply leaves after its modelled delay.
#include <functional>

#include "sim/linudp_drive.hpp"
#include "transport/udp.hpp"

namespace lmcfg::sim {

struct LinudpServeOptions {
  transport::Millis poll{20};         // how often should_stop is checked
  std::function<bool()> should_stop;  // nullptr: never
  std::function<void(bool tx, ByteView bytes)> trace;
  bool real_time = true;  // false: replies at once (--fast)
};

Result<void> serve_linudp(LinudpDrive& drive, transport::UdpServer& socket,
                          const LinudpServeOptions& opt);

}  // namespace lmcfg::sim
