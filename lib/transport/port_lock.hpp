#pragma once
// The lock a serial transport holds on its device while it is open (see
// PortClaim in transport.hpp): flock on the open descriptor, released when it
// closes, and the lock-info file naming the holder, removed when this object
// goes.
#include <memory>
#include <string>

#include "transport/transport.hpp"

namespace lmcfg::transport {

class PortLock {
 public:
  // flock(LOCK_EX|LOCK_NB) on `fd` (open on `device`) and, for a non-empty
  // holder, the lock-info file. Errc::io_error with port_in_use_message() when
  // another open file holds the lock.
  static Result<std::unique_ptr<PortLock>> take(int fd, const std::string& device,
                                                const PortClaim& claim);
  PortLock(const PortLock&) = delete;
  PortLock& operator=(const PortLock&) = delete;
  ~PortLock();

 private:
  PortLock() = default;
  std::string info_path_;  // "" when nothing was recorded
};

}  // namespace lmcfg::transport
