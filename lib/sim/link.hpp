#pragma once
// The wire-time model and the in-process link to simulated drives.
//  - VirtualClock: deterministic time in nanoseconds (reported in microseconds);
//    optionally sleeps so wall-clock figures are honest (real-time mode).
//  - Bus: one RS485 line with one or more drives; every drive hears every byte,
//    only the addressed one answers.
//  - SimLink: transport::Transport over a Bus; write() costs the request's wire
//    time, read_some() delivers answers when they are "on the line".
//  - the faults it injects per exchange: sim/faults.hpp.
#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <vector>

#include "codec/frame.hpp"
#include "sim/drive.hpp"
#include "sim/faults.hpp"
#include "transport/transport.hpp"

namespace lmcfg::sim {

// Wire time of `bytes` bytes: bytes * (1 start + 8 data + parity + stop bits) / baud,
// rounded to the nearest nanosecond.
std::int64_t wire_time_ns(std::size_t bytes, const transport::SerialSettings& line);
double byte_time_us(const transport::SerialSettings& line);

class VirtualClock {
 public:
  std::int64_t now_ns() const { return now_ns_; }
  double now_us() const { return static_cast<double>(now_ns_) / 1000.0; }
  double now_s() const { return static_cast<double>(now_ns_) / 1e9; }
  void advance_ns(std::int64_t d);
  void advance_us(double d) { advance_ns(static_cast<std::int64_t>(d * 1000.0 + 0.5)); }
  void advance_to_ns(std::int64_t t) {
    if (t > now_ns_) advance_ns(t - now_ns_);
  }
  // Real-time mode: every advance sleeps until the wall clock has caught up
  // with the virtual time (anchored when the mode is switched on).
  void set_real_time(bool on);
  bool real_time() const { return real_time_; }

 private:
  std::int64_t now_ns_ = 0;
  bool real_time_ = false;
  std::chrono::steady_clock::time_point anchor_{};
  std::int64_t anchor_virtual_ns_ = 0;
};

// An answer scheduled on the line.
struct TimedAnswer {
  std::uint8_t from = 0;  // MACID of the drive that answered
  Bytes bytes;
  std::int64_t ready_ns = 0;  // when its first byte starts
};

class Bus {
 public:
  explicit Bus(transport::SerialSettings line = {}) : line_(std::move(line)) {}
  void add(std::shared_ptr<Drive> d) { drives_.push_back(std::move(d)); }
  const std::vector<std::shared_ptr<Drive>>& drives() const { return drives_; }
  std::shared_ptr<Drive> drive(std::uint8_t macid) const;  // nullptr when absent
  VirtualClock& clock() { return clock_; }
  const transport::SerialSettings& line() const { return line_; }
  void set_line(transport::SerialSettings s) { line_ = std::move(s); }
  // Every drive hears the bytes (their last byte at now_ns).
  std::vector<TimedAnswer> transmit(ByteView bytes, std::int64_t now_ns);

 private:
  transport::SerialSettings line_;
  std::vector<std::shared_ptr<Drive>> drives_;
  VirtualClock clock_;
};

struct LinkStats {
  std::uint64_t write_calls = 0;  // = exchanges
  std::uint64_t read_calls = 0;
  std::uint64_t read_timeouts = 0;      // read_some calls that returned nothing
  std::uint64_t request_telegrams = 0;  // complete frames written by the master (any ID)
  std::uint64_t request_bytes = 0;
  std::uint64_t answer_telegrams = 0;  // answers put on the line (after faults)
  std::uint64_t answer_bytes = 0;      // bytes put on the line towards the master
  std::uint64_t delivered_bytes = 0;   // bytes handed out by read_some
  std::uint64_t discarded_bytes = 0;
};

class SimLink : public transport::Transport {
 public:
  // One drive on its own line (settings taken from the drive's state).
  explicit SimLink(std::shared_ptr<Drive> drive);
  explicit SimLink(std::shared_ptr<Bus> bus);

  Result<void> write(ByteView bytes) override;
  Result<Bytes> read_some(transport::Millis timeout) override;
  void discard_input() override;
  std::string describe() const override;
  double byte_time_us() const override { return sim::byte_time_us(bus_->line()); }
  std::int64_t now_ns() const override { return bus_->clock().now_ns(); }
  // The master's side of the line: a drive hears only a master at its own settings.
  Result<void> reconfigure(const transport::SerialSettings& s) override;

  VirtualClock& clock() { return bus_->clock(); }
  Bus& bus() { return *bus_; }
  std::shared_ptr<Drive> drive(std::uint8_t macid) const { return bus_->drive(macid); }
  FaultPlan& faults() { return faults_; }
  const LinkStats& stats() const { return stats_; }
  void reset_stats() { stats_ = {}; }
  void set_real_time(bool on) { bus_->clock().set_real_time(on); }
  void close() { closed_ = true; }
  bool closed() const { return closed_; }
  // Bytes on the way to the master that have not been read yet.
  std::size_t pending_bytes() const;

 private:
  struct Chunk {
    Bytes bytes;
    std::int64_t start_ns = 0;  // first bit
  };
  Error closed_error() const;
  void count_request(ByteView bytes);
  void put_on_line(Bytes prefix, const TimedAnswer& a);          // an answer after its faults
  std::int64_t arrival_of(const Chunk& c, std::size_t i) const;  // time byte i is complete

  std::shared_ptr<Bus> bus_;
  FaultPlan faults_;
  LinkStats stats_;
  codec::StreamDecoder monitor_;
  std::deque<Chunk> pending_;
  std::int64_t line_free_ns_ = 0;  // the slave side of the line is busy until then
  bool closed_ = false;
};

}  // namespace lmcfg::sim
