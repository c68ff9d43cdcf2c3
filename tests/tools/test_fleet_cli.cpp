// lmcfg fleet end to end: two lines behind loopback TCP gateways (`lmcfg sim
// --tcp` serving an RS485 line of several MACIDs each) and one simulated line
// in-process (sim:A.json,B.json), archived in a real git repository (libgit2);
// DeviceNet controllers (`lmcfg sim --devicenet`) on a pty and on loopback TCP
// next to a LinRS line on a pty.
#include <catch2/catch.hpp>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "config/config_io.hpp"
#include "devicenet_sim.hpp"
#include "files.hpp"
#include "fleet/archive.hpp"
#include "subprocess.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace tools_test_fleet_cli {

using namespace lmcfg;
namespace fs = std::filesystem;

namespace {

const std::string kFixtures = std::string(LMCFG_SOURCE_DIR) + "/tests/fixtures/sim/";

// The commissioned axis at MACID `id`. Its communication parameters are left
// at their defaults, so a restore without --include-comm reproduces it fully.
void write_axis(const fs::path& path, int id, bool factory_fresh = false) {
  auto j = nlohmann::json::parse(test::slurp(kFixtures + "commissioned-axis.json"));
  j["macid"] = id;
  for (auto& p : j["parameters"]) {
    const std::string upid = p["upid"];
    if (factory_fresh || upid == "200E" || upid == "206C") p["rom"] = p["ram"] = p["default"];
  }
  if (factory_fresh) {
    j["curves"] = nlohmann::json::array();
    j["command_table"] = nlohmann::json::array();
  }
  test::spit(path, j.dump(1));
}

// `lmcfg sim --tcp` serving the drives of `states` on one line.
struct Gateway {
  std::unique_ptr<test::Child> child;
  std::string port;
  explicit Gateway(const std::vector<fs::path>& states) {
    std::vector<std::string> argv{LMCFG_TOOL_PATH, "sim", "--tcp", "127.0.0.1:0", "--fast"};
    for (const auto& s : states) {
      argv.push_back("--state");
      argv.push_back(s.string());
    }
    child = std::make_unique<test::Child>(argv);
    port = "tcp://127.0.0.1:" + child->read_line();
  }
};

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

}  // namespace

