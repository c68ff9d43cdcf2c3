#pragma once
// The terminal lmcfg writes to, set up once at start: nothing to do on POSIX
// (console.cpp); on Windows (console_win32.cpp) the console's input and output
// code pages become UTF-8, the encoding of every text lmcfg prints.
namespace lmcfg::cli {

void init_console();

// True when the program was started with a console of its own that nobody
// else shares and that it writes to: on Windows, a double-click in Explorer
// (the console was made for this process alone), where `lmcfg` without
// arguments opens the page (lmcfg ui) instead of printing the usage into a
// window that closes at once. Never on POSIX.
bool started_by_double_click();

}  // namespace lmcfg::cli
