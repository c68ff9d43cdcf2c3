// Client (lib/client/client.cpp): how an answer is classified. The state byte
// decides a refusal; the key and value fields LinRS marks "No meaning" for
// such answers (the §11 curve transcripts) may hold the request's key, zeros
// or anything else, and the outcome is the same: the drive's refusal
// (Errc from the state, exit 5 in the tools), never a garbled answer.
#include <catch2/catch.hpp>

#include "client/client.hpp"
#include "codec/messages.hpp"
#include "common/result.hpp"
#include "sim/drive.hpp"
#include "sim/link.hpp"
#include "test_sim_harness.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace client_test_client {

using namespace lmcfg;

namespace {

struct Rig {
  std::shared_ptr<sim::Drive> drive;
  sim::SimLink link;
  client::LinrsClient client;
  Rig(sim::RefusalFields fields, bool mc_running)
      : drive(std::make_shared<sim::Drive>([&] {
          auto s = test::load_fixture("commissioned-axis.json");
          s.options.refusal_fields = fields;
          s.options.missing_curve_zero_sizes = false;    // C8 for an empty curve ID
          s.options.missing_ct_entry_zero_size = false;  // C8 for an undefined CT entry
          s.mc_running = mc_running;
          return s;
        }())),
        link(drive),
        client(link, client::ClientOptions{}) {}
};

// The refusal of one request, as the client reports it.
template <class F>
Error refusal_of(F&& request) {
  auto r = request();
  REQUIRE_FALSE(r.ok());
  return r.error();
}

const char* fields_name(sim::RefusalFields f) {
  switch (f) {
    case sim::RefusalFields::echo:
      return "the request's key";
    case sim::RefusalFields::zeros:
      return "zeros";
    case sim::RefusalFields::arbitrary:
      return "arbitrary bytes";
  }
  return "?";
}

}  // namespace

TEST_CASE("LinRS §10 §11 §12 a refusal is the drive's whatever its No-meaning fields hold",
          "[client][refusal]") {
  const auto fields =
      GENERATE(sim::RefusalFields::echo, sim::RefusalFields::zeros, sim::RefusalFields::arbitrary);
  INFO("refusal fields: " << fields_name(fields));
  Rig rig(fields, true);
  auto& c = rig.client;
  const auto stale_before = c.stats().stale_answers;

  struct Case {
    const char* what;
    std::function<Result<void>()> request;
    std::string message;
  };
  // A keyed request sent as it is (transact), for the groups whose typed call
  // treats a refusal as "nothing there" (curve sizes, CT setup read).
  auto raw = [&](codec::Telegram t) -> Result<void> {
    auto r = c.transact(t, transport::Millis(200), true);
    if (!r.ok()) return r.error();
    return {};
  };
  const std::vector<Case> cases = {
      {"§10 ROM read of an unknown UPID",
       [&]() -> Result<void> { return c.read_rom(0x9999).error(); },
       "drive 11h refused ID 11h parameter configuration (main 05h sub 00h), 2 data byte(s) for "
       "UPID 9999h: C8h parameter unknown UPID"},
      {"§10 type of an unknown UPID", [&]() -> Result<void> { return c.get_type(0x9999).error(); },
       "drive 11h refused ID 11h parameter configuration (main 05h sub 04h), 2 data byte(s) for "
       "UPID 9999h: C8h parameter unknown UPID"},
      {"§10 default of an unknown UPID",
       [&]() -> Result<void> { return c.get_default(0x9999).error(); },
       "drive 11h refused ID 11h parameter configuration (main 05h sub 07h), 2 data byte(s) for "
       "UPID 9999h: C8h parameter unknown UPID"},
      {"§11 curve info of a missing curve",
       [&]() -> Result<void> { return c.read_curve_info(77, 70).error(); },
       "drive 11h refused ID 11h curve (main 04h sub 09h), 2 data byte(s) for curve 77: C8h "
       "parameter unknown UPID"},
      {"§11 curve data of a missing curve",
       [&] { return raw(codec::make_curve(0x11, codec::CurveOp::read_data, 77)); },
       "drive 11h refused ID 11h curve (main 04h sub 0Ah), 2 data byte(s) for curve 77: C8h "
       "parameter unknown UPID"},
      {"§11 save curves while MC runs", [&]() -> Result<void> { return c.save_curves(); },
       "drive 11h refused ID 11h curve (main 04h sub 00h), 0 data byte(s): C4h undefined "
       "message sub ID"},
      {"§12 setup read of an undefined entry",
       [&] { return raw(codec::make_ct(0x11, codec::CtOp::setup_read, 200)); },
       "drive 11h refused ID 11h command table (main 08h sub 05h), 2 data byte(s) for entry 200: "
       "C8h parameter unknown UPID"},
      {"§12 data of an undefined entry",
       [&] { return raw(codec::make_ct(0x11, codec::CtOp::read_data, 200)); },
       "drive 11h refused ID 11h command table (main 08h sub 06h), 2 data byte(s) for entry 200: "
       "C8h parameter unknown UPID"},
      {"§12 save the CT while MC runs", [&]() -> Result<void> { return c.save_ct(); },
       "drive 11h refused ID 11h command table (main 08h sub 00h), 0 data byte(s): C4h "
       "undefined message sub ID"},
  };
  for (const auto& k : cases) {
    INFO(k.what);
    const Error e = refusal_of(k.request);
    CHECK(e.message == k.message);
    CHECK(e.code == ErrorClass::drive_refusal);
  }
  // No answer was taken for another request's (the key check did not apply).
  CHECK(c.stats().stale_answers == stale_before);
  CHECK(c.stats().retries == 0);
}

