#include "link/link_advice.hpp"

#include <cstdio>

#include "common/bytes.hpp"
#include "link/scan.hpp"

namespace lmcfg::link {

bool settings_suspect(Session& session, const Error& e) {
  // Answers lost or garbled, never one received: the settings may be wrong.
  return e.code == ErrorClass::bad_answer && session.client().stats().answers == 0;
}

std::optional<std::string> link_advice(Session& session, const std::string& port) {
  // LinRS settings advice; a LinUDP client's own message says what to check.
  if (session.spec().port.scheme && session.spec().port.protocol() == Protocol::linudp)
    return std::nullopt;
  const std::uint8_t id = session.client().options().id;
  const codec::ChecksumConfig chk = session.client().options().checksum;
  const transport::SerialSettings line = session.line();
  const std::string at = " at " + std::to_string(line.baud) + " Bd";
  const std::string scan_hint = "run `lmcfg scan --port " + port + "`";
  ScanOptions so;
  so.bauds = {line.baud};
  so.first_id = so.last_id = id;
  so.checksum = chk;
  so.try_parities = false;  // a pty cannot change parity; parity is named in the advice
  auto mine = scan(session, so);
  if (!mine.ok()) return std::nullopt;
  for (const auto& f : mine->found) {
    if (f.checksum == chk) continue;
    return "answers fail their checksum: the drive seems to use checksum " +
           checksum_name(f.checksum) + ": try " + checksum_options(f.checksum);
  }
  std::size_t garbled = 0;
  for (const auto& p : mine->passes) garbled += p.unexplained_bytes;
  if (garbled > 0) {
    return "the drive's answers" + at + " arrive garbled: check --parity and --stop-bits " +
           "(factory setting 8N1) and --baud, or " + scan_hint;
  }
  // Silent at this MACID: is any drive on this line at this rate?
  so.first_id = 0;
  so.last_id = 255;
  auto all = scan(session, so);
  if (all.ok() && !all->found.empty()) {
    const FoundDrive* f = &all->found.front();
    for (const auto& g : all->found)
      if (g.id == id) f = &g;
    if (f->id == id) {
      return "answers fail their checksum: the drive seems to use checksum " +
             checksum_name(f->checksum) + ": try " + checksum_options(f->checksum);
    }
    std::string s = "no answer from MACID " + hex(id, 2, "h") + at +
                    ", but a drive answers as MACID " + hex(f->id, 2, "h") + ": try --id " + "0x" +
                    hex(f->id, 2);
    if (!(f->checksum == chk)) s += " " + checksum_options(f->checksum);
    return s;
  }
  if (all.ok()) {
    std::size_t heard = 0;
    for (const auto& p : all->passes) heard += p.unexplained_bytes;
    if (heard > 0)
      return "the line" + at +
             " carries bytes no setting explains: check --baud, --parity and "
             "--stop-bits, or " +
             scan_hint;
  }
  // A raw TCP gateway (tcp://) runs its serial side at the rate it was
  // configured with: --baud does not reach the line, and a scan through it
  // tries MACIDs at that one rate. RFC 2217 gateways take the rate from us.
  if (session.client().link().byte_time_us() <= 0.0) {
    return "no answer from MACID " + hex(id, 2, "h") +
           " through the gateway: check --id, and the gateway's serial settings (a tcp:// "
           "gateway sets the line rate itself; --baud does not reach it: use rfc2217://HOST:PORT "
           "if it speaks RFC 2217), or " +
           scan_hint + " to try every MACID at the gateway's rate";
  }
  return "no answer from MACID " + hex(id, 2, "h") + at + ": check --id and --baud (and " +
         "--parity), or " + scan_hint + " to try every MACID and rate";
}

}  // namespace lmcfg::link
