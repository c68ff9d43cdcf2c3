#include "sim/faults.hpp"

#include "codec/frame.hpp"
#include "sim/link.hpp"

namespace lmcfg::sim {

std::vector<Fault> FaultPlan::take(std::size_t exchange, ByteView request) {
  std::vector<Fault> out;
  if (auto it = planned_.find(exchange); it != planned_.end()) {
    out = std::move(it->second);
    planned_.erase(it);
  }
  if (cb_) {
    auto more = cb_(exchange, request);
    out.insert(out.end(), more.begin(), more.end());
  }
  return out;
}

RequestFaults apply_request_faults(const std::vector<Fault>& faults, const Bus& bus,
                                   const std::shared_ptr<Drive>& target, std::int64_t now_ns,
                                   FaultCounters& fc) {
  RequestFaults out;
  for (const auto& f : faults) {
    switch (f.kind) {
      case Fault::Kind::close_link:
        out.close_link = true;
        ++fc.link_closures;
        return out;
      case Fault::Kind::drop_request:
        out.drop_request = true;
        ++fc.dropped_requests;
        break;
      case Fault::Kind::reset_drive:
        for (const auto& d : bus.drives())
          if (!target || d == target) d->reset(now_ns, !f.instant_reset);
        ++fc.drive_resets;
        break;
      case Fault::Kind::slow_flash:
        for (const auto& d : bus.drives())
          if (!target || d == target) d->make_next_flash_save_slow();
        ++fc.slow_flash_saves;
        break;
      default:
        out.answer_faults.push_back(&f);
        break;
    }
  }
  return out;
}

namespace {
// A valid frame from another ID (checksum recomputed); an undecodable one gets
// the ID byte replaced.
void answer_from_other_id(const Fault& f, const Bus& bus, TimedAnswer& a) {
  auto d = bus.drive(a.from);
  const auto cfg = d ? d->state().checksum : codec::ChecksumConfig{};
  auto t = codec::decode(a.bytes, cfg);
  if (t.ok()) {
    t->id = f.id != 0 ? f.id : static_cast<std::uint8_t>(a.from ^ 0x01);
    if (auto enc = codec::encode(*t, cfg); enc.ok()) a.bytes = std::move(enc).value();
  } else if (a.bytes.size() > 1) {
    a.bytes[1] = f.id != 0 ? f.id : static_cast<std::uint8_t>(a.from ^ 0x01);
  }
}
}  // namespace

bool apply_answer_faults(const std::vector<const Fault*>& faults, const Bus& bus, TimedAnswer& a,
                         Bytes& prefix, FaultCounters& fc) {
  bool dropped = false;
  for (const Fault* f : faults) {
    switch (f->kind) {
      case Fault::Kind::drop_answer:
        dropped = true;
        ++fc.dropped_answers;
        break;
      case Fault::Kind::corrupt_answer:
        if (!a.bytes.empty()) {
          const std::size_t i = f->byte_index < a.bytes.size() ? f->byte_index : a.bytes.size() / 2;
          a.bytes[i] = static_cast<std::uint8_t>(a.bytes[i] ^ f->xor_mask);
          ++fc.corrupted_answers;
        }
        break;
      case Fault::Kind::delay_answer:
        a.ready_ns += static_cast<std::int64_t>(f->delay_ms) * 1'000'000;
        ++fc.delayed_answers;
        break;
      case Fault::Kind::garbage_burst:
        prefix.insert(prefix.end(), f->garbage.begin(), f->garbage.end());
        ++fc.garbage_bursts;
        break;
      case Fault::Kind::wrong_id:
        answer_from_other_id(*f, bus, a);
        ++fc.wrong_id_answers;
        break;
      default:
        break;
    }
  }
  return !dropped;
}

}  // namespace lmcfg::sim
