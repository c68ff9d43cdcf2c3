#pragma once
// Finding drives whose link settings are unknown (lmcfg scan).
//
// One pass = one line setting (baud, parity, stop bits) and one checksum: a
// default response request (§6.1.2) to every MACID in the range, each with a
// deadline derived from the wire time at that rate plus the drive's turnaround
// (§6.1.1.1: < 1.5 ms), the adapter's latency timer and a scheduling margin:
// no settle wait, so a silent ID costs a few milliseconds at 115200. Answers
// are attributed by the MACID they carry, so an answer that arrives late still
// counts for its drive. Every byte received is kept: when a pass heard bytes it
// could not decode, they are decoded again with every other checksum variant
// (a drive set to CRC answers a telegram without checksum with C2 "end of
// telegram missing" or C1, framed with its own checksum), and a variant that
// explains them is confirmed with one more request. Where no variant explains
// them on a serial line, the pass is repeated with even and odd parity.
#include <optional>
#include <string>
#include <vector>

#include "common/progress.hpp"
#include "link/session.hpp"

namespace lmcfg::link {

struct ScanOptions {
  // Rates to try, in this order; empty = scan_rates() (every §3.2.1 rate,
  // factory 57600 first). A TCP gateway is scanned at its own rate only.
  std::vector<unsigned> bauds;
  unsigned first_id = 0;
  unsigned last_id = 255;
  codec::ChecksumConfig checksum;  // the probes' checksum
  bool try_checksums = true;       // decode unexplained answers with every variant
  bool try_parities = true;        // repeat a garbled pass with even/odd parity (serial)
  // Per-ID deadline; nullopt = computed (id_deadline).
  std::optional<transport::Millis> deadline;
  double turnaround_ms = 1.5;  // §6.1.1.1 upper bound of the default response
  double margin_ms = 4.0;      // scheduling slack on a loaded host
  Progress progress;
};

struct FoundDrive {
  std::uint8_t id = 0;
  transport::SerialSettings line;  // device left empty
  codec::ChecksumConfig checksum;
  std::size_t response_bytes = 0;  // data bytes of its default response
  std::string how;                 // "answered", or how the settings were found
};
// "--baud 115200 --id 0x2A --checksum none" (+ --parity / --stop-bits /
// --checksum-coverage when they are not the defaults).
std::string link_options_of(const FoundDrive& d);

struct ScanPass {
  transport::SerialSettings line;
  codec::ChecksumConfig checksum;
  unsigned ids = 0;
  double deadline_ms = 0;
  double seconds = 0;
  std::size_t unexplained_bytes = 0;  // received bytes no telegram of this pass explained
};

struct ScanReport {
  std::vector<FoundDrive> found;
  std::vector<ScanPass> passes;
  std::vector<std::string> notes;  // e.g. "tcp gateway: scanned at its own rate only"
  double seconds = 0;
  std::uint64_t telegrams = 0;
};

// 57600 (factory, §15), then 115200, 38400, 19200, 9600, 4800.
std::vector<unsigned> scan_rates();
// Per-ID deadline: (request bytes + 1) byte times + turnaround + latency + margin.
double id_deadline_ms(const transport::SerialSettings& line, const codec::ChecksumConfig& c,
                      double latency_ms, const ScanOptions& o);
// Every checksum variant (none; add, crc-ffff, crc-0000, crc-kermit x id/start/data).
std::vector<codec::ChecksumConfig> checksum_variants();

// Scans through the session's link; leaves the session on its last setting.
// Errors: only link failures (closed, I/O); a silent line is a report with no drive.
Result<ScanReport> scan(Session& session, const ScanOptions& o);

}  // namespace lmcfg::link
