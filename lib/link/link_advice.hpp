#pragma once
// Errors that say what to do (docs/reliability.md): when a drive command fails on
// the link before the drive ever answered, the usual cause is a link setting
// (--baud, --id, --checksum, --parity), not the line. link_advice() probes the
// session's port quickly (link::scan at the current rate: this MACID with every
// checksum variant, then every MACID) and names the likely cause and the
// option to change or the `lmcfg scan` to run.
#include <optional>
#include <string>

#include "common/result.hpp"
#include "link/session.hpp"

namespace lmcfg::link {

// True when `e` is a failure of the link (no answer, garbled or misframed
// answers) and the client never received a valid answer in this session.
bool settings_suspect(Session& session, const Error& e);

// The advice for a settings_suspect() failure, e.g. "no answer from MACID 12h
// at 57600 Bd, but a drive answers as MACID 11h: try --id 0x11". `port` is the
// --port text for the `lmcfg scan` suggestion. nullopt when the probe itself
// failed (the caller keeps the original message).
std::optional<std::string> link_advice(Session& session, const std::string& port);

}  // namespace lmcfg::link
