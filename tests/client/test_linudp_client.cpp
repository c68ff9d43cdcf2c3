// The LinUDP client (lib/client/linudp_client.*) against the simulated drive
// over the in-process datagram link (virtual clock): the count rule and
// resends of LinUDP V2 §7, the configuration channel only (§4.4.1),
// the messages of no answer, another master (§5) and a refusal (p14),
// and the same backup over LinUDP as over LinRS.
#include <catch2/catch.hpp>

#include "client/linudp_client.hpp"
#include "db/database.hpp"
#include "linudp_rig.hpp"
#include "ops/backup.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace client_test_linudp_client {

using namespace lmcfg;

namespace {

config::DriveConfig backup_of(client::Client& c) {
  auto cfg = ops::backup(c, ops::BackupOptions{}, db::Database::empty());
  REQUIRE(cfg.ok());
  return std::move(cfg).value();
}

// Link metadata aside (identity: port, time, link settings), and the types
// of parameters: LinUDP has no type request (LinUDP V2 p14); with the
// UPID database (the tools load it) the types come from there.
void require_same_configuration(config::DriveConfig a, config::DriveConfig b) {
  a.identity = {};
  b.identity = {};
  CHECK(a.scope == b.scope);
  for (int l = 1; l <= 4; ++l) {
    for (auto& p : a.layer(l)) p.type.reset();
    for (auto& p : b.layer(l)) p.type.reset();
    CHECK(a.layer(l) == b.layer(l));
  }
  CHECK(a.curves == b.curves);
  CHECK(a.ct_entries == b.ct_entries);
}

std::vector<linudp::Request> requests(const test::DatagramRecorder& w) {
  std::vector<linudp::Request> out;
  for (const auto& d : w.tx) {
    auto r = linudp::decode_request(d);
    REQUIRE(r.ok());
    out.push_back(*r);
  }
  return out;
}

}  // namespace

TEST_CASE("LinUDP client: a backup over LinUDP equals one over LinRS of the same drive",
          "[linudp][client]") {
  test::SimRig linrs("commissioned-axis.json");
  test::LinudpRig udp(test::load_sim_drive("commissioned-axis.json"));
  const auto a = backup_of(*linrs.client);
  const auto b = backup_of(udp.client());
  CHECK_FALSE(b.curves.empty());
  CHECK_FALSE(b.ct_entries.empty());
  require_same_configuration(a, b);
}

TEST_CASE("LinUDP client V2 §4.4.1 and §7: RTC only, a new count per command, a NOP first",
          "[linudp][client]") {
  test::LinudpRig rig(test::load_sim_drive("commissioned-axis.json"));
  (void)backup_of(rig.client());
  const auto reqs = requests(*rig.wire);
  REQUIRE(reqs.size() > 50);
  CHECK(rig.udp->stats().motion_telegrams == 0);
  CHECK(reqs.front().rtc->id == 0x00);  // the seeding NOP
  for (std::size_t i = 0; i < reqs.size(); ++i) {
    CHECK(reqs[i].request_def == linudp::req::rtc);
    CHECK(reqs[i].response_def == linudp::resp::all);
    REQUIRE(reqs[i].rtc);
    CHECK(reqs[i].rtc->count >= 2);
    CHECK(reqs[i].rtc->count <= 14);
    if (i > 0) CHECK(reqs[i].rtc->count != reqs[i - 1].rtc->count);  // no loss: no resend
  }
}

TEST_CASE("LinUDP client V2 §7: a lost datagram is resent with the same count and bytes",
          "[linudp][client]") {
  sim::LinudpField f;
  f.lose_reply_every = 5;
  f.lose_request_every = 7;
  test::LinudpRig lossy(test::load_sim_drive("commissioned-axis.json"), f);
  test::LinudpRig clean(test::load_sim_drive("commissioned-axis.json"));
  require_same_configuration(backup_of(clean.client()), backup_of(lossy.client()));
  CHECK(lossy.client().stats().retries > 0);
  // A resend repeats the datagram byte for byte; a new command changes the count.
  std::size_t resends = 0;
  const auto& tx = lossy.wire->tx;
  for (std::size_t i = 1; i < tx.size(); ++i) {
    auto a = linudp::decode_request(tx[i - 1]), b = linudp::decode_request(tx[i]);
    if (a->rtc->count == b->rtc->count) {
      ++resends;
      CHECK(tx[i] == tx[i - 1]);
    }
  }
  CHECK(resends == lossy.client().stats().retries);
  // The drive ran each command once: the resends it heard were answered from
  // its cache, never executed again.
  CHECK(lossy.udp->stats().resends > 0);
  CHECK(lossy.udp->stats().commands + lossy.udp->stats().resends + lossy.udp->stats().ignored ==
        lossy.udp->stats().datagrams);
}

