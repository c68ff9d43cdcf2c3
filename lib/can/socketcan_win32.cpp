// Windows has no SocketCAN: a CAN adapter is used through its serial port
// speaking slcan (--port slcan:COM5), as on Linux.
#include "can/link.hpp"

namespace lmcfg::can {

Result<std::unique_ptr<Link>> open_socketcan(const std::string& interface) {
  return Error(Errc::not_supported,
               "CAN interface " + interface +
                   ": SocketCAN exists only on Linux; on Windows use a USB adapter speaking "
                   "slcan through its COM port: --port slcan:COM5 (docs/windows.md)");
}

}  // namespace lmcfg::can
