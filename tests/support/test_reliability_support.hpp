#pragma once
// Helpers for the docs/reliability.md reliability tests (tests/*/test_reliability_*.cpp):
// a simulated drive behind a fault-injecting link, faults aimed at the n-th
// telegram of a kind, and checks that a drive holds exactly a configuration.
#include <unistd.h>

#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "client/client.hpp"
#include "codec/frame.hpp"
#include "config/model.hpp"
#include "db/database.hpp"
#include "e2e_support.hpp"
#include "ops/backup.hpp"
#include "ops/restore.hpp"
#include "sim/link.hpp"

namespace lmcfg::test {

// Transport decorator that removes one byte from what read_some returns for
// one exchange (a byte lost on the line: the "dropped byte" fault, which the
// SimLink fault plan does not model).
class ByteDropper final : public transport::Transport {
 public:
  explicit ByteDropper(std::unique_ptr<transport::Transport> inner) : inner_(std::move(inner)) {}
  // Drops byte `index` of the answer to exchange `exchange` (0-based write count).
  void arm(std::size_t exchange, std::size_t index) { armed_ = {exchange, index}; }
  std::size_t dropped() const { return dropped_; }

  Result<void> write(ByteView bytes) override {
    current_ = writes_++;
    seen_ = 0;
    return inner_->write(bytes);
  }
  Result<Bytes> read_some(transport::Millis timeout) override {
    auto r = inner_->read_some(timeout);
    if (r.ok() && armed_ && armed_->first == current_ && !r->empty()) {
      const std::size_t at = armed_->second;
      if (at >= seen_ && at < seen_ + r->size()) {
        r->erase(r->begin() + static_cast<std::ptrdiff_t>(at - seen_));
        armed_.reset();
        ++dropped_;
        seen_ += 1;
      }
    }
    if (r.ok()) seen_ += r->size();
    return r;
  }
  void discard_input() override { inner_->discard_input(); }
  std::string describe() const override { return inner_->describe(); }
  double byte_time_us() const override { return inner_->byte_time_us(); }
  std::int64_t now_ns() const override { return inner_->now_ns(); }

 private:
  std::unique_ptr<transport::Transport> inner_;
  std::optional<std::pair<std::size_t, std::size_t>> armed_;
  std::size_t writes_ = 0, current_ = 0, seen_ = 0, dropped_ = 0;
};

// A drive (shared, so a second rig can talk to the same drive), its SimLink,
// a byte dropper, a wire recorder, and the client.
struct FaultRig {
  std::shared_ptr<sim::Drive> drive;
  std::shared_ptr<WireRecorder> wire = std::make_shared<WireRecorder>();
  sim::SimLink* sim = nullptr;
  ByteDropper* dropper = nullptr;
  std::unique_ptr<transport::Transport> link;
  std::unique_ptr<client::LinrsClient> client;

