#pragma once
// The terminal lmcfg writes to, set up once at start: nothing to do on POSIX
// (console.cpp); on Windows (console_win32.cpp) the console's input and output
// code pages become UTF-8, the encoding of every text lmcfg prints.
namespace lmcfg::cli {

void init_console();

}  // namespace lmcfg::cli
