// SocketCAN (Linux): a raw CAN socket bound to a network interface (can0, vcan0).
#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "can/link.hpp"
#include "transport/pty.hpp"

namespace lmcfg::can {
namespace {

class SocketCanLink final : public Link {
 public:
  SocketCanLink(transport::UniqueFd fd, std::string name)
      : fd_(std::move(fd)), name_(std::move(name)) {}

  Result<void> send(const Frame& f) override {
    LMCFG_TRY(validate(f));
    can_frame raw{};
    raw.can_id = f.id | (f.extended ? CAN_EFF_FLAG : 0u) | (f.rtr ? CAN_RTR_FLAG : 0u);
    raw.can_dlc = f.len;
    std::memcpy(raw.data, f.data.data(), f.len);
    if (::write(fd_.get(), &raw, sizeof raw) != static_cast<ssize_t>(sizeof raw)) {
      return Error(Errc::io_error, describe() + ": send: " + std::strerror(errno));
    }
    return {};
  }

  Result<std::optional<Frame>> receive(transport::Millis timeout) override {
    pollfd p{fd_.get(), POLLIN, 0};
    const int rc = ::poll(&p, 1, static_cast<int>(timeout.count()));
    if (rc < 0 && errno != EINTR)
      return Error(Errc::io_error, describe() + ": poll: " + std::strerror(errno));
    if (rc <= 0) return std::optional<Frame>();
    can_frame raw{};
    if (::read(fd_.get(), &raw, sizeof raw) != static_cast<ssize_t>(sizeof raw)) {
      return Error(Errc::io_error, describe() + ": receive: " + std::strerror(errno));
    }
    Frame f;
    f.extended = (raw.can_id & CAN_EFF_FLAG) != 0;
    f.rtr = (raw.can_id & CAN_RTR_FLAG) != 0;
    f.id = raw.can_id & (f.extended ? CAN_EFF_MASK : CAN_SFF_MASK);
    f.len = std::min<std::uint8_t>(raw.can_dlc, 8);
    std::memcpy(f.data.data(), raw.data, f.len);
    return std::optional<Frame>(f);
  }

  std::string describe() const override { return "socketcan " + name_; }

 private:
  transport::UniqueFd fd_;
  std::string name_;
};

}  // namespace

Result<std::unique_ptr<Link>> open_socketcan(const std::string& ifname) {
  const std::string where = "CAN interface " + ifname;
  if (ifname.empty() || ifname.size() >= IFNAMSIZ)
    return Error(Errc::invalid_argument, where + ": not an interface name");
  transport::UniqueFd fd(::socket(PF_CAN, SOCK_RAW | SOCK_CLOEXEC, CAN_RAW));
  if (!fd) {
    const bool no_can = errno == EAFNOSUPPORT || errno == EPROTONOSUPPORT;
    return Error(Errc::io_error, where + ": socket: " + std::strerror(errno) +
                                     (no_can ? " (this kernel has no SocketCAN: modprobe can_raw, "
                                               "or use a USB adapter speaking slcan: --port "
                                               "slcan:/dev/ttyACM0)"
                                             : ""));
  }
  ifreq ifr{};
  std::memcpy(ifr.ifr_name, ifname.c_str(), ifname.size());
  if (::ioctl(fd.get(), SIOCGIFINDEX, &ifr) != 0) {
    return Error(Errc::io_error,
                 where + ": " + std::strerror(errno) +
                     " (no such interface? `ip link` lists them; a USB adapter speaking slcan "
                     "is --port slcan:/dev/ttyACM0)");
  }
  sockaddr_can addr{};
  addr.can_family = AF_CAN;
  addr.can_ifindex = ifr.ifr_ifindex;
  if (::bind(fd.get(), reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0)
    return Error(Errc::io_error, where + ": bind: " + std::strerror(errno));
  return std::unique_ptr<Link>(std::make_unique<SocketCanLink>(std::move(fd), ifname));
}

}  // namespace lmcfg::can