  explicit FaultRig(std::shared_ptr<sim::Drive> d, client::ClientOptions opt = {},
                    std::int64_t start_ns = 0)
      : drive(std::move(d)) {
    auto raw = std::make_unique<sim::SimLink>(drive);
    sim = raw.get();
    sim->clock().advance_to_ns(start_ns);  // a fresh link continues the drive's time line
    auto dropping = std::make_unique<ByteDropper>(std::move(raw));
    dropper = dropping.get();
    link = transport::make_traced(std::move(dropping), wire);
    opt.checksum = drive->state().checksum;
    client = std::make_unique<client::LinrsClient>(*link, opt);
  }
  std::int64_t now_ns() const { return sim->clock().now_ns(); }
};

using TelegramMatch = std::function<bool(const codec::Telegram&)>;
inline TelegramMatch request(std::uint8_t main, std::uint8_t sub) {
  return [=](const codec::Telegram& t) { return t.main == main && t.sub == sub; };
}

// Faults for the n-th (1-based) request matching `match`; `hits` (optional)
// receives the exchange index it was injected at. A fault of kind
// close_link etc. is passed straight to the SimLink; drop_byte arms the dropper.
struct Aim {
  std::shared_ptr<std::optional<std::size_t>> hit = std::make_shared<std::optional<std::size_t>>();
};
inline Aim aim(FaultRig& rig, TelegramMatch match, int nth, std::optional<sim::Fault> fault,
               std::optional<std::size_t> drop_byte = std::nullopt) {
  Aim a;
  auto count = std::make_shared<int>(0);
  const auto cfg = rig.drive->state().checksum;
  ByteDropper* dropper = rig.dropper;
  auto hit = a.hit;
  rig.sim->faults().set_callback(
      [=](std::size_t exchange, ByteView req) -> std::vector<sim::Fault> {
        auto t = codec::decode(req, cfg);
        if (!t.ok() || !match(*t) || ++*count != nth) return {};
        *hit = exchange;
        if (drop_byte) dropper->arm(exchange, *drop_byte);
        if (fault) return {*fault};
        return {};
      });
  return a;
}

// Parameters the drive holds as modified (ROM != default), per its own state.
inline std::map<std::uint16_t, std::uint32_t> modified_rom(const sim::Drive& d) {
  std::map<std::uint16_t, std::uint32_t> m;
  for (const auto& [upid, p] : d.state().params)
    if (p.modified()) m[upid] = p.rom;
  return m;
}

// Lists every way the drive's stored configuration differs from `file` (ROM
// values of the file's UPIDs, the modified list of the file's layers, flash
// curves, flash command table). Empty = the drive equals the file.
inline std::vector<std::string> drive_vs_file(const sim::Drive& d,
                                              const config::DriveConfig& file) {
  std::vector<std::string> out;
  std::map<std::uint16_t, std::uint32_t> want;
  for (int layer = 1; layer <= 4; ++layer) {
    if (!file.scope.layers[static_cast<std::size_t>(layer - 1)]) continue;
    for (const auto& p : file.layer(layer)) {
      want[p.upid] = p.value;
      auto rom = d.rom(p.upid);
      if (!rom || *rom != p.value) out.push_back("ROM of " + std::to_string(p.upid) + " differs");
    }
  }
  for (const auto& [upid, value] : modified_rom(d)) {
    const int layer = (upid >> 12) + 1;
    if (layer < 1 || layer > 4 || !file.scope.layers[static_cast<std::size_t>(layer - 1)]) continue;
    if (!want.count(upid))
      out.push_back("UPID " + std::to_string(upid) + " modified on the drive, not in the file");
  }
  if (file.scope.curves) {
    std::map<std::uint16_t, sim::Curve> curves;
    for (const auto& c : file.curves)
      curves[static_cast<std::uint16_t>(c.id)] = sim::Curve{c.info, c.data};
    if (curves != d.state().curves_flash) out.push_back("flash curves differ");
  }
  if (file.scope.command_table) {
    std::map<std::uint16_t, Bytes> ct;
    for (const auto& e : file.ct_entries) ct[static_cast<std::uint16_t>(e.id)] = e.raw;
    if (ct != d.state().ct_flash) out.push_back("flash command table differs");
  }
  return out;
}

// The drive's configuration as a backup of it must read it (RAM tables: what
// the drive answers to curve and CT reads).
inline std::vector<std::string> backup_vs_drive(const config::DriveConfig& b, const sim::Drive& d) {
  std::vector<std::string> out;
  std::map<std::uint16_t, std::uint32_t> got;
  for (const auto& l : b.layers)
    for (const auto& p : l) got[p.upid] = p.value;
  if (got != modified_rom(d))
    out.push_back("parameters differ from the drive's modified ROM values");
  std::map<std::uint16_t, sim::Curve> curves;
  for (const auto& c : b.curves)
    curves[static_cast<std::uint16_t>(c.id)] = sim::Curve{c.info, c.data};
  if (curves != d.state().curves_ram) out.push_back("curves differ");
  std::map<std::uint16_t, Bytes> ct;
  for (const auto& e : b.ct_entries) ct[static_cast<std::uint16_t>(e.id)] = e.raw;
  if (ct != d.state().ct_ram) out.push_back("command table differs");
  return out;
}

// plan + execute + verify, as `lmcfg restore` runs them. ok() only when the
// plan was accepted, every step was written and verification found nothing.
struct RestoreRun {
  Result<void> outcome;
  std::size_t mismatches = 0;
  bool ok() const { return outcome.ok(); }
};
// Restores every parameter of the file, the LinRS ones too: the fixtures' LinRS
// parameters select the line they are served on (docs/simulator.md).
// The recovery record the in-process restores share (one drive at a time per
// test process; ops/recovery.hpp). A test starting a new scenario forgets it.
inline std::filesystem::path restore_record() {
  return std::filesystem::temp_directory_path() /
         ("lmcfg-test-restore-record-" + std::to_string(::getpid()) + ".json");
}
inline void forget_restore_record() {
  std::error_code ec;
  std::filesystem::remove(restore_record(), ec);
}
inline ops::RestoreOptions restore_everything() {
  ops::RestoreOptions ro;
  ro.include_comm = true;
  ro.recovery_path = restore_record();
  return ro;
}
inline RestoreRun run_restore(client::Client& c, const config::DriveConfig& file,
                              const ops::RestoreOptions& ro = restore_everything()) {
  RestoreRun run;
  auto plan = ops::plan_restore(c, file, db::Database::empty(), ro);
  if (!plan.ok()) {
    run.outcome = std::move(plan).error();
    return run;
  }
  if (!plan->ok()) {
    run.outcome = Error(Errc::plan_refused, plan->problems.front());
    return run;
  }
  if (auto r = ops::execute_plan(c, *plan, ro); !r.ok()) {
    run.outcome = std::move(r).error();
    return run;
  }
  auto v = ops::verify_restore(c, *plan, ro);
  if (!v.ok()) {
    run.outcome = std::move(v).error();
    return run;
  }
  // As ops::run_restore: one second pass for a table the reset reloaded from
  // a flash that held another one.
  if (v->ct_differs || v->curves_differ) {
    auto pass = ops::plan_table_pass(c, *plan, *v, ro);
    if (!pass.ok()) {
      run.outcome = std::move(pass).error();
      return run;
    }
    if (!pass->steps.empty()) {
      if (auto r = ops::execute_plan(c, *pass, ro); !r.ok()) {
        run.outcome = std::move(r).error();
        return run;
      }
      v = ops::verify_restore(c, *plan, ro);
      if (!v.ok()) {
        run.outcome = std::move(v).error();
        return run;
      }
    }
  }
  run.mismatches = v->mismatches.size();
  if (!v->ok()) run.outcome = Error(Errc::verify_mismatch, v->mismatches.front());
  return run;
}

inline bool is_comm_failure(const Error& e) { return e.code == ErrorClass::link_failure; }

}  // namespace lmcfg::test
