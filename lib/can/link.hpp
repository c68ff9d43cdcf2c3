#pragma once
// One small frame interface for CAN adapters (docs/can.md), next to the byte
// transports: CAN carries frames, not a byte stream.
//   can0, vcan0            SocketCAN network interface (Linux): open_socketcan
//   slcan:/dev/ttyACM0     serial-line adapter speaking slcan (Lawicel ASCII): open_slcan
// Framing of the application protocol (DeviceNet) stays above this layer.
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "can/frame.hpp"
#include "transport/pty.hpp"
#include "transport/transport.hpp"

namespace lmcfg::can {

class Link {
 public:
  virtual ~Link() = default;
  // Queues one frame for the bus (slcan: the adapter's acknowledgement is
  // waited for only with SlcanOptions::expect_transmit_ack).
  virtual Result<void> send(const Frame& f) = 0;
  // The next frame from the bus, waiting at most `timeout`; nullopt on timeout.
  virtual Result<std::optional<Frame>> receive(transport::Millis timeout) = 0;
  virtual std::string describe() const = 0;
  // The adapter's error flags since the last call (slcan "F"), nonzero after
  // bus errors, e.g. frames no node acknowledged (a wrong bit rate, a bus
  // without the device); nullopt where the adapter cannot tell.
  virtual Result<std::optional<std::uint8_t>> status_flags() {
    return std::optional<std::uint8_t>();
  }
};

struct SlcanOptions {
  unsigned bitrate = 125000;
  // Lawicel adapters acknowledge each transmitted frame ("z\r", some "\r"),
  // others send nothing (slcan leaves it open). false (the default, as the
  // Linux slcan driver and python-can): do not wait, drop the acknowledgements
  // that come; true: wait for each (never for an adapter that answered
  // neither "C" nor "V" when opened).
  bool expect_transmit_ack = false;
  transport::Millis ack_timeout{200};
};

// Sets the bit rate and opens the channel on an adapter behind `serial`
// ("C", "V", "Sn", "O"); closes the channel ("C") when destroyed. The
// adapter's answers are used when it gives them (a BEL to "Sn" or "O" is a
// refusal; the version goes into describe()), never required: an adapter
// that answers nothing is opened, and describe() says so.
Result<std::unique_ptr<Link>> open_slcan(std::unique_ptr<transport::Transport> serial,
                                         const SlcanOptions& opt);
// SocketCAN interface by name; its bit rate is the interface's (ip link set
// can0 type can bitrate 125000).
Result<std::unique_ptr<Link>> open_socketcan(const std::string& ifname);
// Ports ("slcan:/dev/ttyACM0", "can0") are opened through the table of port
// schemes: link::open_can_link (link/port.hpp).

// Writes each frame as a line ("TX 123 [2] AA BB" plus what `annotate` says of
// it, e.g. its DeviceNet meaning) to `sink`, then passes it on.
class TraceLink final : public Link {
 public:
  using Sink = std::function<void(const std::string& line)>;
  using Annotate = std::function<std::string(const Frame& f, bool tx)>;
  TraceLink(std::unique_ptr<Link> inner, Sink sink, Annotate annotate = nullptr)
      : inner_(std::move(inner)), sink_(std::move(sink)), annotate_(std::move(annotate)) {}
  Result<void> send(const Frame& f) override;
  Result<std::optional<Frame>> receive(transport::Millis timeout) override;
  std::string describe() const override { return inner_->describe(); }
  Result<std::optional<std::uint8_t>> status_flags() override { return inner_->status_flags(); }

 private:
  void trace(const Frame& f, bool tx);
  std::unique_ptr<Link> inner_;
  Sink sink_;
  Annotate annotate_;
};

}  // namespace lmcfg::can
