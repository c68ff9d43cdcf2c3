// The restore plans made for the API (docs/serve.md "Plans"): each executes
// once, and not after it expires.
#include "serve/plan_store.hpp"

namespace lmcfg::serve::detail {

PlanStore::PlanStore(std::function<TimePoint()> clock, std::chrono::seconds lifetime)
    : clock_(std::move(clock)), lifetime_(lifetime) {}

void PlanStore::add(StoredPlan sp) {
  const TimePoint now = clock_();
  std::lock_guard<std::mutex> lock(mu_);
  std::erase_if(plans_, [&](const auto& kv) { return kv.second.expires <= now; });
  std::string id = sp.id;
  plans_.insert_or_assign(std::move(id), std::move(sp));
}

Result<std::shared_ptr<StoredPlan>> PlanStore::take(
    const std::string& id, const std::function<Result<void>(const StoredPlan&)>& check) {
  const TimePoint now = clock_();
  std::lock_guard<std::mutex> lock(mu_);
  auto it = plans_.find(id);
  if (it == plans_.end()) return Error(Errc::not_found, "no plan '" + id + "'");
  if (it->second.expires <= now) {
    const std::string when = iso_time(it->second.expires);
    plans_.erase(it);
    return Error(Errc::not_found, "plan '" + id + "' expired at " + when +
                                      " (a plan is valid for " + std::to_string(lifetime_.count()) +
                                      " s): make a new one");
  }
  LMCFG_TRY(check(it->second));
  auto taken = std::make_shared<StoredPlan>(std::move(it->second));
  plans_.erase(it);
  return taken;
}

std::size_t PlanStore::size() const {
  std::lock_guard<std::mutex> lock(mu_);
  return plans_.size();
}

}  // namespace lmcfg::serve::detail
