#pragma once
// Finding LinUDP V2 drives in an address range (`lmcfg scan --port
// linudp://RANGE`). LinUDP has no discovery message (linudp-facts.md §1.1,
// "facts"); the vendor DLL sweeps the subnet with a control-word telegram
// (control word 0000h to every drive, facts §1.1 "inferred: a backup tool must
// not copy it"). This scan is opt-in (the range is named), bounded
// (kMaxScanAddresses), and sends only the RTC part (request definition 04h,
// facts §1.4): to each address a NOP (00h, facts §2.2: it runs nothing
// whichever count the drive holds), and to a drive that answered, two RAM
// reads (11h) of the firmware version UPIDs 0034h/0035h (facts §2.4 "Firmware
// version is read as (RAM UPID 0034h << 8) + RAM UPID 0035h"). Reads change
// nothing; no control word, MC command or write is ever sent.
//
// One address at a time (one datagram in flight), each probe `deadline` long
// and sent at most `attempts` times (same count, facts §2.2), probes started
// at least `gap` apart (the DLL's 10 ms spacing, facts §1.1): at most 100
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

// One /24: the addresses the vendor DLL sweeps (facts §1.1, "every host
// address of the subnet").
inline constexpr std::size_t kMaxScanAddresses = 256;

struct LinudpRange {
  std::vector<std::string> hosts;  // dotted IPv4, in order (or one name)
  std::uint16_t port = 49360;      // facts §1.1 drive port
};
// The address part of `linudp://RANGE[:PORT]` (without the prefix): HOST,
// A.B.C.D/N (network and broadcast skipped for N <= 30), A.B.C.D-A.B.C.E or
// A.B.C.D-E (last octet). Errc::invalid_argument naming the problem; a range
// of more than kMaxScanAddresses addresses is refused with its size.
Result<LinudpRange> parse_linudp_range(const std::string& address);

enum class LinudpAnswer : std::uint8_t {
  answered,  // a reply with our count
  held,      // all-zero replies (facts §4 #6)
  silent,    // nothing within the deadline
};

struct LinudpScanned {
  std::string host;
  LinudpAnswer answer = LinudpAnswer::silent;
  // From the NOP's reply (response definition 1FFh, facts §1.3).
  std::optional<std::uint16_t> status_word, state_var, error_code;
  // (0034h << 8) + 0035h from RAM; nullopt with `firmware_note` saying why.
  std::optional<std::uint32_t> firmware;
  std::string firmware_note;
  double ms = 0;  // this address's time, gap included
  int datagrams = 0;
};

struct LinudpScanOptions {
  std::chrono::milliseconds deadline{200};  // facts §2.2: Go's 200 ms per attempt
  int attempts = 1;
  std::chrono::milliseconds gap{10};  // facts §1.1: the DLL's 10 ms between addresses
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
