// The desk behind lmcfg ui (ui/desk.hpp): its refusals, names and files,
// one operation per port. The flow over HTTP is test_server.cpp's.
#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <thread>

#ifndef _WIN32
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>
#endif

#include "files.hpp"
#include "ui/desk.hpp"

namespace ui_test_desk {

using namespace lmcfg;
namespace fs = std::filesystem;

struct DeskRig {
  test::ScratchDir dir{"ui-desk"};
  std::unique_ptr<ui::Desk> desk;
  explicit DeskRig(std::string practice = "") {
    ::setenv("XDG_STATE_HOME", (dir.path / "state").string().c_str(), 1);
    ui::DeskOptions o;
    o.folder = dir.path / "backups";
    o.practice_state = std::move(practice);
    o.list_ports = [] { return std::vector<ui::SerialPortInfo>{}; };
    auto d = ui::Desk::create(std::move(o));
    REQUIRE(d.ok());
    desk = std::move(d).value();
  }
  ~DeskRig() {
    desk.reset();
    ::unsetenv("XDG_STATE_HOME");
  }
};

TEST_CASE("desk: names, link options and file names", "[ui_desk]") {
  ui::DriveLink l;
  l.port = "sim:/x/a.json";
  l.id = 0x11;
  CHECK(ui::drive_key(l) == "sim__x_a.json-11h");
  CHECK(ui::link_options_text(l) == "--port sim:/x/a.json --baud 57600 --id 0x11");
  l.parity = "even";
  l.checksum = "crc-ffff";
  l.baud = 115200;
  CHECK(ui::link_options_text(l) ==
        "--port sim:/x/a.json --baud 115200 --id 0x11 --parity even --checksum crc-ffff");
  CHECK(ui::plain_file_name("axis-20261129T001500Z.json"));
  CHECK_FALSE(ui::plain_file_name("../state/journal.jsonl"));
  CHECK_FALSE(ui::plain_file_name("a/b.json"));
  CHECK_FALSE(ui::plain_file_name("a\\b.json"));
  CHECK_FALSE(ui::plain_file_name(".hidden"));
  CHECK_FALSE(ui::plain_file_name("C:x.json"));
  CHECK_FALSE(ui::plain_file_name(""));
}

TEST_CASE("desk: refusals say what and what to do, and nothing starts", "[ui_desk]") {
  DeskRig rig;
  auto b = rig.desk->backup("nope");
  REQUIRE_FALSE(b.ok());
  CHECK(b.error().message == "no drive 'nope' on this page: find it first");
  auto f = rig.desk->file("../x");
  REQUIRE_FALSE(f.ok());
  CHECK(f.error().message ==
        "'../x' is not a file name of the backup folder (no folders, no '..')");
  auto missing = rig.desk->file("gone.json");
  REQUIRE_FALSE(missing.ok());
  CHECK(missing.error().code == Errc::not_found);
  auto none = rig.desk->find(ui::FindRequest{});
  REQUIRE_FALSE(none.ok());
  CHECK(none.error().message == "no port given: choose one of the list or type one");
  ui::FindRequest can;
  can.port = "slcan:/dev/ttyACM0";
  auto c = rig.desk->find(can);
  REQUIRE_FALSE(c.ok());
  CHECK(c.error().message ==
        "port 'slcan:/dev/ttyACM0' is a CAN port: lmcfg ui talks LinRS and LinUDP only");
  auto e = rig.desk->execute("p9", ops::Audit{"", "why", ""}, false);
  REQUIRE_FALSE(e.ok());
  CHECK(e.error().message == "no plan 'p9'");
  auto no_reason = rig.desk->execute("p9", ops::Audit{}, false);
  REQUIRE_FALSE(no_reason.ok());
  CHECK(no_reason.error().message == "a reason is required: the journal records why");
  CHECK(rig.desk->jobs().empty());
}

TEST_CASE("desk: the practice drive is written once and offered", "[ui_desk]") {
  DeskRig rig("{\"format\": \"lmcfg-sim-state\"}");
  const fs::path state = rig.dir.path / "backups" / "practice" / "drive.json";
  CHECK(fs::exists(state));
  CHECK(rig.desk->practice_port() == "sim:" + state.string());
  const auto ports = rig.desk->ports();
  CHECK(ports["practice"] == "sim:" + state.string());
  CHECK(ports["ports"].empty());
}

#ifndef _WIN32
TEST_CASE("desk: one operation per port, a second one told what runs", "[ui_desk]") {
  // A gateway that accepts and never answers: a scan waits out each ID.
  int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  REQUIRE(::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0);
  REQUIRE(::listen(fd, 4) == 0);
  socklen_t len = sizeof a;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
  const std::string port = "tcp://127.0.0.1:" + std::to_string(ntohs(a.sin_port));
  DeskRig rig;
  ui::FindRequest req;
  req.port = port;
  auto first = rig.desk->find(req);
  REQUIRE(first.ok());
  CHECK(rig.desk->busy());
  auto second = rig.desk->find(req);
  REQUIRE_FALSE(second.ok());
  CHECK(second.error().code == Errc::plan_refused);
  CHECK(second.error().message.rfind("port " + port + " is busy: find (job " + *first + ", since ",
                                     0) == 0);
  // After stop() the desk waits for the scan to end, and takes no new work.
  rig.desk->stop();
  rig.desk->wait_idle();
  CHECK_FALSE(rig.desk->busy());
  auto j = rig.desk->job(*first);
  REQUIRE(j.ok());
  CHECK((*j)["state"] != "running");
  CHECK_FALSE((*j)["finished"].is_null());
  auto late = rig.desk->find(req);
  REQUIRE_FALSE(late.ok());
  CHECK(late.error().message == "lmcfg ui is stopping: it takes no new work");
  ::close(fd);
}
#endif

}  // namespace ui_test_desk