TEST_CASE(
    "fleet: backup, drift, a silent line and a restored replacement, over TCP gateways "
    "and a simulated RS485 line",
    "[fleet][cli]") {
  test::ScratchDir d("fleet");
  const auto& dir = d.path;
  write_axis(dir / "g1a.json", 0x11);
  write_axis(dir / "g1b.json", 0x12);
  write_axis(dir / "g1c.json", 0x13);
  write_axis(dir / "g2a.json", 0x21);
  write_axis(dir / "g2b.json", 0x22);
  write_axis(dir / "s1.json", 0x11);
  write_axis(dir / "s2.json", 0x12);
  Gateway gw1({dir / "g1a.json", dir / "g1b.json", dir / "g1c.json"});
  auto gw2 = std::make_unique<Gateway>(std::vector<fs::path>{dir / "g2a.json", dir / "g2b.json"});
  REQUIRE(gw1.port.size() > 16);
  REQUIRE(gw2->port.size() > 16);
  test::spit(dir / "plant.toml", "[[line]]\nname = \"line1\"\nport = \"" + gw1.port +
                                     "\"\n"
                                     "[[line.drive]]\nname = \"press3/z-axis\"\nid = 0x11\n"
                                     "labels = { machine = \"press3\" }\n"
                                     "[[line.drive]]\nname = \"press3/x-axis\"\nid = 0x12\n"
                                     "[[line.drive]]\nname = \"press3/y-axis\"\nid = 0x13\n"
                                     "[[line]]\nname = \"line2\"\nport = \"" +
                                     gw2->port +
                                     "\"\ntimeout_ms = 50\nretries = 0\n"
                                     "[[line.drive]]\nname = \"press4/z\"\nid = 0x21\n"
                                     "[[line.drive]]\nname = \"press4/x\"\nid = 0x22\n"
                                     "[[line]]\nname = \"bench\"\nport = \"sim:s1.json,s2.json\"\n"
                                     "[[line.drive]]\nname = \"bench/a\"\nid = 0x11\n"
                                     "[[line.drive]]\nname = \"bench/b\"\nid = 0x12\n");
  const std::vector<std::string> files = {
      "press3/z-axis.json", "press3/x-axis.json", "press3/y-axis.json", "press4/z.json",
      "press4/x.json",      "bench/a.json",       "bench/b.json"};

  auto check = test::run_tool_in(dir, "fleet check plant.toml");
  INFO(check.err);
  CHECK(check.exit_code == 0);
  CHECK(check.out == "plant.toml: 3 line(s), 7 drive(s): ok\n");

  // The first backup creates the archive and commits every file.
  auto first = test::run_tool_in(dir, "fleet backup plant.toml --archive arch");
  INFO(first.err);
  REQUIRE(first.exit_code == 0);
  auto archive = fleet::Archive::open((dir / "arch").string(), false);
  REQUIRE(archive.ok());
  auto head1 = archive->resolve("HEAD");
  REQUIRE(head1.ok());
  REQUIRE(*head1);
  CHECK((*head1)->summary == "fleet backup: 0 changed, 0 unchanged, 7 new, 0 failed");
  for (const auto& f : files) {
    INFO(f);
    auto text = archive->read(f);
    REQUIRE(text.ok());
    REQUIRE(*text);
    CHECK(**text == test::slurp(dir / "arch" / f));
  }
  CHECK(archive->read("press3/z-axis.json").value()->find("\"machine\": \"press3\"") !=
        std::string::npos);
  CHECK(count(first.err, "[line1 ") == 3);  // progress per line
  CHECK(count(first.err, "[line2 ") == 2);

  // Nothing changed: no commit, and the run says so.
  auto second = test::run_tool_in(dir, "fleet backup plant.toml --archive arch");
  CHECK(second.exit_code == 0);
  CHECK(second.out.find("7 drive(s): 0 changed, 7 unchanged, 0 new, 0 failed; no changes") !=
        std::string::npos);
  CHECK(archive->resolve("HEAD").value()->id == (*head1)->id);

  // Someone tunes a gain on one drive: status reports exactly that drift.
  auto set =
      test::run_tool_in(dir, "set --port " + gw1.port + " --id 0x12 --rom --stop-mc 13A2 1234");
  INFO(set.err);
  REQUIRE(set.exit_code == 0);
  auto status = test::run_tool_in(dir, "fleet status plant.toml --archive arch");
  CHECK(status.exit_code == 1);
  CHECK(status.out.rfind(
            "drift: press3/x-axis (line line1, MACID 12h): 1 parameter, 0 curves, 0 CT entries\n"
            "    MC 13A2h P Gain Position Controller Set A: 40 -> 1234\n"
            "7 drive(s): 6 as archived, 1 drifted, 0 not in archive, 0 failed (against the "
            "approved configurations)",
            0) == 0);
  auto status_json = test::run_tool_in(dir, "fleet status plant.toml --archive arch --json");
  CHECK(status_json.exit_code == 1);
  const auto sj = nlohmann::json::parse(status_json.out);
  CHECK(sj["counts"]["changed"] == 1);
  CHECK(sj["drives"][1]["differences"][0]["key"] == 0x13A2);

  // The next backup commits only that drive's file, naming the drive and the UPID.
  auto third = test::run_tool_in(dir, "fleet backup plant.toml --archive arch");
  CHECK(third.exit_code == 0);
  auto head2 = archive->resolve("HEAD").value();
  REQUIRE(head2);
  CHECK(head2->id != (*head1)->id);
  CHECK(head2->message ==
        "fleet backup: 1 changed, 6 unchanged, 0 new, 0 failed\n"
        "\n"
        "changed press3/x-axis (line line1, MACID 12h): 1 parameter, 0 curves, 0 CT entries\n"
        "  MC 13A2h P Gain Position Controller Set A: 40 -> 1234\n");
  for (const auto& f : files) {
    INFO(f);
    const bool same = *archive->read(f, "HEAD").value() == *archive->read(f, "HEAD~1").value();
    CHECK(same == (f != "press3/x-axis.json"));
  }
  // Archived is not approved: the position stays in drift against its
  // commissioned file until someone approves the change.
  auto archived = test::run_tool_in(dir, "fleet status plant.toml --archive arch");
  CHECK(archived.exit_code == 1);
  CHECK(count(archived.out, "drift: press3/x-axis ") == 1);
  CHECK(test::run_tool_in(dir, "fleet status plant.toml --archive arch --since HEAD").exit_code ==
        0);
  auto since = test::run_tool_in(dir, "fleet status plant.toml --archive arch --since HEAD~1");
  CHECK(since.exit_code == 1);
  CHECK(count(since.out, "drift: ") == 1);

  auto approved = test::run_tool_in(dir,
                                    "fleet approve press3/x-axis --archive arch --reason \"gain "
                                    "retuned after the new tool\" --ticket CHG-7 --who maria");
  INFO(approved.err);
  CHECK(approved.exit_code == 0);
  CHECK(approved.out == "fleet approve: press3/x-axis <- press3/x-axis.json at " +
                            head2->id.substr(0, 12) +
                            " (HEAD), approved by maria: gain retuned after the new tool (ticket "
                            "CHG-7)\n");
  CHECK(test::run_tool_in(dir, "fleet status plant.toml --archive arch").exit_code == 0);

  // A line that stops answering fails the run (exit 4), names its drives and
  // keeps their files; the other lines are still read.
  gw2.reset();
  auto silent = test::run_tool_in(dir, "fleet backup plant.toml --archive arch");
  CHECK(silent.exit_code == 4);
  CHECK(count(silent.out, "failed: press4/") == 2);
  CHECK(silent.out.find("7 drive(s): 0 changed, 5 unchanged, 0 new, 2 failed; no changes") !=
        std::string::npos);
  CHECK(archive->resolve("HEAD").value()->id == head2->id);
  CHECK(fs::exists(dir / "arch/press4/z.json"));

  // A factory-fresh replacement at bench/b is brought back to the archived file.
  write_axis(dir / "s2.json", 0x12, true);
  auto drift = test::run_tool_in(dir, "fleet status plant.toml --archive arch --json");
  CHECK(nlohmann::json::parse(drift.out)["drives"][6]["status"] == "changed");
  auto restore =
      test::run_tool_in(dir, "fleet restore plant.toml --archive arch --drive bench/b --yes");
  INFO(restore.err);
  CHECK(restore.exit_code == 0);
  // Without --rev the position's approved configuration: its first backup's (commissioning).
  CHECK(restore.err.find("verified: the drive matches bench/b.json@" +
                         (*head1)->id.substr(0, 12)) != std::string::npos);
  auto record = archive->resolve("HEAD").value();
  CHECK(record->summary == "fleet restore: bench/b <- bench/b.json at " +
                               (*head1)->id.substr(0, 12) + " (approved): restored and verified");
  auto after = test::run_tool_in(dir, "fleet status plant.toml --archive arch --json");
  const auto aj = nlohmann::json::parse(after.out);
  CHECK(aj["drives"][5]["status"] == "unchanged");
  CHECK(aj["drives"][6]["status"] == "unchanged");
}

