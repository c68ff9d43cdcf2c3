#pragma once
// SIGINT/SIGTERM during a command that writes to a drive (docs/restore.md): the
// handler only sets a flag (std::atomic<bool>, lock-free, async-signal-safe);
// the client checks it before each telegram (ClientOptions::cancel), so the
// telegram in flight completes and no half telegram is ever left on the line.
// The operation then fails with Errc::interrupted and names the step reached;
// the tool exits 130.
#include <atomic>

namespace lmcfg::ops {

// The process-wide flag the handlers set.
std::atomic<bool>& interrupt_flag();

// Installs SIGINT and SIGTERM handlers that set interrupt_flag(). A second
// signal more than a second after the first ends the process at once (exit
// 130); one sooner is taken as the same Ctrl-C delivered twice (GNU timeout
// signals the process and its group).
void install_interrupt_handlers();

}  // namespace lmcfg::ops
