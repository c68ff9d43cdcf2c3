// docs/reliability.md: faults on the line never cost a configuration.
//
// Expected behaviour, per fault, proven below against the simulated drive:
//  - corrupted byte, dropped byte, lost answer, wrong-ID answer: a read is
//    repeated (input discarded, decoder reset, line settled) and the backup /
//    diff / restore plan completes with the right data. A write is never sent
//    again blindly: write_rom reads the ROM value back and succeeds only if the
//    drive holds it; any other write fails with a communication error, the
//    restore says the drive is partially configured, and running the same
//    restore again converges.
//  - late answer: within the deadline it is simply the answer; after the
//    deadline the client waits for a quiet line before the next request, so
//    the late answer is dropped, never taken for the next request's answer.
//  - garbage burst: skipped by the decoder, the answer behind it is used.
//  - drive reset in the middle of a block transfer: a block read restarts from
//    its setup telegram; a block write fails (the drive's state per chunk shows
//    the lost transfer), the restore reports failure and a rerun converges.
//  - a block read pass that stops at its last undecided chunk (no end state
//    confirms the drive's cursor) never takes the answers of a cursor that a
//    reset restarted: the pass reads on to its end instead.
//  - a flash save that takes its full 10 s: within the 12 s flash deadline.
//  - the link closing: the operation gives up at once with link_closed
//    (exit code 4, communication failure); nothing is reported as done.
#include <catch2/catch.hpp>

#include "db/database.hpp"
#include "ops/diff.hpp"
#include "test_reliability_support.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace client_test_reliability_faults {

using namespace lmcfg;
using test::FaultRig;
using test::request;

namespace {

struct Fixtures {
  config::DriveConfig source_backup;  // clean backup of the commissioned axis
  sim::DriveState source, spare;
};
const Fixtures& fixtures() {
  static const Fixtures f = [] {
    Fixtures x;
    x.source = test::load_sim_drive("commissioned-axis.json")->state();
    x.spare = test::load_sim_drive("used-spare.json")->state();
    // A corrupted value byte is only detectable with a checksum: LinRS has no
    // other integrity check. The fault tests run with CRC-CCITT on.
    x.source.checksum.mode = codec::ChecksumMode::crc_ccitt;
    x.spare.checksum.mode = codec::ChecksumMode::crc_ccitt;
    FaultRig rig(std::make_shared<sim::Drive>(x.source));
    auto b = ops::backup(*rig.client, ops::BackupOptions{}, db::Database::empty());
    if (!b.ok()) throw std::runtime_error(b.error().message);
    x.source_backup = std::move(b).value();
    return x;
  }();
  return f;
}

// One fault as the tests name it; drop_byte is done by the rig's ByteDropper.
struct FaultCase {
  const char* name;
  std::optional<sim::Fault> fault;
  std::optional<std::size_t> drop_byte;
};
std::vector<FaultCase> all_faults() {
  return {
      {"corrupted byte", sim::Fault::corrupt(), std::nullopt},
      {"dropped byte", std::nullopt, 5},
      {"lost answer", sim::Fault::drop_answer(), std::nullopt},
      {"lost request", sim::Fault::drop_request(), std::nullopt},
      {"late answer within the deadline", sim::Fault::delay(150), std::nullopt},
      {"late answer after the deadline", sim::Fault::delay(400), std::nullopt},
      {"answer from the wrong ID", sim::Fault::wrong_id(), std::nullopt},
      {"garbage burst", sim::Fault::garbage_burst(), std::nullopt},
      {"garbage burst with start bytes",
       sim::Fault::garbage_burst({0x01, 0x11, 0x3F, 0x01, 0x04, 0x02}), std::nullopt},
      {"drive reset (instant reboot)", sim::Fault::reset_drive(true), std::nullopt},
      {"drive reset (3 s reboot)", sim::Fault::reset_drive(false), std::nullopt},
      {"flash save takes 10 s", sim::Fault::slow_flash(), std::nullopt},
      {"link closes", sim::Fault::close_link(), std::nullopt},
  };
}

bool closes(const FaultCase& f) { return f.fault && f.fault->kind == sim::Fault::Kind::close_link; }
bool slow_reboot(const FaultCase& f) {
  return f.fault && f.fault->kind == sim::Fault::Kind::reset_drive && !f.fault->instant_reset;
}

}  // namespace

