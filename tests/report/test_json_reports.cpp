// The commands' --json reports (lib/report/json_reports.cpp), checked against
// the examples and member lists of docs/json-reports.md: member names, their
// order and their values, as the CLI prints them (`dump()`).
#include <catch2/catch.hpp>
#include <string>

#include "config/model.hpp"
#include "db/database.hpp"
#include "ops/restore_run.hpp"
#include "report/json_reports.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace report_test_json_reports {

using namespace lmcfg;

namespace {

config::DriveConfig counted(std::size_t params, std::size_t curves, std::size_t entries) {
  config::DriveConfig c;
  for (std::size_t i = 0; i < params; ++i) {
    config::Parameter p;
    p.upid = static_cast<std::uint16_t>(0x1000 + i);
    c.layers[i % 2].push_back(p);
  }
  for (std::size_t i = 0; i < curves; ++i)
    c.curves.emplace_back().id = static_cast<std::uint32_t>(i + 1);
  for (std::size_t i = 0; i < entries; ++i)
    c.ct_entries.emplace_back().id = static_cast<std::uint32_t>(i);
  return c;
}

}  // namespace

TEST_CASE("json reports: convert --json as docs/json-reports.md shows it", "[report][json]") {
  const auto j = report::convert_json("a.json", "a.xml", config::FileFormat::xml, 5120,
                                      counted(5, 1, 1), true);
  CHECK(j.dump() ==
        R"({"input":"a.json","output":"a.xml","format":"xml","format_version":3,"bytes":5120,)"
        R"("parameters":5,"curves":1,"ct_entries":1,"ct_decoded":true})");
  // A DeviceNet capture adds the number of values and live values.
  auto dn = counted(0, 0, 0);
  dn.devicenet.emplace();
  dn.devicenet->values.resize(3);
  dn.devicenet->live.resize(2);
  const auto d =
      report::convert_json("(stdin)", "dn.json", config::FileFormat::json, 10, dn, false);
  CHECK(d["devicenet_values"] == 3);
  CHECK(d["devicenet_live"] == 2);
  CHECK(d["input"] == "(stdin)");
}

TEST_CASE("json reports: get --json as docs/json-reports.md shows it, set --rom adds undo",
          "[report][json]") {
  db::Parameter d;
  d.upid = 0x13A2;
  d.name = "...";
  db::ValueSpec spec;
  spec.type = db::TypeCode::UInt16;
  auto j = report::param_json(0x13A2, &d, spec, "RAM", 16, "16", std::nullopt);
  CHECK(j.dump() == R"({"upid":"13A2","name":"...","type":"UINT16","memory":"RAM","raw":16,)"
                    R"("raw_hex":"00000010","integer":16,"unit":"","value":"16"})");
  // Unknown type: integer null; an undo record: its path and command.
  ops::UndoSaved u;
  u.path = "/state/undo/x.json";
  u.command = "lmcfg undo --port P --id 0x11";
  j = report::param_json(0x13A2, nullptr, {}, "ROM", 0xFFFFFFFF, "4294967295", u);
  CHECK(j["name"] == "");
  CHECK(j["type"] == "");
  CHECK(j["raw_hex"] == "FFFFFFFF");
  CHECK(j["integer"].is_null());
  CHECK(j["undo"].dump() ==
        R"({"path":"/state/undo/x.json","command":"lmcfg undo --port P --id 0x11"})");
}

TEST_CASE("json reports: default --json members, a failure before a report", "[report][json]") {
  CHECK(report::default_json("failed", nullptr, db::Database::empty(), "no answer").dump() ==
        R"({"outcome":"failed","steps":[],"kept":[],"error":"no answer"})");
  ops::DefaultReport rep;
  rep.done = {"MC defaulted"};
  rep.kept.push_back({0x2012, 8});
  rep.recovery_note = "none";
  const auto j = report::default_json("defaulted", &rep, db::Database::empty(), "");
  std::vector<std::string> keys;
  for (const auto& [k, v] : j.items()) keys.push_back(k);
  CHECK(keys == std::vector<std::string>{"outcome", "steps", "kept", "recovered", "recovery",
                                         "link_may_change"});
  CHECK(j["kept"][0]["upid"] == "2012");
  CHECK(j["kept"][0]["value"]["raw"] == 8);
  // Its journal steps: one per layer, the deletions, the kept value written back.
  ops::DefaultOptions o;
  o.layers = {false, true, false, false};
  o.command_table = true;
  const auto steps = report::default_steps_json(o, &rep, db::Database::empty());
  REQUIRE(steps.size() == 3);
  CHECK(steps[0].dump() == R"({"step":1,"action":"default_layer","layer":"MC"})");
  CHECK(steps[1].dump() == R"({"step":2,"action":"delete_all_ct"})");
  CHECK(steps[2]["action"] == "write_rom");
  CHECK(steps[2]["upid"] == "2012");
  CHECK(steps[2]["why"] == "kept communication value");
}

