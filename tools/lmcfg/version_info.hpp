#pragma once
// `lmcfg --version`: the program version, the git revision it was built from
// (when known), and the UPID database it finds (path, fingerprint, profiles).
#include <string>

namespace lmcfg::cli {
std::string version_text();
}