TEST_CASE("LinUDP client C1250 notes: stale echoes are ignored", "[linudp][client]") {
  sim::LinudpField f;
  f.stale_echo_every = 3;
  test::LinudpRig stale(test::load_sim_drive("commissioned-axis.json"), f);
  test::LinudpRig clean(test::load_sim_drive("commissioned-axis.json"));
  require_same_configuration(backup_of(clean.client()), backup_of(stale.client()));
  CHECK(stale.client().stats().stale_answers > 0);
  CHECK(stale.client().stats().retries == 0);
}

TEST_CASE("LinUDP client: the exact message of a drive that does not answer", "[linudp][client]") {
  sim::LinudpField f;
  f.lose_request_every = 1;
  test::LinudpRig rig(test::load_sim_drive("commissioned-axis.json"), f);
  auto r = rig.client().read_rom(0x13A2);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == make_error_code(Errc::timeout));
  CHECK(r.error().message ==
        "no answer from the LinUDP drive at linudp-sim to no operation (00h) (count 2, sent 7 "
        "times, 1400 ms in all): check the address and port (linudp://HOST[:PORT], drive port "
        "49360), that the drive is powered and on this network, and that LinUDP V2 is its "
        "interface (LinUDP V2 §3.2, §4.3)");
  CHECK(rig.wire->tx.size() == 7);
}

TEST_CASE("LinUDP client V2 §5: a drive held by another master is said so", "[linudp][client]") {
  sim::LinudpField f;
  f.held_by_other_master = true;
  test::LinudpRig rig(test::load_sim_drive("commissioned-axis.json"), f);
  auto r = rig.client().read_rom(0x13A2);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == make_error_code(Errc::io_error));
  CHECK(r.error().message == client::held_by_other_master_message("linudp-sim"));
  CHECK(r.error().message ==
        "the LinUDP drive at linudp-sim answers with all-zero telegrams: it is held by another "
        "master (LinMot-Talk or another LinUDP client, LinUDP V2 §5); disconnect that "
        "master and try again");
  CHECK(rig.wire->tx.size() == 1);  // not resent: another master's drive is left alone
}

TEST_CASE("LinUDP client V2 p14: a refused command names the command, UPID and status",
          "[linudp][client]") {
  test::LinudpRig rig(test::load_sim_drive("commissioned-axis.json"));
  auto r = rig.client().read_rom(0x5555);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == make_error_code(Errc::drive_refused));
  CHECK(r.error().message ==
        "the LinUDP drive at linudp-sim refused read ROM value (10h) for UPID 5555h: status C0h "
        "UPID error (LinUDP V2 p14)");
  CHECK(r.error().code == ErrorClass::drive_refusal);
}

TEST_CASE("LinUDP client V2 p13-p15: no type request, no single-curve delete, said as such",
          "[linudp][client]") {
  test::LinudpRig rig(test::load_sim_drive("commissioned-axis.json"));
  auto& c = rig.client();
  CHECK_FALSE(c.capabilities().delete_one_curve);
  CHECK(c.capabilities().protocol == "LinUDP");
  auto t = c.get_type(0x13A2);
  REQUIRE_FALSE(t.ok());
  CHECK(t.error().code == ErrorClass::drive_refusal);
  CHECK(t.error().message == "LinUDP has no request for the type of UPID 13A2h (LinUDP V2 p14)");
  auto d = c.delete_curve(1);
  REQUIRE_FALSE(d.ok());
  CHECK(d.error().code == make_error_code(Errc::not_supported));
  CHECK(rig.wire->tx.empty());  // nothing was sent for either
}

