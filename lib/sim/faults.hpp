#pragma once
// The faults the simulated line injects (the reliability work), kept apart
// from the data path of SimLink (sim/link.hpp): what a fault is, the plan of
// faults per exchange, their counters, and what each does to a request and to
// the answers.
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <vector>

#include "common/bytes.hpp"

namespace lmcfg::sim {

class Bus;
class Drive;
struct TimedAnswer;

struct Fault {
  enum class Kind : std::uint8_t {
    drop_request,    // the drives never hear the request
    drop_answer,     // the drive answers, the master never sees it
    corrupt_answer,  // one byte of the answer XORed with xor_mask
    delay_answer,    // the answer comes delay_ms later
    garbage_burst,   // `garbage` bytes on the line before the answer
    wrong_id,        // the answer carries MACID `id` (valid frame, checksum recomputed)
    reset_drive,     // the addressed drive resets as the request arrives (forgets transfers)
    slow_flash,      // the next flash save takes Timing::flash_save_max_us (10 s)
    close_link,      // write/read return Errc::link_closed from now on
  };
  Kind kind = Kind::drop_answer;
  std::uint32_t delay_ms = 0;
  std::size_t byte_index = static_cast<std::size_t>(-1);  // corrupt: default = middle byte
  std::uint8_t xor_mask = 0x01;
  Bytes garbage{0xFF, 0x00, 0x55, 0xAA};
  std::uint8_t id = 0x00;      // wrong_id: the ID to answer from (0 = MACID XOR 1)
  bool instant_reset = false;  // reset_drive: true = reboot in no time and answer

  static Fault drop_request() { return {Kind::drop_request}; }
  static Fault drop_answer() { return {Kind::drop_answer}; }
  static Fault corrupt(std::size_t index = static_cast<std::size_t>(-1), std::uint8_t mask = 0x01) {
    Fault f{Kind::corrupt_answer};
    f.byte_index = index;
    f.xor_mask = mask;
    return f;
  }
  static Fault delay(std::uint32_t ms) {
    Fault f{Kind::delay_answer};
    f.delay_ms = ms;
    return f;
  }
  static Fault garbage_burst(Bytes g = {0xFF, 0x00, 0x55, 0xAA}) {
    Fault f{Kind::garbage_burst};
    f.garbage = std::move(g);
    return f;
  }
  static Fault wrong_id(std::uint8_t id = 0) {
    Fault f{Kind::wrong_id};
    f.id = id;
    return f;
  }
  static Fault reset_drive(bool instant = false) {
    Fault f{Kind::reset_drive};
    f.instant_reset = instant;
    return f;
  }
  static Fault slow_flash() { return {Kind::slow_flash}; }
  static Fault close_link() { return {Kind::close_link}; }
};

struct FaultCounters {
  std::uint64_t dropped_requests = 0, dropped_answers = 0, corrupted_answers = 0,
                delayed_answers = 0, garbage_bursts = 0, wrong_id_answers = 0, drive_resets = 0,
                slow_flash_saves = 0, link_closures = 0;
  std::uint64_t total() const {
    return dropped_requests + dropped_answers + corrupted_answers + delayed_answers +
           garbage_bursts + wrong_id_answers + drive_resets + slow_flash_saves + link_closures;
  }
};

// Exchange index = number of write() calls before this one (0-based).
class FaultPlan {
 public:
  using Callback = std::function<std::vector<Fault>(std::size_t exchange, ByteView request)>;
  void schedule(std::size_t exchange, Fault f) { planned_[exchange].push_back(std::move(f)); }
  void set_callback(Callback cb) { cb_ = std::move(cb); }
  void clear() {
    planned_.clear();
    cb_ = nullptr;
  }
  const FaultCounters& counters() const { return counters_; }
  FaultCounters& counters() { return counters_; }
  // Used by SimLink: the faults for this exchange (planned ones, then the callback's).
  std::vector<Fault> take(std::size_t exchange, ByteView request);

 private:
  std::map<std::size_t, std::vector<Fault>> planned_;
  Callback cb_;
  FaultCounters counters_;
};

// What the faults of one exchange do to the request (faults.cpp), counted in
// `fc`: the link closes (the faults after it do not apply), the request is
// lost, drives reset or get a slow flash save (`target`: the addressed drive,
// nullptr: every drive). The faults left apply to each answer.
struct RequestFaults {
  bool close_link = false;
  bool drop_request = false;
  std::vector<const Fault*> answer_faults;  // into the exchange's faults
};
RequestFaults apply_request_faults(const std::vector<Fault>& faults, const Bus& bus,
                                   const std::shared_ptr<Drive>& target, std::int64_t now_ns,
                                   FaultCounters& fc);
// The answer faults on one answer: lost (returns false), corrupted, delayed,
// garbage before it (into `prefix`), another ID.
bool apply_answer_faults(const std::vector<const Fault*>& faults, const Bus& bus, TimedAnswer& a,
                         Bytes& prefix, FaultCounters& fc);

}  // namespace lmcfg::sim
