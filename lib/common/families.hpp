#pragma once
// Drive families that speak LinRS, and what each has: the one table every part
// of lmcfg (backup, restore plan, the simulator, the CLI) consults. Sources:
// LinRS 3V27 §11-§12, p26, p32; LinRS 3.23 p53; DCF p8;
// the C1250 notes; seed 003 for E1100. The seeds' drive is E1100: a drive
// whose family nobody names is taken for one.
#include <string>
#include <string_view>
#include <vector>

#include "common/result.hpp"

namespace lmcfg::families {

struct Family {
  std::string_view name;     // "E1100", "B1100", "C1100", "E1200", "E1400"
  std::string_view profile;  // upid-db profile whose names label its values
  // LinRS §11 curve group / §12 command table group over LinRS. B1100: "not on
  // B1100" (3V27 §11-§12).
  bool curves = true;
  bool command_table = true;
  // RAM -> flash save of curves and CT (§11 00h, §12 00h). C1100: add and
  // delete act on flash directly, "save to flash" has no function (3V27 p32).
  bool flash_save = true;
  // Default values stored on the drive (§10 get default 05h/07h, defaulting a
  // layer 05h/0Ch-0Fh). B1100: "defaults are not stored on the drive" (DCF p8).
  bool stored_defaults = true;
  // Curve storage limit (C1250 notes: "B1100 16, A1100/C1100 50, others 100").
  unsigned curve_limit = 100;
  std::string_view macid;   // where the MACID lives, for people
  std::string_view source;  // where the row comes from
};

// The table, E1100 first.
const std::vector<Family>& all();
// The seeds' family (E1100): what a drive nobody names is taken for.
const Family& reference();
// Case-insensitive by name ("e1100", "E1400"); nullptr when unknown.
const Family* find(std::string_view name);
// "E1100, B1100, C1100, E1200, E1400": for messages listing what is known.
std::string names();
// A family named by a user (--family, the inventory's `family`): "" is not
// named (nullptr); an unknown name is Errc::invalid_argument naming the known
// ones. `where` says where the name came from ("--family", "inventory.toml:12").
Result<const Family*> parse(std::string_view name, std::string_view where);

}  // namespace lmcfg::families
