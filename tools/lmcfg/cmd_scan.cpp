// lmcfg scan: find drives whose link settings are unknown (link::scan).
#include <cstdio>

#include "command.hpp"
#include "link/port.hpp"
#include "link/scan.hpp"
#include "link_options.hpp"
#include "report/json_reports.hpp"
#include "transport/ports.hpp"

namespace lmcfg::cli {
namespace {

struct ScanCli {
  CommonOptions common;
  std::string from = "0";
  std::string to = "0xFF";
  bool baud_given = false, timeout_given = false;
};

int run(ScanCli& o) {
  auto first = parse_number(o.from, false);
  auto last = parse_number(o.to, false);
  if (!first || !last || *first > 0xFF || *last > 0xFF || *first > *last) {
    return fail("scan",
                Error(Errc::invalid_argument, "--from/--to must be MACIDs 0..255 with from <= to"));
  }
  if (link::scheme_of(o.common.port).protocol == link::Protocol::linudp)
    return fail("scan", Error(Errc::not_supported,
                              "--port " + o.common.port +
                                  ": lmcfg scan finds LinRS drives on a serial line; a LinUDP "
                                  "drive is named by its address (docs/linudp.md)"));
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
      "/dev/ttyACM*; Windows: the COM ports).\n"
      "Examples:\n  lmcfg scan --port /dev/ttyUSB0\n"
      "  lmcfg scan --port /dev/ttyUSB0 --baud 115200 --from 1 --to 0x20 --json");
  add_link_options(sub, o->common);
  add_output_options(sub, o->common);
  sub->add_option("--from", o->from, "first MACID")->capture_default_str();
  sub->add_option("--to", o->to, "last MACID")->capture_default_str();
  sub->callback([o, sub, &exit_code] {
    o->baud_given = sub->get_option("--baud")->count() > 0;
    o->timeout_given = sub->get_option("--timeout-ms")->count() > 0;
    exit_code = o->common.port.empty() ? run_all_ports(*o) : run(*o);
  });
}
}  // namespace lmcfg::cli
