#include "common/families.hpp"

#include "common/bytes.hpp"

namespace lmcfg::families {

namespace {
// The MACID of a LinRS drive (seed 003 §10.2 example; LinRS 3.23 p8: MACID
// source 206Ch, value 2076h, or the hex switches S1/S2, S1 the high nibble).
constexpr std::string_view kLinRsMacid =
    "LinRS: MACID Source Select 206Ch (hex switches S1/S2 or parameter), MACID Parameter Value "
    "2076h";

const std::vector<Family> kFamilies = {
    {"E1100", "e1100-mc-linrs", true, true, true, true, 100, kLinRsMacid,
     "seed 003 (LinRS V3.6), seed 001; curve limit: C1250 notes"},
    // 3V27 §11-§12 "not on B1100"; 3.23 p53 MACID; DCF p8 defaults; C1250 notes 16 curves.
    {"B1100", "b1100-mc", false, false, false, false, 16,
     "OS\\Communication\\MACID: from the digital inputs, source select and value (value UPID "
     "6081h, offset modes \"+ Offset\")",
     "LinRS 3V27 §11-§12, p26; LinRS 3.23 p53; DCF p8; C1250 notes"},
    {"C1100", "c1100-mc-linrs", true, true, false, true, 50, kLinRsMacid,
     "LinRS 3V27 p5, p32; C1250 notes"},
    {"E1200", "e1200-mc-linrs", true, true, true, true, 100, kLinRsMacid,
     "LinRS 3.16b and later; C1250 notes"},
    {"E1400", "e1200-mc-linrs", true, true, true, true, 100, kLinRsMacid,
     "LinRS 3.16b and later; C1250 notes"},
};

}  // namespace

const std::vector<Family>& all() { return kFamilies; }
const Family& reference() { return kFamilies.front(); }

const Family* find(std::string_view name) {
  for (const auto& f : kFamilies)
    if (iequals(f.name, name)) return &f;
  return nullptr;
}

std::string names() {
  std::string s;
  for (const auto& f : kFamilies) s += (s.empty() ? "" : ", ") + std::string(f.name);
  return s;
}

Result<const Family*> parse(std::string_view name, std::string_view where) {
  if (name.empty()) return static_cast<const Family*>(nullptr);
  if (const Family* f = find(name)) return f;
  return Error(Errc::invalid_argument, std::string(where) + ": unknown drive family '" +
                                           std::string(name) + "'; expected one of " + names() +
                                           " (docs/families.md)");
}

}  // namespace lmcfg::families
