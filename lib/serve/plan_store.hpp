#pragma once
// Private to the serve layer: the restore plans made for the API, kept until
// they expire or execute (once), under their own lock. Not installed.
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "fleet/archive.hpp"
#include "ops/restore_run.hpp"
#include "serve/service.hpp"

namespace lmcfg::serve::detail {

// A plan made for the API: what execute() needs, kept until it expires.
struct StoredPlan {
  std::string id;
  fleet::ArchivedFile file;
  std::size_t line = 0;
  ops::Plan plan;
  std::string who;
  TimePoint expires;
};

class PlanStore {
 public:
  // `lifetime`: how long a plan may wait for its execution (said in the
  // expiry's message).
  PlanStore(std::function<TimePoint()> clock, std::chrono::seconds lifetime);

  // Keeps `sp` (the expired plans go: an API client looping on plan must not
  // grow the store).
  void add(StoredPlan sp);
  // The plan `id` for its execution, taken out: a plan executes once.
  // Errc::not_found for an unknown or expired one (an expired one goes);
  // `check` runs under the store's lock first, and its error leaves the plan
  // kept (the same plan may be executed again once the cause is gone).
  Result<std::shared_ptr<StoredPlan>> take(
      const std::string& id, const std::function<Result<void>(const StoredPlan&)>& check);
  std::size_t size() const;

 private:
  const std::function<TimePoint()> clock_;
  const std::chrono::seconds lifetime_;
  mutable std::mutex mu_;
  std::map<std::string, StoredPlan> plans_;  // by id
};

}  // namespace lmcfg::serve::detail
