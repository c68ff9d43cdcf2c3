#include "ops/long_step.hpp"

namespace lmcfg::ops {

Result<LongStep> long_step(client::Client& c, const std::string& what,
                           const std::function<Result<void>()>& op) {
  auto r = op();
  if (r.ok()) return LongStep{};
  if (r.error().code != make_error_code(Errc::timeout) || c.options().recover_timeout.count() <= 0)
    return std::move(r).error();
  auto back = c.find_again(what);
  const long long deadline_s =
      what.find("flash") != std::string::npos ? c.options().flash_timeout.count() / 1000
      : what.rfind("defaulting", 0) == 0      ? c.options().defaulting_timeout.count() / 1000
                                              : c.options().reset_timeout.count() / 1000;
  if (back.ok()) {
    LongStep s;
    s.acknowledged = false;
    s.note = "the drive did not acknowledge " + what + " within " + std::to_string(deadline_s) +
             " s and answered again " + std::to_string(back->count() / 1000) + " s later";
    return s;
  }
  Error e = std::move(back).error();
  if (e.code != make_error_code(Errc::timeout)) return e;
  // Field reports, C1250 notes: a drive may be silent for 30-90 s after a save or a
  // ROM write; one silent longer than both waits is slow or gone, which the
  // tool cannot tell apart: say what was waited and how to wait longer.
  e.message = "no answer within " + std::to_string(deadline_s) + " s, and " + e.message +
              "; the drive may still be busy (real drives were silent for 30-90 s " +
              "after saves and ROM writes) or gone: if it is slow, wait longer with " +
              "--long-timeout-s (now " + std::to_string(deadline_s) + ") or --recover-timeout-s " +
              "(now " + std::to_string(c.options().recover_timeout.count() / 1000) +
              "), else check its power and wiring";
  return e;
}

}  // namespace lmcfg::ops
