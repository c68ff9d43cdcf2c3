// lmcfg scan: find drives whose link settings are unknown (link::scan).
#include <cstdio>

#include "command.hpp"
#include "link/linudp_scan.hpp"
#include "link/port.hpp"
#include "link/scan.hpp"
#include "link_options.hpp"
#include "ops/drive_info.hpp"
#include "report/json_reports.hpp"
#include "transport/ports.hpp"
#include "transport/udp.hpp"

namespace lmcfg::cli {
namespace {

struct ScanCli {
  CommonOptions common;
  std::string from = "0";
  std::string to = "0xFF";
  bool baud_given = false, timeout_given = false, ids_given = false, retries_given = false;
};

// "state 8 Operation Enabled (state var 08C2h), status word 4C37h, error 0000h, firmware 0606h"
std::string linudp_drive_line(const link::LinudpScanned& d) {
  char buf[64];
  std::string out;
  if (d.state_var) {
    const unsigned main = *d.state_var >> 8;
    const std::string name = ops::state_name(main);
    std::snprintf(buf, sizeof buf, " (state var %04Xh)", *d.state_var);
    out += "state " + std::to_string(main) + (name.empty() ? "" : " " + name) + buf;
  }
  auto word = [&](const char* what, std::optional<std::uint16_t> v) {
    if (!v) return;
    std::snprintf(buf, sizeof buf, "%s%s %04Xh", out.empty() ? "" : ", ", what, *v);
    out += buf;
  };
  word("status word", d.status_word);
  word("error", d.error_code);
  if (d.firmware) {
    std::snprintf(buf, sizeof buf, ", firmware %04Xh", static_cast<unsigned>(*d.firmware));
    out += buf;
  } else {
    out += ", " + d.firmware_note;
  }
  return out;
}

// A LinUDP address range (link/linudp_scan.hpp): opt-in (the range is named
// in --port), at most link::kMaxScanAddresses addresses, a NOP and two RAM
// reads per drive, never a control word (docs/linudp.md "Scan").
int run_linudp(ScanCli& o) {
  if (o.ids_given || o.baud_given)
    return fail("scan", Error(Errc::invalid_argument,
                              "--from/--to and --baud name MACIDs and rates of a LinRS line; a "
                              "LinUDP scan takes its addresses from --port linudp://RANGE"));
  const std::string address = o.common.port.substr(std::string("linudp://").size());
  auto range = link::parse_linudp_range(address);
  if (!range.ok()) return fail("scan", range.error());
  link::LinudpScanOptions so;
  if (o.timeout_given) so.deadline = std::chrono::milliseconds(o.common.timeout_ms);
  if (o.retries_given) so.attempts = 1 + std::max(0, o.common.retries);
  ProgressBar bar(o.common);
  so.progress = bar.callback();
  auto scanned = link::scan_linudp(
      *range,
      [](const std::string& host, std::uint16_t port) { return transport::open_udp(host, port); },
      so);
  bar.end();
  if (!scanned.ok()) return fail("scan", scanned.error());
  const auto& r = *scanned;
  const std::size_t answered = r.count(link::LinudpAnswer::answered);
  const std::size_t held = r.count(link::LinudpAnswer::held);
  if (o.common.json) {
    std::printf("%s\n", report::linudp_scan_json(r).dump(2).c_str());
  } else {
    for (const auto& d : r.addresses) {
      const std::string at = d.host + ":" + std::to_string(r.port);
      if (d.answer == link::LinudpAnswer::answered)
        std::printf("drive at %s: %s; link options: --port linudp://%s\n", at.c_str(),
                    linudp_drive_line(d).c_str(), at.c_str());
      else if (d.answer == link::LinudpAnswer::held)
        std::printf("drive at %s: held by another master (all-zero replies, LinUDP V2 §5)\n",
                    at.c_str());
    }
    std::printf("%zu address(es) probed: %zu answered, %zu held by another master, %zu silent\n",
                r.addresses.size(), answered, held, r.count(link::LinudpAnswer::silent));
  }
  if (!o.common.quiet && !o.common.json) {
    std::fprintf(stderr, "lmcfg scan: %zu address(es), %llu datagrams, %.2f s\n",
                 r.addresses.size(), static_cast<unsigned long long>(r.datagrams), r.seconds);
  }
  return answered + held > 0 ? kOk : kDifferent;  // 1: nothing answered
}

int run(ScanCli& o) {
  auto first = parse_number(o.from, false);
  auto last = parse_number(o.to, false);
  if (!first || !last || *first > 0xFF || *last > 0xFF || *first > *last) {
    return fail("scan",
                Error(Errc::invalid_argument, "--from/--to must be MACIDs 0..255 with from <= to"));
  }
  if (link::scheme_of(o.common.port).protocol == link::Protocol::linudp) return run_linudp(o);
  auto lo = link_options(o.common);
  if (!lo.ok()) return fail("scan", lo.error());
  link::ScanOptions so;
  so.first_id = static_cast<unsigned>(*first);
  so.last_id = static_cast<unsigned>(*last);
  so.checksum = lo->client.checksum;
  if (o.baud_given) so.bauds = {o.common.baud};
  if (o.timeout_given) so.deadline = transport::Millis(o.common.timeout_ms);
  ProgressBar bar(o.common);
  so.progress = bar.callback();
  // One probe per ID: the scan's spec has no read retries.
  CommonOptions once = o.common;
  once.retries = 0;
  auto spec = link_options(once);
  if (!spec.ok()) return fail("scan", spec.error());
  auto session = link::open_session(*spec);
  if (!session.ok()) return fail("scan", session.error());
  auto scanned = link::scan(**session, so);
  bar.end();
  if (!scanned.ok()) return fail("scan", scanned.error());
  if (auto closed = (*session)->close(); !closed.ok()) return fail("scan", closed.error());
  const auto& r = *scanned;
  if (o.common.json) {
    std::printf("%s\n", report::scan_json(r).dump(2).c_str());
  } else {
    for (const auto& d : r.found) {
      std::printf("drive at MACID 0x%02X (%u), %s, checksum %s: %s\n", d.id, d.id,
                  transport::format_settings(d.line).c_str(),
                  link::checksum_name(d.checksum).c_str(), link::link_options_of(d).c_str());
    }
    for (const auto& n : r.notes) std::printf("note: %s\n", n.c_str());
    if (r.found.empty()) {
      std::printf("no drive answered (%zu setting(s), MACIDs 0x%02X..0x%02X, %.1f s)\n",
                  r.passes.size(), so.first_id, so.last_id, r.seconds);
    }
  }
  if (!o.common.quiet && !o.common.json) {
    std::fprintf(stderr, "lmcfg scan: %zu pass(es), %llu telegrams, %.2f s\n", r.passes.size(),
                 static_cast<unsigned long long>(r.telegrams), r.seconds);
  }
  return r.found.empty() ? kDifferent : kOk;  // 1: no drive answered
}

// Without --port: every serial port of this computer in turn
// (transport::list_serial_ports), each named before its results. Exit 0 when
// a drive answered on any, 1 when none did, else the first port's error.
int run_all_ports(ScanCli& o) {
  const auto ports = transport::list_serial_ports();
  if (ports.empty())
    return fail("scan", Error(Errc::invalid_argument,
                              "no --port given and no serial port found on this computer; plug "
                              "in the adapter or name the port with --port"));
  if (o.common.json && ports.size() > 1)
    return fail("scan",
                Error(Errc::invalid_argument, "--json needs --port: this computer has " +
                                                  std::to_string(ports.size()) + " serial ports"));
  int result = kDifferent;
  for (const auto& port : ports) {
    if (!o.common.json) std::printf("port %s:\n", port.c_str());
    std::fflush(stdout);
    o.common.port = port;
    const int rc = run(o);
    if (rc == kOk) result = kOk;
    if (rc != kOk && rc != kDifferent && result == kDifferent) result = rc;
  }
  return result;
}

}  // namespace

void add_scan(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<ScanCli>();
  auto* sub = app.add_subcommand("scan",
                                 "Find drives: tries MACIDs at every LinRS baud rate (or --baud), "
                                 "detects checksum and parity");
  sub->footer(
      "Without --baud every rate of seed 003 §3.2.1 is tried, factory 57600 first; answers "
      "framed with another checksum are detected and confirmed. Prints the link options of "
      "each drive found; exit 1 when none answered. Without --port every serial port of this "
      "computer is scanned in turn (Linux: /dev/serial/by-id, else /dev/ttyUSB* and "
      "/dev/ttyACM*; Windows: the COM ports). LinUDP drives only when named: --port "
      "linudp://10.8.7.0/24, linudp://10.8.7.1-40 or linudp://A.B.C.D-A.B.C.E[:PORT] (at most "
      "256 addresses; a NOP and two RAM reads each, never a control word; --timeout-ms per "
      "address, default 200; docs/linudp.md).\n"
      "Examples:\n  lmcfg scan --port /dev/ttyUSB0\n"
      "  lmcfg scan --port linudp://10.8.7.0/24\n"
      "  lmcfg scan --port /dev/ttyUSB0 --baud 115200 --from 1 --to 0x20 --json");
  add_link_options(sub, o->common);
  add_output_options(sub, o->common);
  sub->add_option("--from", o->from, "first MACID")->capture_default_str();
  sub->add_option("--to", o->to, "last MACID")->capture_default_str();
  sub->callback([o, sub, &exit_code] {
    o->baud_given = sub->get_option("--baud")->count() > 0;
    o->timeout_given = sub->get_option("--timeout-ms")->count() > 0;
    o->retries_given = sub->get_option("--retries")->count() > 0;
    o->ids_given = sub->get_option("--from")->count() + sub->get_option("--to")->count() > 0;
    exit_code = o->common.port.empty() ? run_all_ports(*o) : run(*o);
  });
}
}  // namespace lmcfg::cli
