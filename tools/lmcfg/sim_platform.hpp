#pragma once
// What `lmcfg sim` needs from the operating system (sim_platform.cpp: POSIX
// signals and poll; sim_platform_win32.cpp: the console's Ctrl handler): a
// stop request and the end of stdin. Pseudo-terminals are transport/pty.hpp's.
namespace lmcfg::cli {

// SIGINT/SIGTERM (Windows: Ctrl-C, Ctrl-Break, the console closing) set the
// stop request; a closed peer never kills the process (SIGPIPE ignored).
void install_sim_stop_handlers();
bool sim_stop_requested();
// True when stdin reached end of file (--until-stdin-eof); never waits.
bool stdin_at_eof();
// Whether `lmcfg sim` can serve on a pseudo-terminal here (not on Windows).
bool sim_has_pty();

}  // namespace lmcfg::cli
