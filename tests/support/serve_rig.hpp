#pragma once
// A serve::Service over an inventory's text (sim: ports), in a scratch
// directory of its own, on a clock the test sets, collecting the events it sends.
#include <catch2/catch.hpp>
#include <functional>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "files.hpp"
#include "ops/session.hpp"
#include "serve/service.hpp"
#include "sim/state_file.hpp"

namespace lmcfg::test {

struct ServiceRig {
  ScratchDir dir;
  serve::TimePoint now = serve::Clock::from_time_t(1'800'000'000);
  std::mutex mu;
  std::vector<nlohmann::json> events;
  std::unique_ptr<serve::Service> service;

  explicit ServiceRig(const std::string& prefix) : dir(prefix) {}

  // The service over `inventory_text`, its archive in dir/archive, one link per
  // line on the line's port; `tweak` changes the options before it starts.
  void start(const std::string& inventory_text,
             const std::function<void(serve::ServiceOptions&)>& tweak = {}) {
    ops::register_link_scheme("sim", sim::state_file_link_factory());
    auto inv = fleet::parse_inventory(inventory_text, "plant.toml");
    REQUIRE(inv.ok());
    serve::ServiceOptions o;
    o.inventory = *inv;
    o.archive = (dir.path / "archive").string();
    for (const auto& l : inv->lines) {
      ops::LinkOptions link;
      link.port = l.port;
      o.links.push_back(link);
    }
    o.clock = [this] { return now; };
    o.notify = [this](const serve::Json& e) {
      std::lock_guard<std::mutex> lock(mu);
      events.push_back(nlohmann::json::parse(e.dump()));
    };
    if (tweak) tweak(o);
    auto s = serve::Service::create(std::move(o));
    REQUIRE(s.ok());
    service = std::move(s).value();
  }
  // The jobs due at `t`, run to the end.
  void at(serve::TimePoint t) {
    now = t;
    service->tick(t);
    service->wait_idle();
  }
  std::vector<nlohmann::json> take_events() {
    std::lock_guard<std::mutex> lock(mu);
    return std::exchange(events, {});
  }
};

}  // namespace lmcfg::test
