#include "console.hpp"

namespace lmcfg::cli {

// A POSIX terminal takes the bytes as they are (the locale is the user's).
void init_console() {}

}  // namespace lmcfg::cli
