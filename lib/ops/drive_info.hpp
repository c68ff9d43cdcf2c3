#pragma once
// `lmcfg info`: the default response decoded (MC SW §3: state machine,
// status word §3.23, warn word §3.24), the actual error text (LinRS §14.1)
// and the error log (§14.3, §14.4) with texts from the database.
#include <optional>
#include <string>
#include <vector>

#include "client/client.hpp"

namespace lmcfg::db {
class Database;
}

namespace lmcfg::ops {

// Main state number (state var high byte) -> name; "" when the seed names none.
std::string state_name(unsigned main_state);
// Names of the set bits of the status / warn word.
std::vector<std::string> status_word_bits(std::uint16_t w);
std::vector<std::string> warn_word_bits(std::uint16_t w);

struct ErrorLogLine {
  std::uint16_t code = 0;
  std::uint32_t millis = 0;
  std::uint32_t hours = 0;
  std::string text;  // database text, else the drive's own (§14.2)
};

struct DriveInfo {
  codec::DefaultResponse response;
  std::string actual_error;
  codec::ErrorCounters counters;
  std::vector<ErrorLogLine> log;
};

// The drive's error state, read after a refused request: a refusal can put
// MC into its error state (LinRS §15 Error Detection Mask). State var
// (MC SW §3: main state 4 = Error State), status word bits 3 Error and 12
// Fatal Error (§3.23), the actual error text (LinRS §14.1). Reads only.
struct ErrorState {
  std::optional<std::uint16_t> state_var;
  std::optional<std::uint16_t> status_word;
  std::string actual_error;  // "" when the drive reports none
  bool in_error() const;
};
Result<ErrorState> read_error_state(client::Client& c);
// "drive state: 4 Error State (state var 0401h), status word 0008h (Error); actual error: Motor
// Hot"
std::string render_error_state(const ErrorState& s);

// Reads at most `max_log` newest error log entries.
Result<DriveInfo> read_drive_info(client::Client& c, const db::Database& db,
                                  std::size_t max_log = 8);
std::string render_info(const DriveInfo& i);
// The same as one JSON object (docs/json-reports.md "info").
std::string render_info_json(const DriveInfo& i);

}  // namespace lmcfg::ops
