#pragma once
// The rules for free text that ends up in the archive's commit messages, job
// records, pages and API answers (docs/serve.md "Security model"): who asked,
// why (reason, ticket), revisions, labels. One checker for the service's API
// and the HTTP edge; one sanitizer for what is written without a check (CLI
// flags, messages from elsewhere); one escaper for what is read back (a commit
// message made by hand with invalid UTF-8).
#include <cstddef>
#include <string>
#include <string_view>

#include "common/result.hpp"

namespace lmcfg {

// Longest accepted values, in bytes (UTF-8). A reason is a sentence, a ticket
// and a name an identifier; a revision ("HEAD~2", a 40-digit hash, a tag).
inline constexpr std::size_t kMaxReasonBytes = 200;
inline constexpr std::size_t kMaxTicketBytes = 64;
inline constexpr std::size_t kMaxWhoBytes = 64;
inline constexpr std::size_t kMaxRevBytes = 200;
inline constexpr std::size_t kMaxLabelBytes = 200;

// Well-formed UTF-8 (RFC 3629 §4: no overlong forms, no surrogates, nothing
// above U+10FFFF). The offset of the first byte that is not, else npos.
std::size_t invalid_utf8_at(std::string_view s) noexcept;
inline bool valid_utf8(std::string_view s) noexcept {
  return invalid_utf8_at(s) == std::string_view::npos;
}

// A control character: C0 (U+0000..U+001F, line breaks and tab included),
// DEL (U+007F) or C1 (U+0080..U+009F, two bytes in UTF-8). The offset of the
// first one in well-formed UTF-8 `s`, else npos.
std::size_t control_at(std::string_view s) noexcept;

// `s` with each byte that is not part of well-formed UTF-8 written as "\xNN"
// (upper-case hex): valid UTF-8 out, whatever came in. Valid text is returned
// unchanged (a backslash stays a backslash).
std::string escape_invalid_utf8(std::string_view s);

// `s` made one line of valid UTF-8: invalid bytes escaped as above, every
// control character (line breaks too) replaced by a space. For text written
// into a commit message or a log line that no check refused.
std::string one_line(std::string_view s);

// `s` for a log line: each byte that is a control character (C0, DEL, the two
// bytes of a C1) or not part of well-formed UTF-8 written as "\xNN"
// (upper-case hex); the rest unchanged. What a client sent can neither start
// a line of its own in the log nor move the terminal's cursor. Applying it
// twice changes nothing more.
std::string log_text(std::string_view s);

// One line of valid UTF-8 without control characters, at most `max_bytes`
// bytes. Errc::invalid_argument otherwise, the message naming `field`:
//   "reason is not valid UTF-8 (byte 0xFF at offset 3): send UTF-8 text"
//   "reason contains a control character (0x0A at offset 5): give one line without control
//    characters"
//   "reason is 240 bytes long, at most 200 are accepted: shorten it"
Result<void> check_line(std::string_view field, std::string_view value, std::size_t max_bytes);

}  // namespace lmcfg
