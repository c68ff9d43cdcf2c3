#include "sim/link.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <thread>

namespace lmcfg::sim {

std::int64_t wire_time_ns(std::size_t bytes, const transport::SerialSettings& line) {
  const double bits = static_cast<double>(transport::bits_per_byte(line));
  const double baud = line.baud == 0 ? 57600.0 : static_cast<double>(line.baud);
  return std::llround(static_cast<double>(bytes) * bits * 1e9 / baud);
}

double byte_time_us(const transport::SerialSettings& line) {
  const double baud = line.baud == 0 ? 57600.0 : static_cast<double>(line.baud);
  return static_cast<double>(transport::bits_per_byte(line)) * 1e6 / baud;
}

void VirtualClock::advance_ns(std::int64_t d) {
  if (d <= 0) return;
  now_ns_ += d;
  if (real_time_)
    std::this_thread::sleep_until(anchor_ + std::chrono::nanoseconds(now_ns_ - anchor_virtual_ns_));
}

void VirtualClock::set_real_time(bool on) {
  real_time_ = on;
  anchor_ = std::chrono::steady_clock::now();
  anchor_virtual_ns_ = now_ns_;
}

std::shared_ptr<Drive> Bus::drive(std::uint8_t macid) const {
  for (const auto& d : drives_)
    if (d->macid() == macid) return d;
  return nullptr;
}

namespace {
// Bytes sent at other settings reach a UART as garbage or framing errors: the
// drive hears nothing it can decode, and the master cannot decode its answers.
bool same_line(const transport::SerialSettings& a, const transport::SerialSettings& b) {
  return a.baud == b.baud && a.parity == b.parity && a.stop_bits == b.stop_bits;
}
}  // namespace

std::vector<TimedAnswer> Bus::transmit(ByteView bytes, std::int64_t now_ns) {
  std::vector<TimedAnswer> out;
  for (const auto& d : drives_) {
    if (!same_line(d->state().link, line_)) continue;
    auto answers = d->receive(bytes, now_ns);
    // A reset may have switched the drive to other settings before it answers.
    if (!same_line(d->state().link, line_)) continue;
    for (auto& a : answers) out.push_back({d->macid(), std::move(a.bytes), now_ns + a.delay_ns});
  }
  std::stable_sort(out.begin(), out.end(),
                   [](const auto& a, const auto& b) { return a.ready_ns < b.ready_ns; });
  return out;
}

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

SimLink::SimLink(std::shared_ptr<Drive> drive) : bus_(std::make_shared<Bus>(drive->state().link)) {
  bus_->add(std::move(drive));
}

SimLink::SimLink(std::shared_ptr<Bus> bus) : bus_(std::move(bus)) {}

Error SimLink::closed_error() const {
  return Error(Errc::link_closed, describe() + ": link closed");
}

std::int64_t SimLink::arrival_of(const Chunk& c, std::size_t i) const {
  return c.start_ns + wire_time_ns(i + 1, bus_->line());
}

std::size_t SimLink::pending_bytes() const {
  std::size_t n = 0;
  for (const auto& c : pending_) n += c.bytes.size();
  return n;
}

Result<void> SimLink::reconfigure(const transport::SerialSettings& s) {
  LMCFG_TRY(transport::validate(s));
  transport::SerialSettings line = s;
  line.device.clear();
  bus_->set_line(line);
  return {};
}

std::string SimLink::describe() const {
  std::string s = "sim " + transport::format_settings(bus_->line());
  char buf[16];
  for (std::size_t i = 0; i < bus_->drives().size(); ++i) {
    std::snprintf(buf, sizeof buf, "%s%02Xh", i == 0 ? " ID " : ",", bus_->drives()[i]->macid());
    s += buf;
  }
  return s;
}

Result<void> SimLink::write(ByteView bytes) {
  if (closed_) return closed_error();
  const std::size_t exchange = stats_.write_calls++;
  auto faults = faults_.take(exchange, bytes);
  auto& fc = faults_.counters();
  auto& clock = bus_->clock();

  stats_.request_bytes += bytes.size();
  if (!bus_->drives().empty()) monitor_.set_checksum(bus_->drives().front()->state().checksum);
  monitor_.feed(bytes);
  while (auto r = monitor_.next())
    if (r->ok()) ++stats_.request_telegrams;

  clock.advance_ns(wire_time_ns(bytes.size(), bus_->line()));
  const std::int64_t now = clock.now_ns();

  // The addressed drive: the ID byte of the first frame in the request.
  std::shared_ptr<Drive> target;
  for (std::size_t i = 0; i + 1 < bytes.size(); ++i)
    if (bytes[i] == codec::kStartHeader) {
      target = bus_->drive(bytes[i + 1]);
      break;
    }

  bool drop_request = false;
  std::vector<const Fault*> answer_faults;
  for (const auto& f : faults) {
    switch (f.kind) {
      case Fault::Kind::close_link:
        closed_ = true;
        ++fc.link_closures;
        return closed_error();
      case Fault::Kind::drop_request:
        drop_request = true;
        ++fc.dropped_requests;
        break;
      case Fault::Kind::reset_drive:
        for (const auto& d : bus_->drives())
          if (!target || d == target) d->reset(now, !f.instant_reset);
        ++fc.drive_resets;
        break;
      case Fault::Kind::slow_flash:
        for (const auto& d : bus_->drives())
          if (!target || d == target) d->make_next_flash_save_slow();
        ++fc.slow_flash_saves;
        break;
      default:
        answer_faults.push_back(&f);
        break;
    }
  }
  if (drop_request) return {};

  for (auto& a : bus_->transmit(bytes, now)) {
    bool dropped = false;
    Bytes prefix;
    for (const Fault* f : answer_faults) {
      switch (f->kind) {
        case Fault::Kind::drop_answer:
          dropped = true;
          ++fc.dropped_answers;
          break;
        case Fault::Kind::corrupt_answer:
          if (!a.bytes.empty()) {
            const std::size_t i =
                f->byte_index < a.bytes.size() ? f->byte_index : a.bytes.size() / 2;
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
        case Fault::Kind::wrong_id: {
          auto d = bus_->drive(a.from);
          const auto cfg = d ? d->state().checksum : codec::ChecksumConfig{};
          auto t = codec::decode(a.bytes, cfg);
          if (t.ok()) {
            t->id = f->id != 0 ? f->id : static_cast<std::uint8_t>(a.from ^ 0x01);
            if (auto enc = codec::encode(*t, cfg); enc.ok()) a.bytes = std::move(enc).value();
          } else if (a.bytes.size() > 1) {
            a.bytes[1] = f->id != 0 ? f->id : static_cast<std::uint8_t>(a.from ^ 0x01);
          }
          ++fc.wrong_id_answers;
          break;
        }
        default:
          break;
      }
    }
    if (dropped) continue;
    Chunk c;
    c.bytes = std::move(prefix);
    c.bytes.insert(c.bytes.end(), a.bytes.begin(), a.bytes.end());
    c.start_ns = std::max(a.ready_ns, line_free_ns_);
    line_free_ns_ = c.start_ns + wire_time_ns(c.bytes.size(), bus_->line());
    ++stats_.answer_telegrams;
    stats_.answer_bytes += c.bytes.size();
    pending_.push_back(std::move(c));
  }
  return {};
}

Result<Bytes> SimLink::read_some(transport::Millis timeout) {
  if (closed_) return closed_error();
  ++stats_.read_calls;
  auto& clock = bus_->clock();
  const std::int64_t deadline =
      clock.now_ns() + static_cast<std::int64_t>(timeout.count()) * 1'000'000;
  if (pending_.empty() || arrival_of(pending_.front(), 0) > deadline) {
    clock.advance_to_ns(deadline);
    ++stats_.read_timeouts;
    return Bytes{};
  }
  Bytes out;
  {
    Chunk& c = pending_.front();
    clock.advance_to_ns(arrival_of(c, c.bytes.size() - 1));
    out = std::move(c.bytes);
    pending_.pop_front();
  }
  // Anything else that has completely arrived meanwhile comes along.
  while (!pending_.empty() &&
         arrival_of(pending_.front(), pending_.front().bytes.size() - 1) <= clock.now_ns()) {
    out.insert(out.end(), pending_.front().bytes.begin(), pending_.front().bytes.end());
    pending_.pop_front();
  }
  stats_.delivered_bytes += out.size();
  return out;
}

void SimLink::discard_input() {
  const std::int64_t now = bus_->clock().now_ns();
  while (!pending_.empty()) {
    Chunk& c = pending_.front();
    std::size_t arrived = 0;
    while (arrived < c.bytes.size() && arrival_of(c, arrived) <= now) ++arrived;
    if (arrived == 0) break;
    stats_.discarded_bytes += arrived;
    if (arrived == c.bytes.size()) {
      pending_.pop_front();
      continue;
    }
    c.start_ns += wire_time_ns(arrived, bus_->line());
    c.bytes.erase(c.bytes.begin(), c.bytes.begin() + static_cast<std::ptrdiff_t>(arrived));
    break;
  }
}

}  // namespace lmcfg::sim