TEST_CASE("fleet: bad inventories and archives give positioned errors and write nothing",
          "[fleet][cli]") {
  test::ScratchDir d("fleet-bad");
  const auto& dir = d.path;
  write_axis(dir / "s1.json", 0x11);
  test::spit(dir / "dup.toml",
             "[[line]]\nname = \"l\"\nport = \"sim:s1.json\"\n[[line.drive]]\nname = \"a\"\nid = "
             "1\n[[line.drive]]\nname = \"b\"\nid = 1\n");
  auto dup = test::run_tool_in(dir, "fleet backup dup.toml --archive arch");
  CHECK(dup.exit_code == 2);
  CHECK(dup.err ==
        "lmcfg fleet backup: dup.toml:7:1: line 'l': drives 'a' (dup.toml:4:1) and "
        "'b' (dup.toml:7:1) both have MACID 01h\n");
  CHECK_FALSE(fs::exists(dir / "arch"));

  test::spit(dir / "baud.toml",
             "[[line]]\nname = \"l\"\nport = \"sim:s1.json\"\nbaud = 12345\n[[line.drive]]\nname "
             "= \"a\"\nid = 0x11\n");
  auto baud = test::run_tool_in(dir, "fleet check baud.toml");
  CHECK(baud.exit_code == 2);
  CHECK(baud.err.rfind("lmcfg fleet check: baud.toml:1:1: line 'l': ", 0) == 0);

  test::spit(dir / "reads.toml",
             "[[line]]\nname = \"l\"\nport = \"sim:s1.json\"\nagreeing_reads = 9\n[[line.drive]]\n"
             "name = \"a\"\nid = 0x11\n");
  auto reads = test::run_tool_in(dir, "fleet check reads.toml");
  CHECK(reads.exit_code == 2);
  CHECK(reads.err ==
        "lmcfg fleet check: reads.toml:1:1: line 'l': --agreeing-reads '9' is not auto or 1..5\n");

  test::spit(dir / "usb.toml",
             "[[line]]\nname = \"usb\"\nport = \"/dev/lmcfg-no-adapter\"\n[[line.drive]]\nname "
             "= \"a\"\nid = 0x11\n");
  auto usb = test::run_tool_in(dir, "fleet backup usb.toml --archive arch");
  CHECK(usb.exit_code == 2);
  CHECK(usb.err ==
        "lmcfg fleet backup: usb.toml:1:1: line 'usb': port /dev/lmcfg-no-adapter "
        "does not exist (is the adapter plugged in?)\n");
  CHECK_FALSE(fs::exists(dir / "arch"));

  test::spit(dir / "ok.toml",
             "[[line]]\nname = \"l\"\nport = \"sim:s1.json\"\n[[line.drive]]\nname = \"a\"\nid "
             "= 0x11\n");
  fs::create_directories(dir / "notes");
  test::spit(dir / "notes/readme.txt", "not an archive");
  auto notgit = test::run_tool_in(dir, "fleet backup ok.toml --archive notes");
  CHECK(notgit.exit_code == 2);
  CHECK(notgit.err ==
        "lmcfg fleet backup: archive notes is not a git repository (and not empty, so it is not "
        "made one: give an empty or new directory, or run git init there)\n");
  CHECK(fs::directory_iterator(dir / "notes") != fs::directory_iterator());
  CHECK_FALSE(fs::exists(dir / "notes/a.json"));
  auto nostatus = test::run_tool_in(dir, "fleet status ok.toml --archive nothing-here");
  CHECK(nostatus.exit_code == 2);
  CHECK(nostatus.err == "lmcfg fleet status: archive nothing-here is not a git repository\n");
  auto nodrive = test::run_tool_in(dir, "fleet restore ok.toml --archive notes --drive zz --yes");
  CHECK(nodrive.exit_code == 2);
  CHECK(nodrive.err == "lmcfg fleet restore: ok.toml: no drive named 'zz' in the inventory\n");
}