TEST_CASE("faults in backup: reads retried and resynchronised, the backup equals a clean one",
          "[reliability]") {
  const auto& fx = fixtures();
  // Aimed at the 2nd chunk of the first curve's info block: an idempotent read
  // inside a block transfer, the hardest place for a read to fail.
  for (const auto& f : all_faults()) {
    DYNAMIC_SECTION(f.name) {
      FaultRig rig(std::make_shared<sim::Drive>(fx.source));
      auto hit = test::aim(rig, request(0x04, 0x09), 2, f.fault, f.drop_byte);
      auto b = ops::backup(*rig.client, ops::BackupOptions{}, db::Database::empty());
      REQUIRE(hit.hit->has_value());
      CHECK(rig.client->stats().write_requests == 0);  // backup never writes, faults or not
      if (closes(f)) {
        REQUIRE_FALSE(b.ok());
        CHECK(b.error().code == Errc::link_closed);
        continue;
      }
      if (slow_reboot(f) && !b.ok()) {
        // A 3 s reboot outlasts the read retries: a communication failure, reported.
        CHECK(b.error().code == Errc::timeout);
        continue;
      }
      INFO((b.ok() ? std::string() : b.error().message));
      REQUIRE(b.ok());
      b->identity.captured_at = fx.source_backup.identity.captured_at;
      CHECK(*b == fx.source_backup);
      CHECK(test::backup_vs_drive(*b, *rig.drive).empty());
      const auto& st = rig.client->stats();
      if (f.fault && (f.fault->kind == sim::Fault::Kind::drop_answer ||
                      f.fault->kind == sim::Fault::Kind::corrupt_answer ||
                      f.fault->kind == sim::Fault::Kind::wrong_id)) {
        CHECK(st.retries >= 1);
      }
      if (std::string(f.name) == "late answer after the deadline") {
        CHECK(st.settle_bytes > 0);  // the late answer was dropped while settling
      }
      if (std::string(f.name) == "late answer within the deadline") CHECK(st.retries == 0);
      if (f.drop_byte) CHECK(rig.dropper->dropped() == 1);
    }
  }
}

TEST_CASE(
    "block reads: a pass that stops at its last undecided chunk never takes a restarted "
    "cursor's answers",
    "[reliability]") {
  const auto& fx = fixtures();
  // The first command table entry (16 chunks): chunk `hole` answered lost in
  // the first pass; in the second pass (setup, chunks 0..hole) the drive
  // resets at once as chunk `reset_at` is asked for and starts the entry
  // again from its first chunk with state 04h (the simulator's model of a
  // drive that forgot the transfer). Nothing but the state of the last chunk
  // shows it; the pass reads on to the end then.
  const int kChunks = 16;
  for (int hole : {1, 5, 9, 14}) {
    for (int reset_at = -1; reset_at <= hole; ++reset_at) {
      DYNAMIC_SECTION("hole " << hole << ", reset at " << reset_at) {
        FaultRig rig(std::make_shared<sim::Drive>(fx.source));
        const auto cfg = rig.drive->state().checksum;
        auto chunk_reads = std::make_shared<int>(0);
        rig.sim->faults().set_callback([=](std::size_t, ByteView req) -> std::vector<sim::Fault> {
          auto t = codec::decode(req, cfg);
          if (!t.ok() || t->main != 0x08 || t->sub != 0x06) return {};
          const int n = (*chunk_reads)++;
          if (n == hole) return {sim::Fault::drop_answer()};
          if (reset_at >= 0 && n == kChunks + reset_at) return {sim::Fault::reset_drive(true)};
          return {};
        });
        auto b = ops::backup(*rig.client, ops::BackupOptions{}, db::Database::empty());
        INFO((b.ok() ? std::string() : b.error().message));
        REQUIRE(b.ok());
        b->identity.captured_at = fx.source_backup.identity.captured_at;
        CHECK(*b == fx.source_backup);
        CHECK(test::backup_vs_drive(*b, *rig.drive).empty());
        const int entries = static_cast<int>(fx.source_backup.ct_entries.size());
        if (reset_at < 0 && hole + 1 < kChunks) {
          // No reset: the second pass stopped at the hole.
          CHECK(*chunk_reads == kChunks * entries + hole + 1);
        }
      }
    }
  }
}

