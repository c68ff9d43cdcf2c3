#pragma once
// One confirmation for every command that changes a drive (`restore`,
// `default`): with `yes` go on; on a terminal ask `question` on stderr and read
// the answer from stdin; without a terminal refuse (Errc::invalid_argument,
// exit 2) so a script never writes to a drive it did not mean to.
#include <string>

#include "common/result.hpp"

namespace lmcfg::ops {

enum class Consent { go, declined };

// `action`: "default a drive", "restore FILE onto the drive" (for the refusal).
Result<Consent> confirm(const std::string& question, const std::string& action, bool yes);

}  // namespace lmcfg::ops
