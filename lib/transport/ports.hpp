#pragma once
// The serial ports of this computer (serial.cpp, serial_win32.cpp).
#include <string>
#include <vector>

namespace lmcfg::transport {

// Sorted, for `lmcfg scan` without --port: on Linux /dev/serial/by-id/* (USB
// adapters by name), else /dev/ttyUSB* and /dev/ttyACM*; on Windows the COM
// ports QueryDosDevice knows ("COM3", "COM10").
std::vector<std::string> list_serial_ports();

}  // namespace lmcfg::transport
