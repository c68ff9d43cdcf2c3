#include "console.hpp"

namespace lmcfg::cli {

// A POSIX terminal takes the bytes as they are (the locale is the user's).
void init_console() {}

// A desktop starts a program without arguments in a terminal of its own only
// when told to; the usage is what `lmcfg` alone prints there.
bool started_by_double_click() { return false; }

}  // namespace lmcfg::cli
