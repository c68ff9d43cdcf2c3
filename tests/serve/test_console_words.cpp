// The console's words for people (lib/serve/console_words.cpp): what each
// error a technician can meet means and what to check, plan steps and the
// plan's verdict, messages without their section signs.
#include <catch2/catch.hpp>

#include "serve/console_words.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace serve_test_console_words {

using namespace lmcfg;
using namespace lmcfg::serve;

TEST_CASE("console words: each error a technician can meet has its sentence and checklist",
          "[console_words]") {
  auto h =
      words::help_for(Error(Errc::timeout, "no answer from drive 11h within 200.0 ms"), "press3/z");
  CHECK(h.sentence == "The drive at press3/z did not answer.");
  REQUIRE(h.checklist.size() == 5);
  CHECK(h.checklist[0] == "Is the drive powered? Its status LEDs are lit when it is.");
  CHECK(h.checklist[2] ==
        "Does the drive's ID (its address switches) match the position's drive ID?");

  h = words::help_for(Error(Errc::checksum_mismatch, "checksum mismatch"), "");
  CHECK(h.sentence ==
        "Something answers on the line, but not in a way the service can read: most often a "
        "baud rate that differs from the drive's, or another device with the same ID.");
  CHECK(h.checklist[0] == "Is the line's baud rate the drive's?");

  h = words::help_for(Error(make_comm_state_error(0xC4), "refused"), "press3/x");
  CHECK(h.sentence == "The drive at press3/x answered, but refused the command.");

  h = words::help_for(Error(Errc::not_found, "plan 'ab' expired at 2027-01-15T08:05:00Z"), "");
  CHECK(h.sentence ==
        "The plan expired: a plan is valid for a few minutes only, because the drive may change "
        "in the meantime. Nothing was written.");
  CHECK(h.checklist == std::vector<std::string>{"Make a new plan: it reads the drive again."});

  h = words::help_for(Error(Errc::interrupted, "the service is stopping"), "");
  CHECK(h.sentence == "The service is stopping, so it took no new work. Nothing was written.");

  h = words::help_for(Error(Errc::link_closed, "port closed"), "");
  CHECK(h.sentence ==
        "The service cannot reach the line: its serial port or network server does not work.");

  h = words::help_for(
      Error(Errc::plan_refused,
            "the restore of drive press3/z is running as job 4: it is not stopped between its "
            "writes; wait for it to end"),
      "press3/z");
  CHECK(h.sentence ==
        "A restore of this drive is running now; it is not stopped between its writes.");
}

TEST_CASE("console words: a failed restore says what the drive holds", "[console_words]") {
  serve::Json job{{"message", "no answer from drive 11h"},
                  {"exit_code", 4},
                  {"drive_state", "untouched: nothing was written to it"}};
  auto h = words::restore_failure_help(job, "press3/z");
  CHECK(h.sentence ==
        "The drive at press3/z stopped answering during the restore. The drive is untouched: "
        "nothing was written to it.");
  job["exit_code"] = 6;
  job.erase("drive_state");
  h = words::restore_failure_help(job, "press3/z");
  CHECK(h.sentence == "Everything was written, but the drive reads back differently.");
}

TEST_CASE("console words: the CLI's exit codes read back as the kinds of docs/cli.md",
          "[console_words]") {
  CHECK(words::errc_for_exit_code(2) == Errc::invalid_argument);
  CHECK(words::errc_for_exit_code(3) == Errc::plan_refused);
  CHECK(words::errc_for_exit_code(4) == Errc::timeout);
  CHECK(words::errc_for_exit_code(5) == Errc::drive_refused);
  CHECK(words::errc_for_exit_code(6) == Errc::verify_mismatch);
  CHECK(words::errc_for_exit_code(70) == Errc::cancelled);
  // A restore that failed on bad input reads as a read that did: one table.
  serve::Json job{{"message", "bad value"}, {"exit_code", 2}};
  CHECK(words::restore_failure_help(job, "press3/z").sentence ==
        words::help_for(Error(Errc::invalid_argument, "bad value"), "press3/z").sentence);
  job["exit_code"] = 5;
  CHECK(words::restore_failure_help(job, "press3/z").sentence ==
        "The drive at press3/z answered, but refused the command.");
}

TEST_CASE("console words: messages without section signs, plan steps in words", "[console_words]") {
  CHECK(words::plain("stop MC and application software (\u00a713.3): the axis stops") ==
        "stop MC and application software: the axis stops");
  CHECK(words::plain("save the command table to flash (\u00a712 08h 00h saves every entry; up "
                     "to 10 s)") == "save the command table to flash");
  CHECK(words::plain("no curve group (LinRS 3V27 \u00a711): curves not asked") ==
        "no curve group: curves not asked");
  CHECK(words::plain("the file, which seed 003 \u00a710 does not define") ==
        "the file, which seed 003 does not define");
  CHECK(words::plain("no section sign (here)") == "no section sign (here)");

  CHECK(words::step(serve::Json{{"kind", "stop_mc"}}) ==
        "Stop motion control: the axis stops, and stays stopped until the restore ends");
  CHECK(words::step(serve::Json{{"kind", "default_layer"}, {"layer", "MC"}}) ==
        "Set every MC parameter to its factory default");
  CHECK(words::step(serve::Json{{"kind", "write_curve"}, {"id", 3}}) == "Write curve 3");
  CHECK(words::step(serve::Json{{"kind", "reset"}}) ==
        "Restart the drive (it is silent for a few seconds)");
}

