#pragma once
// Private to the serve layer: what the service knows about each position
// (its state, and the restore begun on it and not finished), under its own
// lock, and its files in the state directory (docs/serve.md "State"):
// states.json, pending/. Not installed.
#include <filesystem>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "fleet/approved.hpp"
#include "fleet/archive.hpp"
#include "fleet/inventory.hpp"
#include "serve/service.hpp"

namespace lmcfg::serve::detail {

// A restore the service began and has not finished: written before the
// first write, removed after the outcome is recorded; a start that finds one
// (the service was killed mid-restore) runs the restore again, which converges.
struct PendingRestore {
  std::string drive, commit, who, reason, ticket, cause;
  bool skip_incompatible = false;
  // The job that began it (an automatic retry says "automatic retry of job N"),
  // and what the drive held when it stopped (drive_state_after).
  std::string origin_job, drive_state;
  // The automatic retries that failed: the newest kRetryFailuresKept (when,
  // which job, why), and how many in all.
  struct Failure {
    std::string time, job, reason;
  };
  std::vector<Failure> failures;
  std::size_t failed_attempts = 0;
};
inline constexpr std::size_t kRetryFailuresKept = 10;

// What the service knows about one position.
struct DriveState {
  std::string status = "unknown";  // ok, drift, failed, replaced, unknown
  std::string message = "not read yet";
  std::optional<TimePoint> last_backup;
  std::optional<TimePoint> last_attempt;
  std::string last_kind;
  bool last_ok = false;
  int last_exit_code = 0;
  std::size_t differences = 0;
  std::vector<std::string> differing;       // the differences, as the commit message says them
  std::string notified;                     // the last state an event was sent for
  std::optional<fleet::Approval> approved;  // the position's approved configuration, when known
  // What differs but is kept by policy (ops/matching.hpp), as ops::kept_json:
  // not drift, said on the position.
  Json kept = Json::array();
  // After a failed restore: what the drive holds (drive_state_after); "" otherwise.
  std::string drive_state;
  std::uint64_t retries_failed = 0;  // automatic retries of a restore that failed (a counter)
};

class StateStore {
 public:
  struct Data {
    std::map<std::string, DriveState> states;       // by position name
    std::map<std::string, PendingRestore> pending;  // restores begun, by position
  };

  StateStore(std::filesystem::path dir, std::function<void(const std::string&)> log);

  // `f(data)` under the store's lock (never call another part from `f`).
  template <class F>
  decltype(auto) with(F&& f) {
    std::lock_guard<std::mutex> lock(mu_);
    return f(data_);
  }
  template <class F>
  decltype(auto) read(F&& f) const {
    std::lock_guard<std::mutex> lock(mu_);
    return f(static_cast<const Data&>(data_));
  }
  // A copy of position `name`'s state (the unknown state when none).
  DriveState state(const std::string& name) const;
  std::optional<PendingRestore> pending(const std::string& name) const;
  bool is_pending(const std::string& name) const;

  // The states as they are now, written to states.json (writers in turn,
  // the last write the newest; a failure is logged: it costs the states
  // after a restart, not the run).
  void save();
  // At start: states.json read back, each position's approval from the
  // archive; a position it does not name takes its last backup from the
  // archive's history, so a restart changes nothing people see.
  void load(const fleet::Inventory& inventory, fleet::Archive& archive);

  // A restore begun (or its record updated): pending/<line>-<id>.json, then the store.
  Result<void> save_pending(const fleet::LineEntry& line, const fleet::DriveEntry& d,
                            const PendingRestore& p);
  void remove_pending(const fleet::LineEntry& line, const fleet::DriveEntry& d);
  // At start: the records in pending/ read back; the positions they name.
  std::vector<std::string> load_pending(const fleet::Inventory& inventory);

  const std::filesystem::path& dir() const { return dir_; }

 private:
  const std::filesystem::path dir_;
  const std::function<void(const std::string&)> log_;
  mutable std::mutex mu_;
  std::mutex file_mu_;  // states.json: one writer at a time (taken before mu_)
  Data data_;
};

}  // namespace lmcfg::serve::detail
