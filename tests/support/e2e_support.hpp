#pragma once
// End-to-end helpers: simulated drives from the demo fixtures, the database if
// built, and counting write telegrams in what actually went over the link.
#include <memory>
#include <optional>
#include <string>

#include "client/client.hpp"
#include "codec/frame.hpp"
#include "db/database.hpp"
#include "sim/link.hpp"
#include "sim/state_file.hpp"
#include "transport/transport.hpp"

namespace lmcfg::test {

inline std::string sim_fixture(const std::string& name) {
  return std::string(LMCFG_SOURCE_DIR) + "/tests/fixtures/sim/" + name;
}

inline std::shared_ptr<sim::Drive> load_sim_drive(const std::string& fixture) {
  auto st = sim::load_state(sim_fixture(fixture));
  if (!st.ok()) throw std::runtime_error(st.error().message);
  return std::make_shared<sim::Drive>(std::move(st).value());
}

inline std::optional<db::Database> built_database() {
  auto r = db::Database::open(LMCFG_DB_PATH);
  if (!r.ok()) return std::nullopt;
  return std::move(r).value();
}

// Records every request the master put on the wire.
class WireRecorder : public transport::TraceSink {
 public:
  std::vector<Bytes> tx;
  void record(bool is_tx, ByteView bytes) override {
    if (is_tx) tx.emplace_back(bytes.begin(), bytes.end());
  }
  // Write telegrams (codec::is_write_request) among everything sent.
  std::size_t write_telegrams() const {
    std::size_t n = 0;
    codec::StreamDecoder dec;
    for (const auto& chunk : tx) {
      dec.feed(chunk);
      while (auto t = dec.next()) {
        if (t->ok() && codec::is_write_request(t->value())) ++n;
      }
    }
    return n;
  }
};

// A simulated drive behind a traced link and a client.
struct SimRig {
  std::shared_ptr<sim::Drive> drive;
  std::shared_ptr<sim::SimLink> sim_link;
  std::shared_ptr<WireRecorder> wire = std::make_shared<WireRecorder>();
  std::unique_ptr<transport::Transport> link;
  std::unique_ptr<client::LinrsClient> client;

  explicit SimRig(const std::string& fixture, client::ClientOptions opt = {})
      : drive(load_sim_drive(fixture)) {
    auto raw = std::make_unique<sim::SimLink>(drive);
    sim_link_ptr = raw.get();
    link = transport::make_traced(std::move(raw), wire);
    client = std::make_unique<client::LinrsClient>(*link, opt);
  }
  sim::SimLink& sim() { return *sim_link_ptr; }

 private:
  sim::SimLink* sim_link_ptr = nullptr;
};

}  // namespace lmcfg::test