TEST_CASE("faults in diff: a modified list restarted after a fault gives an identical diff",
          "[reliability]") {
  const auto& fx = fixtures();
  // "get next" of the modified list is not idempotent (it advances the drive's
  // cursor): the list is restarted from "start", never resumed.
  for (const auto& f : all_faults()) {
    DYNAMIC_SECTION(f.name) {
      client::ClientOptions co;
      co.confirm_empty_lists =
          true;  // a reset between "start" and the first "get next" looks like an empty list
      FaultRig rig(std::make_shared<sim::Drive>(fx.source), co);
      auto hit = test::aim(rig, request(0x05, 0x09), 3, f.fault, f.drop_byte);
      auto b = ops::backup(*rig.client, ops::BackupOptions{}, db::Database::empty());
      REQUIRE(hit.hit->has_value());
      if (closes(f) || (slow_reboot(f) && !b.ok())) {
        REQUIRE_FALSE(b.ok());
        CHECK(test::is_comm_failure(b.error()));
        continue;
      }
      INFO((b.ok() ? std::string() : b.error().message));
      REQUIRE(b.ok());
      auto d =
          ops::diff(fx.source_backup, *b, db::Database::empty(), {}, ops::DiffOptions{true, false});
      for (const auto& it : d.items) UNSCOPED_INFO(it.name << ": " << it.a << " vs " << it.b);
      CHECK(d.identical());
      CHECK(rig.client->stats().write_requests == 0);
    }
  }
}