TEST_CASE("console words: the plan's verdict first", "[console_words]") {
  bool refused = true;
  auto plan = serve::Json::parse(R"({"steps": [{"kind": "stop_mc"}, {"kind": "write_rom"},
    {"kind": "write_rom"}, {"kind": "write_curve"}, {"kind": "reset"}], "problems": [],
    "incompatible": []})");
  CHECK(words::verdict(plan, refused) ==
        "Will write 2 values, replace 1 curve. The axis stops during the restore. The drive "
        "restarts at the end.");
  CHECK_FALSE(refused);

  plan["incompatible"] = serve::Json::array({serve::Json{{"message", "3010h absent"}}});
  CHECK(words::verdict(plan, refused) ==
        "Cannot be restored as it stands: this drive cannot take 1 value of the configuration "
        "(listed below). You can restore the rest without them; the position then stays in "
        "drift until someone approves the result. The rest would write 2 values, replace 1 "
        "curve. The axis stops during the restore. The drive restarts at the end.");
  CHECK(refused);

  plan["problems"] = serve::Json::array({serve::Json{{"message", "wrong drive"}}});
  CHECK(words::verdict(plan, refused) ==
        "Cannot be restored: 1 problem (below) must be resolved first. Nothing will be "
        "written.");
  CHECK(refused);

  CHECK(words::verdict(serve::Json::parse(R"({"steps": [], "nothing_to_do": true})"), refused) ==
        "Nothing to write: the drive already holds this configuration.");
}

TEST_CASE("console words: plan notes and progress lines in a technician's words",
          "[console_words]") {
  CHECK(words::note("Intf: the UPID database does not know the address usage of 9 parameter(s); "
                    "read the target's UPID list (412 UPIDs, \u00a710.3) to check ROM write "
                    "access") ==
        "The parameter list does not say whether some of these values can be stored on the "
        "drive, so the service asked the drive itself. Nothing to do.");
  CHECK(words::note("leftover MC 13A2h = 5 goes back to its default") ==
        "MC 13A2h = 5 is not set by the configuration: it goes back to its factory setting.");
  CHECK(words::note("found the recovery record /var/lib/lmcfg/restore-x.json of a restore that "
                    "did not finish (2027-01-15T08:00:00Z): the command table ...") ==
        "An earlier restore of this drive did not finish: the command table and curves are "
        "saved again and the drive restarts at the end.");
  CHECK(words::note("something else (\u00a712)") == "Something else");

  CHECK(words::progress("plan: command table") == "Checking the drive: reading its command table");
  CHECK(words::progress("plan: MC UPID list") ==
        "Checking the drive: reading its list of MC parameters");
  CHECK(words::progress("save the command table to flash (\u00a712 08h 00h saves every entry; up "
                        "to 10 s)") ==
        "Saving the command table to the drive's flash (10 s by the manual; some drives take a "
        "minute or more)");
  CHECK(words::progress("write ROM MC 13A2h P Gain: 5 -> 7") == "Writing MC 13A2h P Gain: 5 -> 7");
  CHECK(words::progress("write curve 3 'Lift'") == "Writing curve 3 'Lift'");
  CHECK(words::progress("stop MC and application software (\u00a713.3): the axis stops") ==
        "Stopping motion control (the axis stops)");
  CHECK(words::progress("verify curves") == "Reading back the curves");
  for (const char* cli : {"plan: comparing parameters", "reset the drive so the ROM values act"})
    CHECK(words::progress(cli).find("plan:") == std::string::npos);
}

TEST_CASE("console words: what the drive holds after a restore stopped at a step",
          "[console_words]") {
  using A = ops::PlanStep::Action;
  ops::RestoreOutcome out;
  for (A a : {A::stop_mc, A::write_rom, A::save_ct, A::start_mc, A::reset}) {
    ops::PlanStep st;
    st.action = a;
    out.plan.steps.push_back(st);
  }
  CHECK(words::drive_state_after(out, 1) == "untouched: nothing was written to it");
  out.written = true;
  CHECK(words::drive_state_after(out, 2) ==
        "partially configured, and its motion control is stopped: the axis does not move until "
        "a restore completes");
  // Motion control started again before the step in hand.
  out.plan.steps.insert(out.plan.steps.begin() + 4, out.plan.steps[1]);  // a write after start_mc
  CHECK(words::drive_state_after(out, 4) ==
        "partially configured: some values were written, others not");
  CHECK(words::drive_state_after(out, 5) ==
        "written, but it has not answered since its restart: whether it holds the whole "
        "configuration is known when it answers again (a restore then reads it back)");
  CHECK(words::drive_state_after(out, 9).rfind("written, but it has not answered", 0) == 0);
}

}  // namespace serve_test_console_words
