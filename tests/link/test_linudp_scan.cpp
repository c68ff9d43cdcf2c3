// Finding LinUDP drives in an address range (lib/link/linudp_scan.*): the
// range syntax and its bound, and a scan of simulated drives over in-process
// datagram links on the virtual clock: what answered, what is held by another
// master (LinUDP V2 §5, C1250 notes), what is silent, and that only NOPs and RAM
// reads of the RTC part went out (LinUDP V2 §4.4.1, §7, p14).
#include <catch2/catch.hpp>
#include <map>

#include "link/linudp_scan.hpp"
#include "linudp_rig.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace link_test_linudp_scan {

using namespace lmcfg;

TEST_CASE("LinUDP scan: address ranges and their bound", "[linudp][scan]") {
  auto net = link::parse_linudp_range("10.8.7.0/24");
  REQUIRE(net.ok());
  CHECK(net->port == 49360);  // LinUDP V2 §4.3 drive port
  REQUIRE(net->hosts.size() == 254);
  CHECK(net->hosts.front() == "10.8.7.1");
  CHECK(net->hosts.back() == "10.8.7.254");

  auto dash = link::parse_linudp_range("10.8.7.1-40:5000");
  REQUIRE(dash.ok());
  CHECK(dash->port == 5000);
  REQUIRE(dash->hosts.size() == 40);
  CHECK(dash->hosts[39] == "10.8.7.40");

  auto full = link::parse_linudp_range("10.8.7.250-10.8.8.1");
  REQUIRE(full.ok());
  CHECK(full->hosts == std::vector<std::string>{"10.8.7.250", "10.8.7.251", "10.8.7.252",
                                                "10.8.7.253", "10.8.7.254", "10.8.7.255",
                                                "10.8.8.0", "10.8.8.1"});
  auto one = link::parse_linudp_range("drive-7.plant:49360");
  REQUIRE(one.ok());
  CHECK(one->hosts == std::vector<std::string>{"drive-7.plant"});
  auto host32 = link::parse_linudp_range("10.8.7.9/32");
  REQUIRE(host32.ok());
  CHECK(host32->hosts == std::vector<std::string>{"10.8.7.9"});

  CHECK(link::parse_linudp_range("10.8.0.0/16").error().message ==
        "--port linudp://10.8.0.0/16: 65534 addresses, more than the 256 a LinUDP scan probes "
        "(one /24); name a smaller range");
  CHECK(link::parse_linudp_range("10.8.7.0-10.8.8.1").error().message ==
        "--port linudp://10.8.7.0-10.8.8.1: 258 addresses, more than the 256 a LinUDP scan "
        "probes (one /24); name a smaller range");
  CHECK(link::parse_linudp_range("10.8.7.40-1").error().message ==
        "--port linudp://10.8.7.40-1: the range ends before it starts (expected "
        "linudp://HOST[:PORT], linudp://A.B.C.D/N[:PORT], linudp://A.B.C.D-A.B.C.E[:PORT] or "
        "linudp://A.B.C.D-E[:PORT])");
  CHECK(link::parse_linudp_range("10.8.7.0/33").error().code ==
        make_error_code(Errc::invalid_argument));
  CHECK(link::parse_linudp_range("10.8.7.1-300").error().code ==
        make_error_code(Errc::invalid_argument));
  CHECK(link::parse_linudp_range("10.8.7.1:0").error().code ==
        make_error_code(Errc::invalid_argument));
}

namespace {

// The firmware version UPIDs (LinUDP DLL: RAM 0034h, 0035h), read-only.
void add_firmware(sim::Drive& d, std::uint32_t major, std::uint32_t minor) {
  for (auto [upid, v] : {std::pair<std::uint16_t, std::uint32_t>{0x0034, major}, {0x0035, minor}}) {
    sim::Parameter p;
    p.upid = upid;
    p.address_usage = sim::au::ram_read;
    p.ram = v;
    d.state().put(p);
  }
}

struct Net {
  std::map<std::string, std::shared_ptr<sim::LinudpDrive>> drives;
  std::map<std::string, std::shared_ptr<test::DatagramRecorder>> wires;
  std::vector<std::string> opened;
  link::UdpOpener opener() {
    return [this](const std::string& host,
                  std::uint16_t port) -> Result<std::unique_ptr<transport::Transport>> {
      opened.push_back(host + ":" + std::to_string(port));
      auto it = drives.find(host);
      std::shared_ptr<sim::LinudpDrive> d;
      if (it != drives.end()) {
        d = it->second;
      } else {  // nobody there: every datagram is lost
        sim::LinudpField f;
        f.lose_request_every = 1;
        d = std::make_shared<sim::LinudpDrive>(test::load_sim_drive("used-spare.json"), f);
      }
      auto& wire = wires[host];
      wire = std::make_shared<test::DatagramRecorder>();
      return transport::make_traced(std::make_unique<sim::LinudpLink>(d), wire);
    };
  }
};

}  // namespace

