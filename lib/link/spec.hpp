#pragma once
// One link specification, built once from what the user typed (the tool's
// options, an inventory line, a Python call) and passed down unchanged: the
// session derives its client's settings from it and keeps what changes while
// it runs (relink) as its own state, never in the spec.
#include <atomic>
#include <functional>
#include <string>

#include "client/client.hpp"
#include "link/port.hpp"
#include "transport/transport.hpp"

namespace lmcfg::link {

struct LinkSpec {
  PortSpec port;                     // parsed by the table of port schemes
  transport::SerialSettings serial;  // device: the serial device's path (serial ports)
  client::ClientOptions client;      // MACID, checksum, timeouts, retries
  std::string trace_path;            // "" = no trace
  bool real_time_sim = false;        // a simulated peer sleeps for the modelled wire time
  // Who opens the port ("lmcfg backup"), recorded in its lock so that a
  // second program is told who has it (transport::PortClaim).
  std::string holder;
  // The session's client has an adaptive answer deadline (capped by
  // client.timeout) and, unless fixed_settle, an adaptive settle (capped by
  // client.settle). fixed_settle: every settle waits client.settle (--settle-ms).
  bool fixed_settle = false;
  // client.agreeing_reads for the session: 0 = automatic (ClientOptions), N =
  // exactly N agreeing reads per value whatever the link (--agreeing-reads).
  int agreeing_reads = 0;

  // The same link to another drive of the line.
  LinkSpec for_macid(std::uint8_t id) const;
};

// The link settings as typed, before they are checked. Text where the user
// types text (an ID in hex or decimal, "auto"), numbers where the source has
// numbers; the defaults are the tool's.
struct LinkInput {
  std::string port;
  unsigned baud = 57600;
  std::string parity = "none";
  unsigned stop_bits = 1;
  std::string id = "0x11";
  std::string checksum = "none";
  std::string checksum_coverage = "id";
  std::string response_layout = "auto";
  int timeout_ms = 200;
  int settle_ms = -1;  // -1: adaptive (the failed exchange's deadline, at most 500 ms)
  int retries = 2;
  int long_timeout_s = 0;  // 0: the client's defaults (120 s each, ClientOptions)
  // How long to look for a drive whose long operation went unanswered
  // (Client::find_again); 0: the client's default (180 s).
  int recover_timeout_s = 0;
  std::string agreeing_reads = "auto";  // or 1..5
  std::string trace;
  std::string holder = "lmcfg";
  // Given to the client as they are (the tools' progress of long waits, the
  // interrupt flag of a writing command).
  std::function<void(const std::string&, transport::Millis)> on_long_wait;
  const std::atomic<bool>* cancel = nullptr;
};

// How a source names the settings in its messages: "--timeout-ms 0 is outside
// 1..60000" (the tool, an inventory line), "timeout_ms 0 is outside 1..60000"
// (Python).
struct InputNames {
  const char* id;
  const char* timeout_ms;
  const char* settle_ms;
  const char* retries;
  const char* long_timeout_s;
  const char* recover_timeout_s;
  const char* agreeing_reads;
  const char* response_layout;
  const char* automatic;  // the word for automatic agreeing reads
  bool quote_text;        // values shown quoted ('0x1FF') where they are typed text
};
inline constexpr InputNames kOptionNames{"--id",
                                         "--timeout-ms",
                                         "--settle-ms",
                                         "--retries",
                                         "--long-timeout-s",
                                         "--recover-timeout-s",
                                         "--agreeing-reads",
                                         "--response-layout",
                                         "auto",
                                         true};
inline constexpr InputNames kPythonNames{"id",
                                         "timeout_ms",
                                         "settle_ms",
                                         "retries",
                                         "long_timeout_s",
                                         "recover_timeout_s",
                                         "agreeing_reads",
                                         "response_layout",
                                         "0 (automatic)",
                                         false};

// The one check of link settings: line settings (for every kind of port: a
// gateway or the simulated drive is configured with them too, and an absurd
// value is a mistake wherever it is typed), MACID, checksum, response layout,
// timeouts, retries, agreeing reads, then the port by its scheme. The first
// problem as Errc::invalid_argument, worded with `names`.
Result<LinkSpec> make_link_spec(const LinkInput& in, const InputNames& names = kOptionNames);
// Every check of make_link_spec but the port's (a caller that checks ports
// on its own, reporting all of them: `fleet check`).
Result<void> check_link_settings(const LinkInput& in, const InputNames& names = kOptionNames);

}  // namespace lmcfg::link