TEST_CASE("fleet: --push sends the run's commit to a bare repository", "[fleet][cli]") {
  test::ScratchDir d("fleet-push");
  const auto& dir = d.path;
  write_axis(dir / "s1.json", 0x11);
  test::spit(dir / "ok.toml",
             "[[line]]\nname = \"l\"\nport = \"sim:s1.json\"\n[[line.drive]]\nname = \"a\"\nid "
             "= 0x11\n");
  REQUIRE(std::system(("git init -q --bare '" + (dir / "central.git").string() + "'").c_str()) ==
          0);
  auto r = test::run_tool_in(
      dir, "fleet backup ok.toml --archive arch --push '" + (dir / "central.git").string() + "'");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  auto local = fleet::Archive::open((dir / "arch").string(), false);
  REQUIRE(local.ok());
  const auto head = local->resolve("HEAD").value();
  REQUIRE(head);
  REQUIRE(std::system(("git clone -q '" + (dir / "central.git").string() + "' '" +
                       (dir / "clone").string() + "'")
                          .c_str()) == 0);
  auto clone = fleet::Archive::open((dir / "clone").string(), false);
  REQUIRE(clone.ok());
  CHECK(clone->resolve("HEAD").value()->id == head->id);
  CHECK(clone->read("a.json").value() == local->read("a.json").value());

  // A remote configured in the archive, pushed to by name.
  REQUIRE(
      std::system(("git init -q --bare '" + (dir / "named.git").string() + "' && git init -q '" +
                   (dir / "arch2").string() + "' && git -C '" + (dir / "arch2").string() +
                   "' remote add central '" + (dir / "named.git").string() + "'")
                      .c_str()) == 0);
  auto named = test::run_tool_in(dir, "fleet backup ok.toml --archive arch2 --push central");
  INFO(named.err);
  REQUIRE(named.exit_code == 0);
  auto pushed = fleet::Archive::open((dir / "arch2").string(), false);
  REQUIRE(pushed.ok());
  REQUIRE(std::system(("git clone -q '" + (dir / "named.git").string() + "' '" +
                       (dir / "clone2").string() + "'")
                          .c_str()) == 0);
  auto clone2 = fleet::Archive::open((dir / "clone2").string(), false);
  REQUIRE(clone2.ok());
  CHECK(clone2->resolve("HEAD").value()->id == pushed->resolve("HEAD").value()->id);
}

