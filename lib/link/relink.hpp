#pragma once
// Finding the drive again after its LinRS settings changed (README,
// `restore --include-comm`). The drive chooses its MACID and baud rate at
// start-up (LinRS §3.2, §15): from hex switches S2/S1, or "By Parameter"
// from MACID Parameter Value 2076h / Baud Rate Parameter Def 2012h. A restore
// that writes those parameters and resets the drive can leave it talking with
// other settings than the ones the tool opened the link with.
//
// expected_link() (ops/expected_link.hpp) reads what the restored ROM values
// select, as far as the database can tell; everything it cannot tell stays
// unknown. reconnect() then
// tries candidate settings in a fixed order, one cheap read (the default
// response request, LinRS §8) each, and keeps the first the drive answers.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "codec/frame.hpp"
#include "link/session.hpp"

namespace lmcfg::link {

// What the restored parameters select after the reset. nullopt = the tool
// cannot tell (hex switch settings, a code the database has no label for, no
// database); `reasons` says how each known value was derived, or why not, in
// the order shown; `macid_reason` and `baud_reason` are the ones of each
// setting among them (for a message about one of them).
struct ExpectedLink {
  std::optional<unsigned> baud;
  std::optional<std::uint8_t> macid;
  std::vector<std::string> reasons;
  std::string macid_reason, baud_reason;
};

// Settings the user names for after the restore (--reconnect-baud/-id/-checksum);
// they are tried first.
struct RelinkOverrides {
  std::optional<unsigned> baud;
  std::optional<std::uint8_t> macid;
  std::optional<codec::ChecksumConfig> checksum;
  // Parity and stop bits the drive takes at its reset (`lmcfg link`); tried
  // before the line's own.
  std::optional<transport::Parity> parity;
  std::optional<unsigned> stop_bits;
};

struct RelinkCandidate {
  transport::SerialSettings line;
  std::uint8_t macid = 0;
  codec::ChecksumConfig checksum;
};
// "--baud 115200 --id 0x11 --checksum crc-ffff" (+ parity, stop bits, coverage
// when not the defaults): the link options of `c`.
std::string link_options_of(const RelinkCandidate& c);

// In the order they are tried: overrides, then the expected values, then the
// settings in use; for an unknown baud rate every rate of LinRS §3.2.1 after
// those. Parity and stop bits stay as they are unless the overrides name them
// (their UPIDs are not in the seeds): then those first, the line's after.
std::vector<RelinkCandidate> relink_candidates(const ExpectedLink& expected,
                                               const RelinkOverrides& overrides,
                                               const transport::SerialSettings& line,
                                               std::uint8_t macid,
                                               const codec::ChecksumConfig& checksum);

struct RelinkReport {
  bool changed = false;  // the drive answered with other settings than before
  RelinkCandidate used;
  std::size_t attempts = 0;
  std::string summary;  // "the drive answers at 38400 Bd, MACID 22h, checksum none"
  std::vector<std::string> reasons;
};

// Tries the candidates on `session`; on success the session keeps the settings
// that worked. Errc::timeout, naming every setting tried, when none answers
// (the session is then back at its original settings). Candidates a link
// cannot take (another baud rate on a TCP gateway) are skipped and named.
// reconnect, repeated while no setting is answered until `budget` of link
// time has passed since the call: a drive may stay silent for 30-90 s after
// ROM writes (field reports, C1250 notes), longer than its reset's answer deadline.
// A round that took no link time (no setting could be tried) is final.
Result<RelinkReport> reconnect_within(Session& session, const ExpectedLink& expected,
                                      const RelinkOverrides& overrides, transport::Millis budget);
Result<RelinkReport> reconnect(Session& session, const ExpectedLink& expected,
                               const RelinkOverrides& overrides);

}  // namespace lmcfg::link
