#pragma once
// A simulated slcan (Lawicel) USB-CAN adapter: speaks the adapter's side of
// the ASCII protocol on a byte transport (the master side of a pty) and
// carries frames to and from a can::VirtualBus, so the tools reach a
// simulated DeviceNet controller through a real serial port. docs/can.md.
#include <functional>

#include "can/virtual_bus.hpp"
#include "transport/transport.hpp"

namespace lmcfg::sim {

struct SlcanAdapterOptions {
  transport::Millis poll{20};
  std::function<bool()> should_stop;  // nullptr: until the transport fails
  bool transmit_ack = true;           // "z\r" after each transmitted frame
  // An adapter that answers no command at all (slcan: whether an
  // adapter acknowledges is open; the Linux slcan driver and python-can never
  // wait for it): no CR/BEL to C, Sn, O, no "z", no answer to V or F. It
  // still takes the commands.
  bool silent = false;
  // "V": the hardware and software version an adapter reports ("V1013").
  std::string version = "1013";
  // The bus's bit rate. An adapter opened at another rate ("Sn") hears nothing
  // and its frames are never acknowledged: it counts bus errors, which "F"
  // (read status flags) reports as bit 7 (bus error) and bit 5 (error
  // passive), as a Lawicel adapter does.
  unsigned bus_bitrate = 125000;
};

// Serves until should_stop() (ok) or the transport fails (its error). Before
// "O" (and after "C") frames are neither sent nor delivered, as on a real
// adapter; "Sn" is refused (BEL) while the channel is open.
Result<void> serve_slcan(can::VirtualBus& bus, transport::Transport& serial,
                         const SlcanAdapterOptions& opt);

}  // namespace lmcfg::sim
