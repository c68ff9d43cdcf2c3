#pragma once
// The request -> answer vocabulary of LinRS (LinRS §5-14), one table for
// both sides: the client uses it to match answers to requests, the simulated
// drive to accept requests and to address its answers. The golden vectors of
// the manual (tests/golden/) check it against every captured exchange.
#include <cstdint>
#include <optional>

#include "codec/frame.hpp"
#include "codec/messages.hpp"

namespace lmcfg::codec {

// §14 error info (main 07).
enum class ErrorInfoOp : std::uint8_t {
  actual_text = 0x00,
  text_of_code = 0x01,
  counters = 0x02,
  log_entry = 0x03,
};

// §9 subs 11h-14h: set the ROM values of layer 1 (OS) .. 4 (Appl) to default.
inline constexpr std::uint8_t kParamDefaultLayerFirst = 0x11;
inline constexpr std::uint8_t kParamDefaultLayerLast = 0x14;

struct RequestSpec {
  std::uint8_t answer_sub =
      0;                      // §6 table: 00 default response, 40h, 50h+sub, 60h, 70h+sub, 80h+sub
  bool writes = false;        // changes drive state (never repeated blindly)
  bool keyed = false;         // the answer echoes the UPID / curve / entry / block of data[0..1]
  std::uint8_t data_len = 0;  // bytes the request carries after SUB MAIN (at least)
};

// What the manual defines for the request (main, sub); nullopt for a sub ID
// the manual does not list (a drive answers C4h, §16.1). Main 00 (§6) and
// the motion command interface (§8, sub 00) included.
std::optional<RequestSpec> request_spec(std::uint8_t main, std::uint8_t sub);
// A main ID of §5 (00..08); a drive answers others with C3h (§16.1).
bool known_main(std::uint8_t main);

// The same, for a request telegram; an unknown (main, sub) gives a spec
// expecting the default response, not writing, not keyed.
std::uint8_t expected_answer_sub(const Telegram& request);
bool is_write_request(const Telegram& request);
// The key the answer must echo (data[0..1]), or nullopt when the answer's key
// is not tied to the request (lists' "get next", saves, delete all).
std::optional<std::uint16_t> request_key(const Telegram& request);

}  // namespace lmcfg::codec
