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

namespace {
// The addressed drive: the ID byte of the first frame in the request.
std::shared_ptr<Drive> addressed(const Bus& bus, ByteView bytes) {
  for (std::size_t i = 0; i + 1 < bytes.size(); ++i)
    if (bytes[i] == codec::kStartHeader) return bus.drive(bytes[i + 1]);
  return nullptr;
}
}  // namespace

Result<void> SimLink::write(ByteView bytes) {
  if (closed_) return closed_error();
  const std::size_t exchange = stats_.write_calls++;
  auto faults = faults_.take(exchange, bytes);
  count_request(bytes);
  auto& clock = bus_->clock();
  clock.advance_ns(wire_time_ns(bytes.size(), bus_->line()));
  const std::int64_t now = clock.now_ns();

  const RequestFaults rf =
      apply_request_faults(faults, *bus_, addressed(*bus_, bytes), now, faults_.counters());
  if (rf.close_link) {
    closed_ = true;
    return closed_error();
  }
  if (rf.drop_request) return {};
  for (auto& a : bus_->transmit(bytes, now)) {
    Bytes prefix;
    if (apply_answer_faults(rf.answer_faults, *bus_, a, prefix, faults_.counters()))
      put_on_line(std::move(prefix), a);
  }
  return {};
}

// The master's request as the line statistics count it.
void SimLink::count_request(ByteView bytes) {
  stats_.request_bytes += bytes.size();
  if (!bus_->drives().empty()) monitor_.set_checksum(bus_->drives().front()->state().checksum);
  monitor_.feed(bytes);
  while (auto r = monitor_.next())
    if (r->ok()) ++stats_.request_telegrams;
}

// The answer goes on the line when it is ready and the line is free.
void SimLink::put_on_line(Bytes prefix, const TimedAnswer& a) {
  Chunk c;
  c.bytes = std::move(prefix);
  c.bytes.insert(c.bytes.end(), a.bytes.begin(), a.bytes.end());
  c.start_ns = std::max(a.ready_ns, line_free_ns_);
  line_free_ns_ = c.start_ns + wire_time_ns(c.bytes.size(), bus_->line());
  ++stats_.answer_telegrams;
  stats_.answer_bytes += c.bytes.size();
  pending_.push_back(std::move(c));
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
