#include "ops/audit.hpp"

#include "common/text.hpp"

namespace lmcfg::ops {

std::string trailers(const Audit& a) {
  std::string out;
  if (!a.who.empty()) out += "Operator: " + one_line(a.who) + "\n";
  if (!a.reason.empty()) out += "Reason: " + one_line(a.reason) + "\n";
  if (!a.ticket.empty()) out += "Ticket: " + one_line(a.ticket) + "\n";
  return out;
}

}  // namespace lmcfg::ops
