#pragma once
// Long operations (defaulting a layer, flash saves, MC start, reset) whose
// answer never comes: one rule for every command that sends them (restore,
// default, link, undo, fleet restore, the service). Real drives took "about
// 39 s" for a command table flash save that "was never acknowledged", and "ROM
// writes and flash saves left drives unresponsive for 30-90 s" (field reports,
// C1250 notes). So an operation whose answer never comes is followed by
// finding the drive again and reading back what it holds (our reading of
// those reports): a missing answer is not a failure: the drive
// is looked for again (Client::find_again), and the caller reads back what the
// drive holds and lets that decide (docs/field.md "Slow saves").
#include <functional>
#include <string>

#include "client/client.hpp"

namespace lmcfg::ops {

struct LongStep {
  bool acknowledged = true;
  // Not acknowledged: for people, "the drive did not acknowledge saving the
  // command table to flash within 120 s and answered again 3 s later".
  std::string note;
};

// Runs `op`, a long operation of `c` ("saving the command table to flash" is
// `what`). Its answer came: acknowledged. It failed with Errc::timeout (no
// answer within the long deadline) and the drive answers again within
// ClientOptions::recover_timeout: not acknowledged, with the note; the caller
// must read back what the drive holds before it reports success. The drive
// stayed silent: Errc::timeout saying how long was waited, for what, and which
// options wait longer (--long-timeout-s, --recover-timeout-s). Any other error
// of `op` or of the polls (a refusal, a closed link, an interruption) as it is.
Result<LongStep> long_step(client::Client& c, const std::string& what,
                           const std::function<Result<void>()>& op);

}  // namespace lmcfg::ops
