// Errors (lib/common/result.cpp): the codes' and LinRS communication states'
// texts, and the one error classification (ErrorClass): every code's class,
// and the comparisons the client, the tools' exit codes, db scan and the tests
// make with it.
#include <catch2/catch.hpp>
#include <map>
#include <system_error>

#include "common/result.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace common_test_result {

using namespace lmcfg;

TEST_CASE("error class: every Errc has exactly one class", "[error_class]") {
  const std::map<Errc, ErrorClass> expected = {
      {Errc::timeout, ErrorClass::bad_answer},
      {Errc::link_closed, ErrorClass::link_down},
      {Errc::io_error, ErrorClass::link_down},
      {Errc::frame_short, ErrorClass::bad_answer},
      {Errc::frame_overlong, ErrorClass::bad_answer},
      {Errc::frame_malformed, ErrorClass::bad_answer},
      {Errc::checksum_mismatch, ErrorClass::bad_answer},
      {Errc::unexpected_response, ErrorClass::bad_answer},
      {Errc::drive_refused, ErrorClass::drive_refusal},
      {Errc::invalid_argument, ErrorClass::bad_input},
      {Errc::parse_error, ErrorClass::bad_input},
      {Errc::unsupported_version, ErrorClass::bad_input},
      {Errc::validation_failed, ErrorClass::bad_input},
      {Errc::not_found, ErrorClass::bad_input},
      {Errc::file_error, ErrorClass::bad_input},
      {Errc::plan_refused, ErrorClass::plan_refused},
      {Errc::verify_mismatch, ErrorClass::verify_mismatch},
      {Errc::cancelled, ErrorClass::bad_input},
      {Errc::not_supported, ErrorClass::bad_input},
      {Errc::interrupted, ErrorClass::interrupted},
  };
  const ErrorClass classes[] = {ErrorClass::link_failure,    ErrorClass::bad_answer,
                                ErrorClass::link_down,       ErrorClass::drive_refusal,
                                ErrorClass::bad_input,       ErrorClass::plan_refused,
                                ErrorClass::verify_mismatch, ErrorClass::interrupted};
  // Every value of the enum, from ok to the last one, is in the table above.
  CHECK_FALSE(class_of(make_error_code(Errc::ok)));
  for (int v = 1; v <= static_cast<int>(Errc::interrupted); ++v) {
    const auto e = static_cast<Errc>(v);
    INFO("Errc " << v << " " << make_error_code(e).message());
    REQUIRE(expected.count(e) == 1);
    const ErrorClass want = expected.at(e);
    CHECK(class_of(make_error_code(e)) == want);
    for (ErrorClass c : classes) {
      const bool member =
          c == want || (c == ErrorClass::link_failure &&
                        (want == ErrorClass::bad_answer || want == ErrorClass::link_down));
      CHECK((make_error_code(e) == c) == member);
    }
  }
  CHECK(expected.size() == static_cast<std::size_t>(Errc::interrupted));
  CHECK_FALSE(class_of(std::error_code(static_cast<int>(Errc::interrupted) + 1, lmcfg_category())));
}

TEST_CASE("error class: communication states and foreign codes", "[error_class]") {
  // Every state byte of LinRS §16.1 and any undocumented one is a refusal.
  for (unsigned s = 0; s <= 0xFF; ++s) {
    const auto code = make_comm_state_error(s);
    CHECK(class_of(code) == ErrorClass::drive_refusal);
    CHECK(code == ErrorClass::drive_refusal);
    CHECK_FALSE(code == ErrorClass::link_failure);
    CHECK_FALSE(code == ErrorClass::bad_answer);
  }
  // An OS error on the link is a link that failed, not a lost answer.
  const auto os = std::make_error_code(std::errc::broken_pipe);
  CHECK(class_of(os) == ErrorClass::link_down);
  CHECK(os == ErrorClass::link_failure);
  CHECK_FALSE(os == ErrorClass::bad_answer);
  CHECK(make_error_condition(ErrorClass::link_failure).message() == "communication failure");
}

