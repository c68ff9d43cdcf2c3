#pragma once
// Who wrote to a drive and why: recorded with every write (restore, default,
// set, fleet restore, the service), as git trailers of the archive's commit
// where there is an archive.
#include <string>

namespace lmcfg::ops {

struct Audit {
  std::string who;     // the OS user, or the API token's name
  std::string reason;  // free text (--reason, the API's "reason")
  std::string ticket;  // a ticket id (--ticket, the API's "ticket")
};

// The trailers block "Operator: who\nReason: ...\nTicket: ...\n", empty fields
// left out; "" when all are empty. git interpret-trailers reads a trailer as
// "Key: value" on its own line of the last paragraph, a line that begins with
// whitespace continuing it: each field is made one line of valid UTF-8
// (common/text.hpp one_line: control characters, line breaks among them,
// become spaces, invalid bytes "\xNN"), so no value can start a line that
// reads as another trailer. The service checks them first (check_line).
std::string trailers(const Audit& a);

// The OS user running this program: the name of the effective uid
// (getpwuid), else $USER, else the uid as a number.
std::string current_user();

}  // namespace lmcfg::ops
