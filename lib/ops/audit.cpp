#include "ops/audit.hpp"

namespace lmcfg::ops {

namespace {

std::string one_line(std::string s) {
  for (char& c : s) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  return s;
}

}  // namespace

std::string trailers(const Audit& a) {
  std::string out;
  if (!a.who.empty()) out += "Operator: " + one_line(a.who) + "\n";
  if (!a.reason.empty()) out += "Reason: " + one_line(a.reason) + "\n";
  if (!a.ticket.empty()) out += "Ticket: " + one_line(a.ticket) + "\n";
  return out;
}

}  // namespace lmcfg::ops
