#pragma once
// An in-process CAN bus for tests and simulations: endpoints are can::Link
// objects; nodes (simulated devices) see every frame an endpoint sends and
// answer at once, inside that send. Deterministic: no threads, no clock.
#include <deque>
#include <functional>
#include <memory>
#include <vector>

#include "can/link.hpp"

namespace lmcfg::can {

class VirtualBus : public std::enable_shared_from_this<VirtualBus> {
 public:
  // A simulated device: called with each frame an endpoint sends; it answers
  // with VirtualBus::put.
  using Node = std::function<void(const Frame& f, VirtualBus& bus)>;

  std::unique_ptr<Link> open(std::string name);
  void attach(Node node) { nodes_.push_back(std::move(node)); }
  // Puts a frame on the bus: every endpoint but `from` receives it; nodes
  // receive frames from endpoints only.
  void put(const Frame& f, const void* from = nullptr);
  std::uint64_t frames() const { return frames_; }

 private:
  friend class VirtualEndpoint;
  std::vector<std::deque<Frame>*> queues_;
  std::vector<Node> nodes_;
  std::uint64_t frames_ = 0;
};

}  // namespace lmcfg::can
