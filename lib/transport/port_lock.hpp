#pragma once
// The lock a serial transport holds on its device while it is open (see
// PortClaim in transport.hpp): flock on the open descriptor, released when it
// closes, and the lock-info file naming the holder, removed when this object
// goes.
#include <memory>
#include <string>

#include "transport/transport.hpp"

namespace lmcfg::transport {

// port_in_use_message() from what the lock records: one text on every platform.
inline std::string in_use_text(const std::string& device, const std::optional<PortHolder>& h) {
  if (h && !h->holder.empty())
    return "port " + device + " is in use by " + h->holder + " (PID " + std::to_string(h->pid) +
           ")";
  return "port " + device + " is in use by another program";
}

// Windows: the device path of a COM port name ("COM7", "com7", "\\.\COM10"
// -> "\\.\COM7"...), nullopt for anything else (serial_win32.cpp).
std::optional<std::string> com_port_path(const std::string& device);

class PortLock {
 public:
  // flock(LOCK_EX|LOCK_NB) on `fd` (open on `device`) and, for a non-empty
  // holder, the lock-info file. On Windows (port_lock_win32.cpp) `fd` is
  // unused: the lock is the exclusive open of the port's lock file, taken
  // before the port is opened. Errc::io_error with port_in_use_message() when
  // another open file holds the lock.
  static Result<std::unique_ptr<PortLock>> take(int fd, const std::string& device,
                                                const PortClaim& claim);
  PortLock(const PortLock&) = delete;
  PortLock& operator=(const PortLock&) = delete;
  ~PortLock();

 private:
  PortLock() = default;
  std::string info_path_;  // "" when nothing was recorded
  // Windows: the open lock file, closed before the file is removed (unused on POSIX).
  std::shared_ptr<void> held_;
};

}  // namespace lmcfg::transport
