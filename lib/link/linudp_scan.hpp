#pragma once
// Finding LinUDP V2 drives in an address range (`lmcfg scan --port
// linudp://RANGE`). LinUDP V2 has no discovery message; the LinUDP DLL sweeps
// the subnet with a control-word telegram (control word 0000h to every drive,
// which, in our reading, a backup tool must not copy). This scan is opt-in
// (the range is named), bounded
// (kMaxScanAddresses), and sends only the RTC part (request definition 04h,
// LinUDP V2 §4.4.1): to each address a NOP (00h, LinUDP V2 §7: it runs nothing
// whichever count the drive holds), and to a drive that answered, two RAM
// reads (11h) of the firmware version UPIDs 0034h/0035h (the LinUDP DLL reads
// the version as (RAM UPID 0034h << 8) + RAM UPID 0035h). Reads change
// nothing; no control word, MC command or write is ever sent.
//
// One address at a time (one datagram in flight), each probe `deadline` long
// and sent at most `attempts` times (same count, LinUDP V2 §7), probes started
// at least `gap` apart (the LinUDP DLL's 10 ms spacing): at most 100
// datagrams a second.
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/progress.hpp"
#include "common/result.hpp"
#include "transport/transport.hpp"

namespace lmcfg::link {

// One /24: the addresses the vendor DLL sweeps (LinUDP DLL: every host
// address of the subnet).
inline constexpr std::size_t kMaxScanAddresses = 256;

struct LinudpRange {
  std::vector<std::string> hosts;  // dotted IPv4, in order (or one name)
  std::uint16_t port = 49360;      // LinUDP V2 §4.3 drive port
};
// The address part of `linudp://RANGE[:PORT]` (without the prefix): HOST,
// A.B.C.D/N (network and broadcast skipped for N <= 30), A.B.C.D-A.B.C.E or
// A.B.C.D-E (last octet). Errc::invalid_argument naming the problem; a range
// of more than kMaxScanAddresses addresses is refused with its size.
Result<LinudpRange> parse_linudp_range(const std::string& address);

enum class LinudpAnswer : std::uint8_t {
  answered,  // a reply with our count
  held,      // all-zero replies (C1250 notes)
  silent,    // nothing within the deadline
};

struct LinudpScanned {
  std::string host;
  LinudpAnswer answer = LinudpAnswer::silent;
  // From the NOP's reply (response definition 1FFh, LinUDP V2 §4.4.2).
  std::optional<std::uint16_t> status_word, state_var, error_code;
  // (0034h << 8) + 0035h from RAM; nullopt with `firmware_note` saying why.
  std::optional<std::uint32_t> firmware;
  std::string firmware_note;
  double ms = 0;  // this address's time, gap included
  int datagrams = 0;
};

struct LinudpScanOptions {
  std::chrono::milliseconds deadline{200};  // C1250 notes: 200 ms per attempt
  int attempts = 1;
  std::chrono::milliseconds gap{10};  // LinUDP DLL: 10 ms between addresses
  Progress progress;
};

struct LinudpScanReport {
  std::uint16_t port = 49360;
  std::vector<LinudpScanned> addresses;  // every address probed, in order
  double seconds = 0;
  std::uint64_t datagrams = 0;
  std::size_t count(LinudpAnswer a) const;
};

// Opens a datagram link to host:port (production: transport::open_udp).
using UdpOpener = std::function<Result<std::unique_ptr<transport::Transport>>(
    const std::string& host, std::uint16_t port)>;

// Errors: only a link that cannot be opened (a silent address is a report line).
Result<LinudpScanReport> scan_linudp(const LinudpRange& range, const UdpOpener& open,
                                     const LinudpScanOptions& o);

}  // namespace lmcfg::link