TEST_CASE("json reports: link --json settings as docs/json-reports.md shows them",
          "[report][json]") {
  ops::LinkState st;
  auto& src = st.values[static_cast<std::size_t>(ops::LinkSetting::baud_source)];
  src.upid = 0x200E;
  src.rom = 1;
  src.text = "hex switch S1";
  src.note = "seed 003 §10.2";
  st.values[static_cast<std::size_t>(ops::LinkSetting::parity)].note = "UPID unknown: ...";
  const auto s = report::link_settings_json(st);
  REQUIRE(s.size() == ops::kLinkSettings);
  CHECK(
      s[0].dump() ==
      R"({"setting":"baud-source","upid":"200E","rom":1,"value":"hex switch S1","note":"seed 003 §10.2"})");
  CHECK(s[5].dump() ==
        R"({"setting":"parity","upid":null,"rom":null,"value":"","note":"UPID unknown: ..."})");
}

TEST_CASE("json reports: undo --list and backup --json", "[report][json]") {
  ops::UndoEntry e;
  e.path = "/s/undo/_dev_ttyUSB0-11h/20261124T171500Z-restore.json";
  e.drive = "_dev_ttyUSB0-11h";
  e.time = "2026-11-24T17:15:00Z";
  e.command = "restore";
  e.holds = "MC 12 parameters";
  CHECK(report::undo_list_json("/s/undo", {e}).dump() ==
        R"({"dir":"/s/undo","records":[{"drive":"_dev_ttyUSB0-11h","time":"2026-11-24T17:15:00Z",)"
        R"("command":"restore","path":"/s/undo/_dev_ttyUSB0-11h/20261124T171500Z-restore.json",)"
        R"("holds":"MC 12 parameters"}]})");
  CHECK(report::backup_json("a.json", counted(4, 2, 3), 120).dump() ==
        R"({"file":"a.json","parameters":4,"curves":2,"ct_entries":3,"telegrams":120})");
}

TEST_CASE("json reports: restore --json and the journal's steps, with a second pass",
          "[report][json]") {
  ops::RestoreOutcome out;
  out.stage = ops::RestoreOutcome::Stage::verify_mismatch;
  out.written = true;
  ops::PlanStep stop;
  stop.action = ops::PlanStep::Action::stop_mc;
  stop.text = "stop motion control";
  ops::PlanStep start = stop;
  start.action = ops::PlanStep::Action::start_mc;
  start.text = "start motion control";
  out.plan.steps = {stop, start};
  ops::PlanStep save;
  save.action = ops::PlanStep::Action::save_ct;
  save.text = "save the command table";
  out.second_pass.emplace().steps = {save};
  out.mismatches = {"command table entry 3 differs"};
  out.undo.emplace();
  out.undo->path = "/u/rec.json";
  out.undo->command = "lmcfg undo --port /dev/ttyS0";
  out.error = Error(Errc::verify_mismatch, "read back differently");

  const auto j = report::restore_json(out, "axis.json");
  CHECK(j.dump() ==
        R"({"file":"axis.json","outcome":"verify mismatch","problems":[],"nothing_to_do":false,)"
        R"("steps":[{"step":1,"action":"stop_mc","text":"stop motion control"},)"
        R"({"step":2,"action":"start_mc","text":"start motion control"}],)"
        R"("losses":[],"skipped":[],"skipped_incompatible":[],"notes":[],"kept":[],)"
        R"("second_pass":[{"step":1,"action":"save_ct","text":"save the command table"}],)"
        R"("mismatches":["command table entry 3 differs"],)"
        R"("undo":{"path":"/u/rec.json","command":"lmcfg undo --port /dev/ttyS0"},)"
        R"("error":"read back differently"})");

  // The journal: the first pass's steps, then the second pass's.
  const auto steps = report::restore_steps_json(out);
  REQUIRE(steps.size() == 3);
  CHECK(steps[0]["action"] == "stop_mc");
  CHECK(steps[1]["action"] == "start_mc");
  CHECK(steps[2]["action"] == "save_ct");
  CHECK(steps[2]["step"] == 1);
}

}  // namespace report_test_json_reports
