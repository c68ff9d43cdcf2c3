#pragma once
// What `lmcfg fleet` and `lmcfg serve` share: the inventory, checked as every
// fleet command checks it, and each line's link settings (cmd_fleet.cpp).
#include <string>
#include <vector>

#include "fleet/inventory.hpp"
#include "link_options.hpp"
#include "ops/line.hpp"
#include "link/session.hpp"

namespace lmcfg::cli {

// The line's link settings, checked as the command-line options are; a bad
// value is reported at the line's position in the inventory.
// A CAN port's line gets DeviceNet options (--can-bitrate ... checked as the
// options are).
Result<std::vector<ops::LineLink>> line_links(const fleet::Inventory& inv,
                                              const CommonOptions& base);
// The inventory at `path` with every check of `fleet check` (keys, names,
// MACIDs, link settings, ports).
Result<fleet::Inventory> load_checked_inventory(const std::string& path, const CommonOptions& base);

}  // namespace lmcfg::cli
