#pragma once
// One confirmation for every command that changes a drive (`restore`,
// `default`, `link`): with `yes` go on; on a terminal ask `question` on stderr
// and read the answer from stdin; without a terminal refuse
// (Errc::invalid_argument, exit 2) so a script never writes to a drive it did
// not mean to. Terminal I/O, so it lives in the tool, not in the library.
#include <string>

#include "common/result.hpp"
#include "ops/confirm.hpp"

namespace lmcfg::cli {

// `action`: "default a drive", "restore FILE onto the drive" (for the refusal).
Result<ops::Consent> confirm(const std::string& question, const std::string& action, bool yes);

}  // namespace lmcfg::cli