namespace {

// Restore of the commissioned axis's backup onto the used spare, with one
// fault aimed at the nth request matching `where`. Returns the first run.
struct RestoreOutcome {
  test::RestoreRun first;
  std::vector<std::string> after_first;  // drive vs file after the first run
  bool converged = false;  // after a rerun on a fresh link (only when the first failed)
  client::Stats stats;
};

RestoreOutcome restore_with(const FaultCase& f, test::TelegramMatch where, int nth) {
  const auto& fx = fixtures();
  auto drive = std::make_shared<sim::Drive>(fx.spare);
  RestoreOutcome out;
  std::int64_t t_end = 0;
  test::forget_restore_record();  // a new drive
  {
    FaultRig rig(drive);
    auto hit = test::aim(rig, where, nth, f.fault, f.drop_byte);
    out.first = test::run_restore(*rig.client, fx.source_backup);
    REQUIRE(hit.hit->has_value());
    out.stats = rig.client->stats();
    t_end = rig.now_ns();
  }
  out.after_first = test::drive_vs_file(*drive, fx.source_backup);
  if (out.first.ok()) {
    out.converged = out.after_first.empty();
    return out;
  }
  // Rerun on a fresh link, 10 s later (a rebooting drive has finished).
  FaultRig again(drive, {}, t_end + 10'000'000'000);
  auto second = test::run_restore(*again.client, fx.source_backup);
  INFO((second.ok() ? std::string() : second.outcome.error().message));
  out.converged = second.ok() && test::drive_vs_file(*drive, fx.source_backup).empty();
  return out;
}

}  // namespace

TEST_CASE(
    "faults in restore: a lost ROM write answer is settled by reading back, never by resending",
    "[reliability]") {
  // Aimed at the 2nd "write ROM value" (05h 01h).
  for (const auto& f : all_faults()) {
    DYNAMIC_SECTION(f.name) {
      auto o = restore_with(f, request(0x05, 0x01), 2);
      INFO((o.first.ok() ? std::string() : o.first.outcome.error().message));
      const bool not_applied_or_reset =
          closes(f) || (f.fault && (f.fault->kind == sim::Fault::Kind::reset_drive ||
                                    f.fault->kind == sim::Fault::Kind::drop_request));
      if (not_applied_or_reset) {
        // The write never landed (lost request, link closed, reboot), or the
        // drive reset under the restore: reported, never success; the rerun converges.
        REQUIRE_FALSE(o.first.ok());
        CHECK(o.first.outcome.error().message.find("partially configured") != std::string::npos);
      } else {
        CHECK(o.first.ok());
        CHECK(o.after_first.empty());
      }
      CHECK(o.converged);
      const bool answer_lost =
          f.drop_byte ||
          (f.fault &&
           (f.fault->kind == sim::Fault::Kind::drop_answer ||
            f.fault->kind == sim::Fault::Kind::corrupt_answer ||
            f.fault->kind == sim::Fault::Kind::wrong_id ||
            (f.fault->kind == sim::Fault::Kind::delay_answer && f.fault->delay_ms > 200)));
      if (answer_lost) CHECK(o.stats.writes_confirmed == 1);
    }
  }
}

TEST_CASE(
    "faults in restore: a fault inside a command table block write is restarted and confirmed, or "
    "fails the restore, a rerun converges",
    "[reliability]") {
  // Aimed at the 2nd data chunk of the first command table entry (08h 04h).
  for (const auto& f : all_faults()) {
    DYNAMIC_SECTION(f.name) {
      auto o = restore_with(f, request(0x08, 0x04), 2);
      INFO((o.first.ok() ? std::string() : o.first.outcome.error().message));
      const bool harmless =
          f.fault && (f.fault->kind == sim::Fault::Kind::garbage_burst ||
                      f.fault->kind == sim::Fault::Kind::slow_flash ||
                      (f.fault->kind == sim::Fault::Kind::delay_answer && f.fault->delay_ms < 200));
      if (harmless) {
        CHECK(o.first.ok());
      } else if (o.first.ok()) {
        // The entry's write was restarted from its setup telegram and
        // confirmed by reading it back (docs/reliability.md): success only
        // with the drive equal to the file.
        CHECK(o.stats.block_rewrites + o.stats.writes_confirmed > 0);
        CHECK(o.after_first.empty());
      } else {
        // The chunk may or may not have landed: the client cannot know and does
        // not write it again. Reported as a communication failure.
        REQUIRE_FALSE(o.first.ok());
        // A reset drive may also refuse the next chunk (C8: the entry is gone).
        if (!(f.fault && f.fault->kind == sim::Fault::Kind::reset_drive))
          CHECK(test::is_comm_failure(o.first.outcome.error()));
        CHECK(o.first.outcome.error().message.find("partially configured") != std::string::npos);
      }
      CHECK(o.converged);
    }
  }
}

TEST_CASE("faults in restore: a curve block write, the flash saves, stop and start",
          "[reliability]") {
  struct Where {
    const char* name;
    test::TelegramMatch match;
    int nth;
  };
  const std::vector<Where> places{
      {"curve data chunk", request(0x04, 0x06), 3}, {"save command table", request(0x08, 0x00), 1},
      {"save curves", request(0x04, 0x00), 1},      {"stop MC", request(0x06, 0x03), 1},
      {"reset at the end", request(0x06, 0x01), 1},
  };
  for (const auto& w : places) {
    for (const auto& f : all_faults()) {
      DYNAMIC_SECTION(w.name << ": " << f.name) {
        auto o = restore_with(f, w.match, w.nth);
        INFO((o.first.ok() ? std::string() : o.first.outcome.error().message));
        // Whatever happened, success means the drive equals the file, failure
        // was reported as such, and a rerun converges.
        if (o.first.ok()) {
          CHECK(o.after_first.empty());
        } else {
          CHECK(o.first.outcome.error().message.size() > 0);
        }
        CHECK(o.converged);
        if (f.fault && f.fault->kind == sim::Fault::Kind::slow_flash &&
            std::string(w.name).rfind("save", 0) == 0) {
          CHECK(o.first.ok());  // 10 s is within the 12 s flash deadline
        }
      }
    }
  }
}

TEST_CASE("a late answer to one request is never taken for the next one", "[reliability]") {
  const auto& fx = fixtures();
  FaultRig rig(std::make_shared<sim::Drive>(fx.source));
  // ROM read of one UPID answered 250 ms late (after the 200 ms deadline),
  // then a read of another UPID: with no settling, the late answer would
  // arrive while the second read waits.
  const auto upids = test::modified_rom(*rig.drive);
  REQUIRE(upids.size() >= 2);
  const auto a = upids.begin()->first, b = std::next(upids.begin())->first;
  rig.sim->faults().schedule(0, sim::Fault::delay(250));
  rig.sim->faults().schedule(1, sim::Fault::drop_request());  // the retry is lost as well
  auto va = rig.client->read_rom(a);
  REQUIRE(va.ok());
  CHECK(*va == upids.at(a));
  auto vb = rig.client->read_rom(b);
  REQUIRE(vb.ok());
  CHECK(*vb == upids.at(b));
  CHECK(rig.client->stats().settles >= 1);

  // Even a late answer beyond the settle time is rejected by its key.
  client::ClientOptions o;
  o.settle = transport::Millis(1);
  FaultRig quick(std::make_shared<sim::Drive>(fx.source), o);
  quick.sim->faults().schedule(0, sim::Fault::delay(1300));  // arrives while the read of b waits
  for (std::size_t x = 1; x <= 5; ++x)
    quick.sim->faults().schedule(x,
                                 x == 3 ? sim::Fault::drop_request() : sim::Fault::drop_answer());
  auto lost = quick.client->read_rom(a);  // 2 reads of 3 attempts each, all lost
  REQUIRE_FALSE(lost.ok());
  auto next = quick.client->read_rom(b);
  REQUIRE(next.ok());
  CHECK(*next == upids.at(b));
  CHECK(quick.client->stats().stale_answers >= 1);
}

TEST_CASE("a lost answer to a write is not resent: exactly one write telegram", "[reliability]") {
  const auto& fx = fixtures();
  FaultRig rig(std::make_shared<sim::Drive>(fx.spare));
  // Block write: the setup's answer is lost; the chunks follow once each, the
  // entry is read back and holds the bytes: confirmed, nothing sent twice.
  rig.sim->faults().schedule(0, sim::Fault::drop_answer());
  auto w = rig.client->write_ct_entry(7, Bytes(64, 0x5A));
  INFO((w.ok() ? std::string() : w.error().message));
  REQUIRE(w.ok());
  CHECK(rig.client->stats().write_requests == 1 + 16);
  CHECK(rig.client->stats().writes_confirmed == 1);
  CHECK(rig.drive->state().ct_ram.at(7) == Bytes(64, 0x5A));
  // write_rom: answer lost, the read-back shows it landed: one write, success.
  FaultRig rom(std::make_shared<sim::Drive>(fx.spare));
  const std::uint16_t upid = rom.drive->state().params.rbegin()->first;
  auto* p = rom.drive->find(upid);
  REQUIRE(p);
  const std::uint32_t v = p->rom == p->min ? p->max : p->min;
  rom.sim->faults().schedule(0, sim::Fault::drop_answer());
  auto r = rom.client->write_rom_confirmed(upid, v);
  INFO((r.ok() ? std::string() : r.error().message));
  if (p->has_rom()) {
    CHECK(r.ok());
    CHECK(rom.client->stats().write_requests == 1);
    CHECK(rom.client->stats().writes_confirmed == 1);
  }
  // The request itself lost: the read-back shows the old value; one write, failure.
  FaultRig lostreq(std::make_shared<sim::Drive>(fx.spare));
  lostreq.sim->faults().schedule(0, sim::Fault::drop_request());
  auto r2 = lostreq.client->write_rom_confirmed(upid, v);
  if (p->has_rom()) {
    REQUIRE_FALSE(r2.ok());
    CHECK(r2.error().code == Errc::timeout);
    CHECK(r2.error().message.find("not the value written") != std::string::npos);
    CHECK(lostreq.client->stats().write_requests == 1);
  }
}

TEST_CASE("faults give up in bounded time with a communication error", "[reliability]") {
  const auto& fx = fixtures();
  // A drive that never answers again: the backup gives up; virtual time spent
  // is bounded by retries x (deadline + settle).
  FaultRig rig(std::make_shared<sim::Drive>(fx.source));
  rig.sim->faults().set_callback([](std::size_t ex, ByteView) -> std::vector<sim::Fault> {
    if (ex >= 5) return {sim::Fault::drop_request()};
    return {};
  });
  auto b = ops::backup(*rig.client, ops::BackupOptions{}, db::Database::empty());
  REQUIRE_FALSE(b.ok());
  CHECK(b.error().code == Errc::timeout);
  CHECK(rig.sim->clock().now_s() < 30.0);
  // A drive answering with garbage only: communication error, bounded.
  FaultRig noisy(std::make_shared<sim::Drive>(fx.source));
  noisy.sim->faults().set_callback([](std::size_t, ByteView) -> std::vector<sim::Fault> {
    return {sim::Fault::corrupt(3, 0xFF)};
  });
  auto n = ops::backup(*noisy.client, ops::BackupOptions{}, db::Database::empty());
  REQUIRE_FALSE(n.ok());
  CHECK(test::is_comm_failure(n.error()));
  CHECK(noisy.sim->clock().now_s() < 30.0);
}

}  // namespace client_test_reliability_faults