TEST_CASE("error class: the client repeats only lost or garbled answers", "[error_class]") {
  // One class per question: the client's retry set (bad_answer) leaves out
  // link_closed and io_error, the tests' communication failure (link_failure)
  // and the exit code 4 include them.
  CHECK(make_error_code(Errc::timeout) == ErrorClass::bad_answer);
  CHECK_FALSE(make_error_code(Errc::link_closed) == ErrorClass::bad_answer);
  CHECK_FALSE(make_error_code(Errc::io_error) == ErrorClass::bad_answer);
  CHECK(make_error_code(Errc::link_closed) == ErrorClass::link_failure);
  CHECK(make_error_code(Errc::io_error) == ErrorClass::link_failure);
  Error refusal(make_comm_state_error(0xC8), "C8h");
  auto r = unless_refused(Result<int>(refusal));
  REQUIRE(r.ok());
  CHECK_FALSE(r->has_value());
  CHECK_FALSE(unless_refused(Result<int>(Error(Errc::timeout, "lost"))).ok());
}

TEST_CASE("LinRS §16.1 communication states: each documented state's text, others named raw",
          "[error_class][result]") {
  // LinRS §16.1: "C1h Checksum error", "C2h Message format error End of
  // Telegram (04h) missing", "C3h Undefined Message Main ID", "C4h Undefined
  // Message Sub ID", "C5h Wrong Baud Rate Defined With S1", "C8h Parameter
  // Unknown UPID", "C9h Parameter Wrong Type".
  CHECK(make_comm_state_error(0xC1).message() == "C1h checksum error");
  CHECK(make_comm_state_error(0xC2).message() ==
        "C2h message format error: end of telegram (04h) missing");
  CHECK(make_comm_state_error(0xC3).message() == "C3h undefined message main ID");
  CHECK(make_comm_state_error(0xC4).message() == "C4h undefined message sub ID");
  CHECK(make_comm_state_error(0xC5).message() == "C5h wrong baud rate defined with S1");
  CHECK(make_comm_state_error(0xC8).message() == "C8h parameter unknown UPID");
  CHECK(make_comm_state_error(0xC9).message() == "C9h parameter wrong type");
  CHECK(make_comm_state_error(0xC7).message() == "C7h undocumented communication state");
  CHECK(std::string(make_comm_state_error(0xC8).category().name()) == "linrs-comm-state");
  CHECK(make_comm_state_error(0xC8).value() == 0xC8);
}

TEST_CASE("result: lmcfg error codes say what went wrong", "[error_class][result]") {
  CHECK(make_error_code(Errc::timeout).message() == "no answer before the deadline");
  CHECK(make_error_code(Errc::checksum_mismatch).message() == "telegram checksum mismatch");
  CHECK(make_error_code(Errc::not_supported).message() == "not supported by this link");
  CHECK(std::string(make_error_code(Errc::timeout).category().name()) == "lmcfg");
  Error e(Errc::file_error, "x.json: cannot open");
  CHECK(e.code == make_error_code(Errc::file_error));
  CHECK(e.message == "x.json: cannot open");
  Result<int> ok(7);
  REQUIRE(ok.ok());
  CHECK(*ok == 7);
  Result<int> bad(e);
  REQUIRE_FALSE(bad.ok());
  CHECK(bad.error().message == "x.json: cannot open");
}

TEST_CASE("LinRS 3V27 p32 communication state D7h is a refusal with its own text", "[result]") {
  // 3V27 p32, the answer to "save curves to flash": "MC SW not stopped". Not in
  // seed 003 §16.1.
  CHECK(make_comm_state_error(0xD7).message() ==
        "D7h MC SW not stopped (LinRS 3V27 p32): stop the motion control software first");
  CHECK(class_of(make_comm_state_error(0xD7)) == ErrorClass::drive_refusal);
  CHECK(std::string(comm_state_text(0xD7)) ==
        "D7h MC SW not stopped (LinRS 3V27 p32): stop the motion control software first");
  CHECK(comm_state_text(0xC7) == nullptr);
  CHECK(comm_state_text(0x00) == nullptr);  // ok is not an error state
}

}  // namespace common_test_result
