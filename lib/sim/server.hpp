#pragma once
// Serving a simulated drive to real programs: over any transport::Transport
// (the master side of a pty, an accepted TCP connection), in real time.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "sim/drive.hpp"
#include "transport/pty.hpp"
#include "transport/transport.hpp"

namespace lmcfg::sim {

struct ServeOptions {
  // true: each answer goes out after its modelled delay (turnaround, defaulting,
  // flash save, reset...) plus the answer's wire time at the drive's baud rate.
  // false: answers go out as soon as they are computed.
  bool real_time = true;
  transport::Millis poll{20};                          // how often should_stop is checked
  std::function<bool()> should_stop;                   // stop when it returns true (nullptr: never)
  std::function<void(bool tx, ByteView bytes)> trace;  // tx = from the drive
  // The master's baud rate, where the link can tell (a pty master reports what
  // its slave was set to, transport::line_baud). While it differs from the
  // drive's own rate the drive hears no telegram and its answers are lost, as
  // on a real line. nullptr or nullopt: not checked (TCP).
  std::function<std::optional<unsigned>()> master_baud;
};

struct ServeStats {
  std::uint64_t bytes_in = 0, bytes_out = 0, answers = 0;
  std::uint64_t bytes_at_wrong_baud = 0;  // heard and dropped, or answers not sent
};

// Serves until should_stop() is true (returns ok) or the transport fails
// (returns its error; Errc::link_closed when the peer went away).
Result<void> serve(Drive& drive, transport::Transport& link, const ServeOptions& opt,
                   ServeStats* stats = nullptr);
// The same for an RS485 line with several drives (distinct MACIDs): every
// drive hears every byte; only the addressed one answers.
Result<void> serve_bus(const std::vector<Drive*>& drives, transport::Transport& link,
                       const ServeOptions& opt, ServeStats* stats = nullptr);

// Loopback TCP listener for `lmcfg sim --tcp`. Port 0 picks a free port;
// the bound port is returned in `bound_port`.
Result<transport::UniqueFd> listen_tcp(const std::string& host, std::uint16_t port,
                                       std::uint16_t& bound_port);
// Waits up to `timeout` for a client; an invalid UniqueFd on timeout.
Result<transport::UniqueFd> accept_client(int listen_fd, transport::Millis timeout);

}  // namespace lmcfg::sim