TEST_CASE("LinRS §11 §12 an empty curve ID or CT entry answered C8 with zeroed fields is empty",
          "[client][refusal]") {
  const auto fields =
      GENERATE(sim::RefusalFields::echo, sim::RefusalFields::zeros, sim::RefusalFields::arbitrary);
  INFO("refusal fields: " << fields_name(fields));
  Rig rig(fields, true);
  auto sizes = rig.client.curve_sizes(77);
  REQUIRE(sizes.ok());
  CHECK_FALSE(sizes->has_value());
  auto entry = rig.client.probe_ct_entry(200);
  REQUIRE(entry.ok());
  CHECK_FALSE(entry->has_value());
}

TEST_CASE("LinRS 3V27 p32 a flash save refused with D7h MC SW not stopped: a refusal at once",
          "[client][refusal]") {
  // The simulator plays the newer manual's reading (flash_refused_state D7h) as
  // well as the seed's (C4h, the case above): either is the drive's refusal.
  Rig rig(sim::RefusalFields::echo, true);
  rig.drive->state().options.flash_refused_state = 0xD7;
  auto& c = rig.client;
  const Error curves = refusal_of([&]() -> Result<void> { return c.save_curves(); });
  CHECK(curves.message ==
        "drive 11h refused ID 11h curve (main 04h sub 00h), 0 data byte(s): D7h MC SW not stopped "
        "(LinRS 3V27 p32): stop the motion control software first");
  CHECK(curves.code == ErrorClass::drive_refusal);
  CHECK(curves.code.value() == 0xD7);
  const Error ct = refusal_of([&]() -> Result<void> { return c.save_ct(); });
  CHECK(ct.message ==
        "drive 11h refused ID 11h command table (main 08h sub 00h), 0 data byte(s): D7h MC SW not "
        "stopped (LinRS 3V27 p32): stop the motion control software first");
  // A named state is not taken for a garbled answer: no retry, not counted as undocumented.
  CHECK(c.stats().retries == 0);
  CHECK(c.stats().undocumented_states == 0);
}

TEST_CASE(
    "EtherCAT curves: the two bytes after the 70-byte curve info block hold stale data: not part "
    "of the block, never compared",
    "[client][blocks]") {
  // The simulator's stale_block_padding: the padding of the 18th chunk changes
  // with every read. Without a checksum two reads must agree (docs/reliability.md).
  const bool stale = GENERATE(false, true);
  INFO("stale padding: " << stale);
  Rig rig(sim::RefusalFields::echo, true);
  rig.drive->state().options.stale_block_padding = stale;
  const Bytes want = rig.drive->state().curves_ram.at(1).info;
  REQUIRE(want.size() == 70);
  auto c = rig.client.read_curve(1);
  REQUIRE(c.ok());
  REQUIRE(c->has_value());
  CHECK((*c)->info == want);  // 70 bytes: the padding is dropped
  CHECK(rig.client.stats().disagreements == 0);
  CHECK(rig.client.stats().retries == 0);
}

}  // namespace client_test_client
