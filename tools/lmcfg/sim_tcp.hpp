#pragma once
// `lmcfg sim --tcp HOST:PORT`, shared by the LinRS and the DeviceNet simulator
// (cmd_sim.cpp): one listener, one client at a time, the simulated devices
// kept between clients.
#include <cstdint>
#include <functional>
#include <string>

#include "common/result.hpp"
#include "transport/transport.hpp"

namespace lmcfg::cli {

// Listens on `tcp` (HOST:PORT as tcp:// ports are written, port 0 = any; a
// bare PORT is on 127.0.0.1), tells `announce` the bound port, then serves
// each client in turn with `serve` until should_stop(). A client that goes
// away ends its turn quietly. The documented exit code (2: not HOST:PORT, 4:
// cannot listen).
int serve_tcp_clients(const std::string& tcp, const std::function<bool()>& should_stop,
                      const std::function<void(std::uint16_t port)>& announce,
                      const std::function<Result<void>(transport::Transport&)>& serve);

}  // namespace lmcfg::cli