TEST_CASE("LinUDP client: values, lists and blocks under each reading LinUDP V2 leaves open",
          "[linudp][client]") {
  test::LinudpRig clean(test::load_sim_drive("commissioned-axis.json"));
  const auto want = backup_of(clean.client());
  for (int variant = 0; variant < 4; ++variant) {
    sim::LinudpField f;
    f.end_on_extra_read = variant & 1;
    f.list_spans_layers = variant & 2;
    f.curve_start_gives_sizes = variant != 3;
    f.running_status = variant == 1 ? 0x05 : 0x02;
    INFO("variant " << variant);
    test::LinudpRig rig(test::load_sim_drive("commissioned-axis.json"), f);
    require_same_configuration(want, backup_of(rig.client()));
  }
}

TEST_CASE("LinUDP client (counts 1 and 15 open in V2 §7): the tools never send them",
          "[linudp][client]") {
  sim::LinudpField f;
  f.strict_counts = true;
  test::LinudpRig rig(test::load_sim_drive("commissioned-axis.json"), f);
  (void)backup_of(rig.client());
  CHECK(rig.udp->stats().counts_seen_15 == 0);
  CHECK(rig.udp->stats().ignored == 0);
}

}  // namespace client_test_linudp_client

namespace client_test_linudp_client {

// C1250 notes: resending 80h while a save is running restarts the save;
// LinUDP V2 §7: the same telegram (same count) does not execute the
// command again. A save with no answer is sent again, with its count, once
// no save can still run (90 s: field reports and C1250 notes, 39-75 s saves,
// 30-90 s silences): the drive saves exactly once whether the request or the reply
// was lost.
TEST_CASE("LinUDP client V2 §7, C1250 notes: a lost save request or reply, one save either way",
          "[linudp][client][save]") {
  struct Case {
    const char* name;
    bool lose_request;
    bool unacknowledged;
    std::uint8_t running;
  };
  for (const Case& k :
       {Case{"request lost", true, false, 0x02}, Case{"reply lost", false, false, 0x02},
        Case{"request lost, silent while saving", true, false, 0},
        Case{"reply lost, silent while saving", false, false, 0},
        Case{"request lost, saves never acknowledged", true, true, 0x02},
        Case{"nothing lost, saves never acknowledged", false, true, 0x02}}) {
    DYNAMIC_SECTION(k.name) {
      sim::LinudpField f;
      f.save_us = 39'000'000;  // field reports: about 39 s
      f.unacknowledged_saves = k.unacknowledged;
      f.running_status = k.running;
      (k.lose_request ? f.lose_save_requests : f.lose_save_replies) = 1;
      test::LinudpRig rig(test::load_sim_drive("commissioned-axis.json"), f);
      auto& c = dynamic_cast<client::LinudpClient&>(rig.client());
      REQUIRE(c.stop_mc().ok());
      REQUIRE_FALSE(rig.drive->state().ct_ram.empty());
      REQUIRE(c.delete_ct_entry(rig.drive->state().ct_ram.begin()->first).ok());
      REQUIRE(rig.drive->state().ct_flash != rig.drive->state().ct_ram);  // a save is owed
      rig.wire->tx.clear();
      const std::int64_t t0 = rig.link->clock().now_ns();
      auto saved = c.save_ct();
      const double waited_s = static_cast<double>(rig.link->clock().now_ns() - t0) / 1e9;
      INFO((saved.ok() ? std::string("ok") : saved.error().message) << ", " << waited_s << " s");
      CHECK(rig.udp->stats().saves == 1);  // never twice, never none
      // The save went out twice with one count: the resend is the same datagram.
      std::vector<Bytes> saves;
      for (const auto& d : rig.wire->tx) {
        auto r = linudp::decode_request(d);
        if (r.ok() && r->rtc && r->rtc->id == 0x80) saves.push_back(d);
      }
      REQUIRE(saves.size() == 2);
      CHECK(saves[0] == saves[1]);
      if (k.unacknowledged || (k.lose_request && k.running == 0)) {
        // No answer to the resend either: ops::long_step looks for the drive.
        REQUIRE_FALSE(saved.ok());
        CHECK(saved.error().code == make_error_code(Errc::timeout));
        auto back = c.find_again("saving the command table to flash");
        REQUIRE(back.ok());
      } else {
        CHECK(saved.ok());
      }
      CHECK(rig.drive->state().ct_flash == rig.drive->state().ct_ram);
      CHECK(waited_s >= 120.0);  // the first wait: --long-timeout-s (120 s)
    }
  }
}

}  // namespace client_test_linudp_client
