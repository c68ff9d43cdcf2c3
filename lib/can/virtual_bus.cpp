#include "can/virtual_bus.hpp"

#include <algorithm>
#include <thread>

namespace lmcfg::can {

class VirtualEndpoint final : public Link {
 public:
  VirtualEndpoint(std::shared_ptr<VirtualBus> bus, std::string name)
      : bus_(std::move(bus)), name_(std::move(name)) {
    bus_->queues_.push_back(&queue_);
  }
  ~VirtualEndpoint() override {
    auto& q = bus_->queues_;
    q.erase(std::remove(q.begin(), q.end(), &queue_), q.end());
  }
  Result<void> send(const Frame& f) override {
    LMCFG_TRY(validate(f));
    bus_->put(f, &queue_);
    return {};
  }
  Result<std::optional<Frame>> receive(transport::Millis timeout) override {
    // Nodes answer inside send(): an empty queue stays empty, so the wait a
    // real bus would have is slept at once.
    if (queue_.empty()) {
      std::this_thread::sleep_for(timeout);
      return std::optional<Frame>();
    }
    Frame f = queue_.front();
    queue_.pop_front();
    return std::optional<Frame>(f);
  }
  std::string describe() const override { return "virtual CAN " + name_; }

 private:
  std::shared_ptr<VirtualBus> bus_;
  std::string name_;
  std::deque<Frame> queue_;
};

std::unique_ptr<Link> VirtualBus::open(std::string name) {
  return std::make_unique<VirtualEndpoint>(shared_from_this(), std::move(name));
}

void VirtualBus::put(const Frame& f, const void* from) {
  ++frames_;
  for (auto* q : queues_)
    if (q != from) q->push_back(f);
  if (!from) return;
  // Copy: a node may attach or answer (put) while being called.
  const auto nodes = nodes_;
  for (const auto& n : nodes) n(f, *this);
}

}  // namespace lmcfg::can
