#pragma once
// What `lmcfg fleet` and `lmcfg serve` share: the inventory, checked as every
// fleet command checks it, and each line's link settings (cmd_fleet.cpp).
#include <string>
#include <vector>

#include "fleet/inventory.hpp"
#include "link/session.hpp"
#include "link_options.hpp"
#include "ops/line.hpp"

namespace lmcfg::cli {

// The line's link settings, checked as the command-line options are
// (fleet::line_link_spec); a bad value is reported at the line's position in
// the inventory. check_only: the settings without the port (the caller
// checks ports with fleet::check_ports), each LinRS line's spec left empty.
// A CAN port's line gets DeviceNet options (--can-bitrate ... checked as the
// options are).
Result<std::vector<ops::LineLink>> line_links(const fleet::Inventory& inv,
                                              const CommonOptions& base,
                                              const std::atomic<bool>* cancel = nullptr,
                                              bool check_only = false);
// The inventory at `path` with every check of `fleet check` (keys, names,
// MACIDs, link settings, ports).
Result<fleet::Inventory> load_checked_inventory(const std::string& path, const CommonOptions& base);

}  // namespace lmcfg::cli
