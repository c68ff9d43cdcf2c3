// A simulated drive answering LinUDP (sim::LinudpDrive over the same
// sim::Drive state as the LinRS simulator) behind an in-process datagram link
// on the virtual clock, in a link::Session as link::open_session opens a
// linudp:// port: long steps (39-75 s saves, silences) take no real time.
#pragma once

#include <memory>
#include <string>

#include "e2e_support.hpp"
#include "link/session.hpp"
#include "linudp/codec.hpp"
#include "sim/linudp_link.hpp"

namespace lmcfg::test {

// Every datagram the master sent (one TX record per write).
class DatagramRecorder : public transport::TraceSink {
 public:
  std::vector<Bytes> tx, rx;
  void record(bool is_tx, ByteView bytes) override {
    (is_tx ? tx : rx).emplace_back(bytes.begin(), bytes.end());
  }
  // Datagrams carrying a command that changes the drive (distinct counts).
  std::size_t write_commands() const {
    std::size_t n = 0;
    std::optional<std::uint8_t> last;
    for (const auto& d : tx) {
      auto r = linudp::decode_request(d);
      if (!r.ok() || !r->rtc) continue;
      if (last && *last == r->rtc->count) continue;  // a resend
      last = r->rtc->count;
      if (linudp::is_write_command(r->rtc->id)) ++n;
    }
    return n;
  }
};

struct LinudpRig {
  std::shared_ptr<sim::Drive> drive;
  std::shared_ptr<sim::LinudpDrive> udp;
  std::shared_ptr<DatagramRecorder> wire = std::make_shared<DatagramRecorder>();
  sim::LinudpLink* link = nullptr;
  std::unique_ptr<link::Session> session;

  explicit LinudpRig(std::shared_ptr<sim::Drive> d, sim::LinudpField field = {},
                     const std::string& port = "linudp://127.0.0.1")
      : drive(std::move(d)), udp(std::make_shared<sim::LinudpDrive>(drive, field)) {
    link::LinkSpec spec;
    spec.port = *link::parse_port(port);
    auto raw = std::make_unique<sim::LinudpLink>(udp);
    link = raw.get();
    transport::OpenedLink opened;
    opened.link = transport::make_traced(std::move(raw), wire);
    session = std::make_unique<link::Session>(spec, spec.serial, std::move(opened), std::nullopt);
  }
  client::Client& client() { return session->client(); }
};

}  // namespace lmcfg::test
