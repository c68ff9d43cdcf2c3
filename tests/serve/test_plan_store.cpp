// The service's plan store (lib/serve/plan_store.cpp): a plan executes once,
// not after it expires, and a refused execution leaves it to be executed
// once the cause is gone; expired plans do not pile up.
#include <catch2/catch.hpp>

#include "serve/plan_store.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace serve_test_plan_store {

using namespace lmcfg;
using namespace lmcfg::serve;
using namespace lmcfg::serve::detail;
using namespace std::chrono_literals;

namespace {

StoredPlan plan(const std::string& id, TimePoint expires) {
  StoredPlan sp;
  sp.id = id;
  sp.who = "ops";
  sp.line = 1;
  sp.expires = expires;
  return sp;
}

const auto kAny = [](const StoredPlan&) -> Result<void> { return {}; };

}  // namespace

TEST_CASE("serve plan store: a plan is taken once", "[serve][plans]") {
  TimePoint now(std::chrono::seconds(1'800'000'000));
  PlanStore plans([&] { return now; }, 300s);
  plans.add(plan("aa", now + 300s));
  plans.add(plan("bb", now + 300s));
  CHECK(plans.size() == 2);
  auto taken = plans.take("aa", kAny);
  REQUIRE(taken.ok());
  CHECK((*taken)->id == "aa");
  CHECK((*taken)->who == "ops");
  CHECK((*taken)->line == 1);
  auto again = plans.take("aa", kAny);
  REQUIRE_FALSE(again.ok());
  CHECK(again.error().code == Errc::not_found);
  CHECK(again.error().message == "no plan 'aa'");
  CHECK(plans.size() == 1);
}

TEST_CASE("serve plan store: an expired plan is refused and goes", "[serve][plans]") {
  TimePoint now(std::chrono::seconds(1'800'000'000));
  PlanStore plans([&] { return now; }, 300s);
  plans.add(plan("aa", now + 300s));
  now += 300s;
  auto late = plans.take("aa", kAny);
  REQUIRE_FALSE(late.ok());
  CHECK(late.error().code == Errc::not_found);
  CHECK(late.error().message ==
        "plan 'aa' expired at 2027-01-15T08:05:00Z (a plan is valid for 300 s): make a new one");
  CHECK(plans.size() == 0);
  CHECK(plans.take("aa", kAny).error().message == "no plan 'aa'");
}

TEST_CASE("serve plan store: a refused execution keeps the plan", "[serve][plans]") {
  TimePoint now(std::chrono::seconds(1'800'000'000));
  PlanStore plans([&] { return now; }, 300s);
  plans.add(plan("aa", now + 300s));
  int checked = 0;
  auto refused = plans.take("aa", [&](const StoredPlan& sp) -> Result<void> {
    ++checked;
    CHECK(sp.id == "aa");
    return Error(Errc::plan_refused, "another restore is running");
  });
  REQUIRE_FALSE(refused.ok());
  CHECK(refused.error().message == "another restore is running");
  CHECK(checked == 1);
  CHECK(plans.size() == 1);
  CHECK(plans.take("aa", kAny).ok());
}

TEST_CASE("serve plan store: adding a plan drops the expired ones", "[serve][plans]") {
  TimePoint now(std::chrono::seconds(1'800'000'000));
  PlanStore plans([&] { return now; }, 300s);
  for (int i = 0; i < 50; ++i) plans.add(plan("old" + std::to_string(i), now + 10s));
  CHECK(plans.size() == 50);
  now += 20s;
  plans.add(plan("new", now + 300s));
  CHECK(plans.size() == 1);
  CHECK(plans.take("new", kAny).ok());
}

}  // namespace serve_test_plan_store