TEST_CASE("fleet: a damaged archived file is drift that the next backup repairs", "[fleet][cli]") {
  test::ScratchDir d("fleet-damaged");
  const auto& dir = d.path;
  write_axis(dir / "s1.json", 0x11);
  test::spit(dir / "ok.toml",
             "[[line]]\nname = \"l\"\nport = \"sim:s1.json\"\n[[line.drive]]\nname = \"a\"\nid "
             "= 0x11\n");
  REQUIRE(test::run_tool_in(dir, "fleet backup ok.toml --archive arch -q").exit_code == 0);
  auto archive = fleet::Archive::open((dir / "arch").string(), false);
  REQUIRE(archive.ok());
  test::spit(dir / "arch/a.json", "{\"format\": \"lmcfg-config\", \"version\": 2");
  REQUIRE(archive->commit({"a.json"}, "someone's edit\n").ok());
  // The approved configuration (the first backup's) is intact: no drift against it.
  CHECK(test::run_tool_in(dir, "fleet status ok.toml --archive arch").exit_code == 0);
  auto status = test::run_tool_in(dir, "fleet status ok.toml --archive arch --since HEAD");
  CHECK(status.exit_code == 1);
  CHECK(status.out.rfind("drift: a (line l, MACID 11h): 0 parameters, 0 curves, 0 CT entries, 1 "
                         "other difference\n    metadata archived file: unreadable (a.json at ",
                         0) == 0);
  auto repair = test::run_tool_in(dir, "fleet backup ok.toml --archive arch");
  CHECK(repair.exit_code == 0);
  CHECK(archive->resolve("HEAD").value()->summary ==
        "fleet backup: 1 changed, 0 unchanged, 0 new, 0 failed");
  CHECK(test::run_tool_in(dir, "fleet status ok.toml --archive arch --since HEAD").exit_code == 0);
}

