// A simulated drive behind a traced link in a link::Session, as
// link::open_session opens a sim: port, for the tests of the operations that
// take a session (restore_run, long steps); and the demo axis's backup.
#pragma once

#include <atomic>
#include <catch2/catch.hpp>
#include <memory>
#include <string>

#include "db/database.hpp"
#include "e2e_support.hpp"
#include "link/session.hpp"
#include "ops/backup.hpp"

namespace lmcfg::test {

struct SessionRig {
  std::shared_ptr<sim::Drive> drive;
  std::shared_ptr<WireRecorder> wire = std::make_shared<WireRecorder>();
  sim::SimLink* sim = nullptr;
  std::unique_ptr<link::Session> session;

  // `port`: the sim: port the session names (recovery records and journal
  // entries are keyed by it); `cancel`: the client's cancel flag.
  explicit SessionRig(std::shared_ptr<sim::Drive> d, const std::string& port = "sim:run",
                      const std::atomic<bool>* cancel = nullptr)
      : drive(std::move(d)) {
    link::LinkSpec spec;
    spec.port = *link::parse_port(port);
    spec.client.id = drive->macid();
    spec.client.cancel = cancel;
    auto raw = std::make_unique<sim::SimLink>(drive);
    sim = raw.get();
    transport::OpenedLink opened;
    opened.link = transport::make_traced(std::move(raw), wire);
    session = std::make_unique<link::Session>(spec, spec.serial, std::move(opened), std::nullopt);
  }
};

// The demo axis (commissioned-axis.json) backed up without a database.
inline config::DriveConfig demo_backup() {
  SimRig demo("commissioned-axis.json");
  auto cfg = ops::backup(*demo.client, ops::BackupOptions{}, db::Database::empty());
  REQUIRE(cfg.ok());
  return std::move(cfg).value();
}

}  // namespace lmcfg::test
