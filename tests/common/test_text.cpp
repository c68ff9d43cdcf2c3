// Free text rules (lib/common/text.cpp): well-formed UTF-8 as RFC 3629 §4
// defines it, control characters, the one-line sanitizer, the escaper and
// check_line's exact messages.
#include <catch2/catch.hpp>

#include "common/text.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace common_test_text {

using namespace lmcfg;

TEST_CASE("RFC 3629 §7: the examples are well-formed UTF-8", "[common][text]") {
  // "A<NOT IDENTICAL TO><ALPHA>." = 41 E2 89 A2 CE 91 2E
  CHECK(valid_utf8("\x41\xE2\x89\xA2\xCE\x91\x2E"));
  // Korean "hangugeo" = ED 95 9C EA B5 AD EC 96 B4
  CHECK(valid_utf8("\xED\x95\x9C\xEA\xB5\xAD\xEC\x96\xB4"));
  // Japanese "nihongo" = E6 97 A5 E6 9C AC E8 AA 9E
  CHECK(valid_utf8("\xE6\x97\xA5\xE6\x9C\xAC\xE8\xAA\x9E"));
  // BOM then U+233B4 = EF BB BF F0 A3 8E B4
  CHECK(valid_utf8("\xEF\xBB\xBF\xF0\xA3\x8E\xB4"));
  CHECK(valid_utf8(""));
}

TEST_CASE("RFC 3629 §4: ill-formed sequences and where they start", "[common][text]") {
  CHECK(invalid_utf8_at("ab\xFF") == 2);
  CHECK(invalid_utf8_at("\xC0\xAF") == 0);          // overlong "/" (RFC 3629 §10)
  CHECK(invalid_utf8_at("\xE0\x80\xAF") == 0);      // overlong, three bytes
  CHECK(invalid_utf8_at("x\xED\xA0\x80") == 1);     // surrogate U+D800
  CHECK(invalid_utf8_at("\xF4\x90\x80\x80") == 0);  // above U+10FFFF
  CHECK(invalid_utf8_at("ok\xE2\x89") == 2);        // cut short
  CHECK(invalid_utf8_at("\x80") == 0);              // a lone continuation byte
  CHECK(invalid_utf8_at("\xF4\x8F\xBF\xBF") == std::string_view::npos);  // U+10FFFF
}

TEST_CASE("text: control characters, C0, DEL and C1", "[common][text]") {
  CHECK(control_at("motor replaced") == std::string_view::npos);
  CHECK(control_at("a\nb") == 1);
  CHECK(control_at("tab\there") == 3);
  CHECK(control_at("del\x7F") == 3);
  CHECK(control_at("csi \xC2\x9B") == 4);                           // U+009B
  CHECK(control_at("nbsp \xC2\xA0 ok") == std::string_view::npos);  // U+00A0 is not one
}

TEST_CASE("text: invalid bytes escaped, valid text unchanged", "[common][text]") {
  CHECK(escape_invalid_utf8("motor \xFF\xFE replaced") == "motor \\xFF\\xFE replaced");
  CHECK(escape_invalid_utf8("caf\xC3\xA9 \\x41") == "caf\xC3\xA9 \\x41");
  CHECK(valid_utf8(escape_invalid_utf8("\xC0\xAF\xED\xA0\x80")));
}

TEST_CASE("text: one_line leaves no line break and no invalid byte", "[common][text]") {
  CHECK(one_line("fix\nOperator: mallory") == "fix Operator: mallory");
  CHECK(one_line("a\r\n\tb\xC2\x85z\xFF") == "a   b z\\xFF");
  CHECK(one_line("plain") == "plain");
}

TEST_CASE("text: log_text escapes control characters and invalid bytes as hex (xNN)",
          "[common][text]") {
  CHECK(log_text("fix\r\nOperator: mallory") == "fix\\x0D\\x0AOperator: mallory");
  CHECK(log_text(std::string("esc\x1B[2Jbel\x07nul\0end", 18)) == "esc\\x1B[2Jbel\\x07nul\\x00end");
  CHECK(log_text("del\x7F c1\xC2\x9B bad\xFF") == "del\\x7F c1\\xC2\\x9B bad\\xFF");
  CHECK(log_text("caf\xC3\xA9 \xC2\xA0 \\ plain") == "caf\xC3\xA9 \xC2\xA0 \\ plain");
  const std::string once = log_text("a\nb\xFF");
  CHECK(log_text(once) == once);
}

TEST_CASE("text: check_line's messages", "[common][text]") {
  CHECK(check_line("reason", "motor replaced", kMaxReasonBytes).ok());
  auto bad = check_line("reason", "abc\xFF", kMaxReasonBytes);
  REQUIRE_FALSE(bad.ok());
  CHECK(bad.error().code == Errc::invalid_argument);
  CHECK(bad.error().message ==
        "reason is not valid UTF-8 (byte 0xFF at offset 3): send UTF-8 text");
  auto nl = check_line("ticket", "T-1\nOperator: mallory", kMaxTicketBytes);
  REQUIRE_FALSE(nl.ok());
  CHECK(nl.error().message ==
        "ticket contains a control character (0x0A at offset 3): give one line without "
        "control characters");
  auto c1 = check_line("who", "x\xC2\x9B", kMaxWhoBytes);
  REQUIRE_FALSE(c1.ok());
  CHECK(c1.error().message ==
        "who contains a control character (0x9B at offset 1): give one line without control "
        "characters");
  auto longer = check_line("reason", std::string(201, 'r'), kMaxReasonBytes);
  REQUIRE_FALSE(longer.ok());
  CHECK(longer.error().message == "reason is 201 bytes long, at most 200 are accepted: shorten it");
  CHECK(check_line("reason", std::string(200, 'r'), kMaxReasonBytes).ok());
}

}  // namespace common_test_text