TEST_CASE(
    "fleet: DeviceNet controllers on a pty and on loopback TCP next to a LinRS line: backup, "
    "drift, restore, under each reading of seed 000 §5.2's toggle rule",
    "[fleet][cli][devicenet]") {
  for (const std::string rule : {"seed", "get-set-ignore", "module"}) {
    INFO("--devicenet-toggle " << rule);
    test::ScratchDir d("fleet-dn");
    const auto& dir = d.path;
    write_axis(dir / "axis.json", 0x11);
    test::Child linrs({LMCFG_TOOL_PATH, "sim", "--state", (dir / "axis.json").string(), "--fast"});
    const std::string rs485 = linrs.read_line();
    REQUIRE(rs485.rfind("/dev/", 0) == 0);
    test::DevicenetSim usb({"--devicenet-toggle", rule});
    test::DevicenetSim gw({"--devicenet-toggle", rule}, test::DevicenetSim::Where::tcp, 7);
    REQUIRE(usb.port == "slcan:" + usb.pty);
    REQUIRE(gw.port.rfind("slcan:tcp://127.0.0.1:", 0) == 0);
    test::spit(dir / "plant.toml", "[[line]]\nname = \"rs485\"\nport = \"" + rs485 +
                                       "\"\n"
                                       "[[line.drive]]\nname = \"press3/z-axis\"\nid = 0x11\n"
                                       "[[line]]\nname = \"can-usb\"\nport = \"" +
                                       usb.port +
                                       "\"\ndevicenet_listen_ms = 20\ntimeout_ms = 100\n"
                                       "[[line.drive]]\nname = \"press5/controller\"\n"
                                       "devicenet_macid = 5\ndevicenet_motors = \"A,B\"\n"
                                       "[[line]]\nname = \"can-gw\"\nport = \"" +
                                       gw.port +
                                       "\"\ncan_bitrate = 125000\ndevicenet_listen_ms = 20\n"
                                       "timeout_ms = 100\n"
                                       "[[line.drive]]\nname = \"press6/controller\"\n"
                                       "devicenet_macid = 7\n");

    auto check = test::run_tool_in(dir, "fleet check plant.toml");
    INFO(check.err);
    CHECK(check.exit_code == 0);
    CHECK(check.out == "plant.toml: 3 line(s), 3 drive(s): ok\n");

    auto first = test::run_tool_in(dir, "fleet backup plant.toml --archive arch");
    INFO(first.out << first.err);
    REQUIRE(first.exit_code == 0);
    auto archive = fleet::Archive::open((dir / "arch").string(), false);
    REQUIRE(archive.ok());
    auto head1 = archive->resolve("HEAD").value();
    REQUIRE(head1);
    CHECK(head1->summary == "fleet backup: 0 changed, 0 unchanged, 3 new, 0 failed");
    CHECK(head1->message.find("\nnew press5/controller (line can-usb, DeviceNet MAC ID 05h): ") !=
          std::string::npos);
    CHECK(head1->message.find("\nnew press6/controller (line can-gw, DeviceNet MAC ID 07h): ") !=
          std::string::npos);
    CHECK(first.err.find("[can-gw 1/1] press6/controller: read ") != std::string::npos);
    for (const char* f : {"press5/controller.json", "press6/controller.json"}) {
      INFO(f);
      auto file = config::read_config_file((dir / "arch" / f).string());
      REQUIRE(file.ok());
      REQUIRE(file->devicenet);
      CHECK(file->devicenet->motors == std::vector<int>{0, 1});  // probed on press6
    }
    // The archived file is what `lmcfg backup` reads from the same controller.
    auto direct = test::run_tool_in(dir, "backup " + gw.link() + " -q -o direct.json");
    REQUIRE(direct.exit_code == 0);
    auto same = test::run_tool_in(dir, "diff direct.json arch/press6/controller.json");
    INFO(same.out);
    CHECK(same.exit_code == 0);
    CHECK(test::run_tool_in(dir, "fleet status plant.toml --archive arch").exit_code == 0);

    // Another master changes two values on the controller behind the gateway.
    test::change_two_values(gw);
    auto status = test::run_tool_in(dir, "fleet status plant.toml --archive arch");
    INFO(status.err);
    CHECK(status.exit_code == 1);
    CHECK(status.out.rfind("drift: press6/controller (line can-gw, DeviceNet MAC ID 07h): 2 "
                           "DeviceNet values\n"
                           "    devicenet motor A: Controller P (34h): ",
                           0) == 0);
    CHECK(status.out.find("\n    devicenet motor B: Filter Maximal Speed (50h): ") !=
          std::string::npos);
    // Against each position's approved configuration: its first backup, head1.
    CHECK(status.out.find("3 drive(s): 2 as archived, 1 drifted, 0 not in archive, 0 failed "
                          "(against the approved configurations)") != std::string::npos);
    auto status_json = test::run_tool_in(dir, "fleet status plant.toml --archive arch --json");
    const auto sj = nlohmann::json::parse(status_json.out);
    CHECK(sj["drives"][2]["status"] == "changed");
    CHECK(sj["drives"][2]["differences"].size() == 2);
    CHECK(sj["drives"][2]["differences"][0]["kind"] == "devicenet");

    // fleet restore puts the archived values back through the DeviceNet restore.
    auto restore = test::run_tool_in(
        dir, "fleet restore plant.toml --archive arch --drive press6/controller --yes");
    INFO(restore.out << restore.err);
    CHECK(restore.exit_code == 0);
    CHECK(restore.out.find("  set 35h motor A: Controller P (34h): ") != std::string::npos);
    CHECK(restore.err.find("restore: 2 Set command(s) sent, verified: the controller matches "
                           "press6/controller.json@" +
                           head1->id.substr(0, 12) + "\n") != std::string::npos);
    auto record = archive->resolve("HEAD").value();
    REQUIRE(record);
    CHECK(record->summary == "fleet restore: press6/controller <- press6/controller.json at " +
                                 head1->id.substr(0, 12) + " (approved): restored and verified");
    CHECK(record->message.find("\nline can-gw (" + gw.port +
                               "), DeviceNet MAC ID 07h, 2 Set command(s)\n") != std::string::npos);
    CHECK(test::run_tool_in(dir, "fleet status plant.toml --archive arch").exit_code == 0);

    // A change on the pty's controller: the next backup commits only its file.
    test::change_two_values(usb);
    auto next = test::run_tool_in(dir, "fleet backup plant.toml --archive arch");
    INFO(next.out << next.err);
    CHECK(next.exit_code == 0);
    auto head2 = archive->resolve("HEAD").value();
    REQUIRE(head2);
    CHECK(head2->summary == "fleet backup: 1 changed, 2 unchanged, 0 new, 0 failed");
    CHECK(head2->message.find("\nchanged press5/controller (line can-usb, DeviceNet MAC ID 05h): "
                              "2 DeviceNet values\n") != std::string::npos);

    // A LinRS-only restore option is refused for a controller, nothing written.
    auto comm =
        test::run_tool_in(dir,
                          "fleet restore plant.toml --archive arch --drive press5/controller --yes "
                          "--include-comm");
    CHECK(comm.exit_code == 2);
    CHECK(comm.err ==
          "lmcfg fleet restore: --include-comm, --no-default, --no-reset and --reconnect-* are "
          "LinRS options; a DeviceNet restore writes only the values that differ\n");
    CHECK(archive->resolve("HEAD").value()->id == head2->id);
  }
}