TEST_CASE("LinUDP scan: answered, held by another master (V2 §5) and silent addresses",
          "[linudp][scan]") {
  Net net;
  auto axis = test::load_sim_drive("commissioned-axis.json");
  add_firmware(*axis, 0x06, 0x0A);  // LinUDP DLL: 060Ah = LT 6.10
  net.drives["10.8.7.1"] = std::make_shared<sim::LinudpDrive>(axis);
  net.drives["10.8.7.3"] =
      std::make_shared<sim::LinudpDrive>(test::load_sim_drive("used-spare.json"));
  sim::LinudpField held;
  held.held_by_other_master = true;
  net.drives["10.8.7.4"] =
      std::make_shared<sim::LinudpDrive>(test::load_sim_drive("used-spare.json"), held);

  auto range = link::parse_linudp_range("10.8.7.1-4:49361");
  REQUIRE(range.ok());
  std::vector<std::string> phases;
  link::LinudpScanOptions o;
  o.progress = [&](const std::string& phase, std::size_t, std::size_t) { phases.push_back(phase); };
  auto rep = link::scan_linudp(*range, net.opener(), o);
  REQUIRE(rep.ok());
  CHECK(net.opened == std::vector<std::string>{"10.8.7.1:49361", "10.8.7.2:49361", "10.8.7.3:49361",
                                               "10.8.7.4:49361"});
  CHECK(phases == std::vector<std::string>{"probing 10.8.7.1", "probing 10.8.7.2",
                                           "probing 10.8.7.3", "probing 10.8.7.4", "done"});
  REQUIRE(rep->addresses.size() == 4);
  const auto& a = rep->addresses;
  CHECK(a[0].answer == link::LinudpAnswer::answered);
  CHECK(a[0].state_var == std::optional<std::uint16_t>(0x08C2));  // the fixture's live words
  CHECK(a[0].status_word == std::optional<std::uint16_t>(0x4C37));
  CHECK(a[0].error_code == std::optional<std::uint16_t>(0x0000));
  CHECK(a[0].firmware == std::optional<std::uint32_t>(0x060A));
  CHECK(a[0].datagrams == 3);  // NOP, 11h 0034h, 11h 0035h
  CHECK(a[1].answer == link::LinudpAnswer::silent);
  CHECK(a[1].datagrams == 1);
  CHECK(a[1].ms == Approx(200.1));  // one attempt of 200 ms (C1250 notes), 0.1 ms on the wire
  CHECK(a[2].answer == link::LinudpAnswer::answered);
  CHECK_FALSE(a[2].firmware);
  CHECK(a[2].firmware_note == "firmware version not readable (RAM 0034h/0035h refused)");
  CHECK(a[3].answer == link::LinudpAnswer::held);
  CHECK(a[3].datagrams == 1);
  CHECK(a[3].ms >= 10.0);  // the 10 ms gap (LinUDP DLL)
  CHECK(rep->count(link::LinudpAnswer::answered) == 2);
  CHECK(rep->count(link::LinudpAnswer::held) == 1);
  CHECK(rep->count(link::LinudpAnswer::silent) == 1);

  // Only the RTC part (request definition 04h, LinUDP V2 §4.4.1), and only NOPs
  // and RAM reads (00h, 11h): nothing that writes or moves.
  std::uint64_t datagrams = 0;
  for (const auto& [host, wire] : net.wires) {
    for (const auto& d : wire->tx) {
      ++datagrams;
      auto r = linudp::decode_request(d);
      REQUIRE(r.ok());
      CHECK(r->request_def == 0x04);
      REQUIRE(r->rtc);
      CHECK((r->rtc->id == 0x00 || r->rtc->id == 0x11));
    }
  }
  CHECK(datagrams == rep->datagrams);
  for (const auto& [host, d] : net.drives) CHECK(d->stats().motion_telegrams == 0);
  INFO("commands " << net.drives["10.8.7.1"]->stats().commands << " datagrams "
                   << net.drives["10.8.7.1"]->stats().datagrams);
  CHECK(net.drives["10.8.7.1"]->stats().commands == 3);
}

TEST_CASE("LinUDP scan: --retries resends the NOP with its count (V2 §7)", "[linudp][scan]") {
  Net net;
  sim::LinudpField lossy;
  lossy.lose_request_every = 1;  // nobody answers: both attempts go out
  net.drives["127.0.0.9"] =
      std::make_shared<sim::LinudpDrive>(test::load_sim_drive("used-spare.json"), lossy);
  link::LinudpScanOptions o;
  o.attempts = 2;
  auto twice = link::scan_linudp(*link::parse_linudp_range("127.0.0.9"), net.opener(), o);
  REQUIRE(twice.ok());
  CHECK(twice->addresses[0].answer == link::LinudpAnswer::silent);
  CHECK(twice->addresses[0].datagrams == 2);
  CHECK(twice->addresses[0].ms == Approx(400.2));  // 2 x (200 ms + 0.1 ms on the wire)
  auto r0 = linudp::decode_request(net.wires["127.0.0.9"]->tx.at(0));
  auto r1 = linudp::decode_request(net.wires["127.0.0.9"]->tx.at(1));
  REQUIRE((r0.ok() && r1.ok()));
  CHECK(r0->rtc->count == r1->rtc->count);
}

}  // namespace link_test_linudp_scan
