#pragma once
// Progress of a long library operation (a backup's reads, a scan's passes),
// reported to whoever draws it: the tools on a terminal, the service's jobs.
#include <cstddef>
#include <functional>
#include <string>

namespace lmcfg {

// Phase name, items done, items expected (0 = unknown).
using Progress = std::function<void(const std::string& phase, std::size_t done, std::size_t total)>;

}  // namespace lmcfg