TEST_CASE("fleet: DeviceNet settings of a line are checked as the options, at the line",
          "[fleet][cli][devicenet]") {
  test::ScratchDir d("fleet-dn-bad");
  const auto& dir = d.path;
  test::spit(dir / "rate.toml",
             "[[line]]\nname = \"can\"\nport = \"vcan0\"\ncan_bitrate = 100000\n[[line.drive]]\n"
             "name = \"a\"\ndevicenet_macid = 5\n");
  auto rate = test::run_tool_in(dir, "fleet check rate.toml");
  CHECK(rate.exit_code == 2);
  CHECK(rate.err ==
        "lmcfg fleet check: rate.toml:1:1: line 'can': --can-bitrate 100000 is not a DeviceNet "
        "bit rate (125000, 250000, 500000)\n");
  test::spit(dir / "own.toml",
             "[[line]]\nname = \"can\"\nport = \"vcan0\"\ndevicenet_own_macid = 5\n"
             "[[line.drive]]\nname = \"a\"\ndevicenet_macid = 5\n");
  auto own = test::run_tool_in(dir, "fleet backup own.toml --archive arch");
  CHECK(own.exit_code == 2);
  CHECK(own.err ==
        "lmcfg fleet backup: own.toml:1:1: line 'can': --devicenet-own-macid 5 must be 0..63 and "
        "differ from the controller's MAC ID\n");
  CHECK_FALSE(fs::exists(dir / "arch"));
  test::spit(dir / "keys.toml",
             "[[line]]\nname = \"can\"\nport = \"slcan:tcp://127.0.0.1:9\"\nparity = \"even\"\n"
             "[[line.drive]]\nname = \"a\"\ndevicenet_macid = 5\n");
  auto keys = test::run_tool_in(dir, "fleet check keys.toml");
  CHECK(keys.exit_code == 2);
  CHECK(keys.err ==
        "lmcfg fleet check: keys.toml:4:1: 'parity' is a LinRS key, not for DeviceNet line 'can' "
        "(port 'slcan:tcp://127.0.0.1:9' is a CAN link)\n");
}

}  // namespace tools_test_fleet_cli
