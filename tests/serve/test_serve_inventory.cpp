// The inventory's service tables (docs/serve.md): [schedule] durations,
// [notify] and `ignore` lists, with the exact messages and positions of
// `lmcfg fleet check`.
#include <catch2/catch.hpp>

#include "fleet/inventory.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace serve_test_serve_inventory {

using namespace lmcfg;

namespace {
const std::string kLine = "[[line]]\nname = \"l1\"\nport = \"sim:a.json\"\n";
const std::string kDrive = "[[line.drive]]\nname = \"a\"\nid = 0x11\n";
}  // namespace

TEST_CASE("serve inventory: durations take s, m, h, d", "[serve][inventory]") {
  using std::chrono::seconds;
  CHECK(*fleet::parse_duration("30s") == seconds(30));
  CHECK(*fleet::parse_duration("15m") == seconds(900));
  CHECK(*fleet::parse_duration("6h") == seconds(21600));
  CHECK(*fleet::parse_duration("1d") == seconds(86400));
  for (const char* bad : {"", "h", "0m", "6", "6x", "-1h", "1.5h", "6 h", "1234567890s"}) {
    auto d = fleet::parse_duration(bad);
    REQUIRE_FALSE(d.ok());
    CHECK(d.error().message == "'" + std::string(bad) +
                                   "' is not a duration (a whole number > 0 and a unit s, m, h "
                                   "or d, e.g. \"15m\", \"6h\")");
  }
}

TEST_CASE("serve inventory: [schedule], [notify] and ignore lists load", "[serve][inventory]") {
  // An absolute path as the platform writes it (a TOML literal string: no escapes).
#ifdef _WIN32
  const std::string command = "C:\\lmcfg\\mail.cmd";
#else
  const std::string command = "/usr/local/bin/lmcfg-mail";
#endif
  const std::string text =
      "[schedule]\nbackup_every = \"6h\"\nstatus_every = \"15m\"\n"
      "[notify]\nwebhook = \"https://hooks.example/lmcfg\"\ncommand = '" +
      command + "'\n" + kLine + "ignore = [\"1037h\"]\n" + kDrive +
      "ignore = [\"0e00\", \"13A2h\"]\n";
  auto inv = fleet::parse_inventory(text, "plant.toml");
  REQUIRE(inv.ok());
  CHECK(inv->schedule.backup_every == std::chrono::hours(6));
  CHECK(inv->schedule.status_every == std::chrono::minutes(15));
  CHECK(inv->notify.webhook == "https://hooks.example/lmcfg");
  CHECK(inv->notify.command == command);
  CHECK(inv->lines[0].ignore == std::vector<std::uint16_t>{0x1037});
  CHECK(inv->lines[0].drives[0].ignore == std::vector<std::uint16_t>{0x0E00, 0x13A2});
  CHECK(fleet::ignored_upids(inv->lines[0], inv->lines[0].drives[0]) ==
        std::vector<std::uint16_t>{0x1037, 0x0E00, 0x13A2});
  // Without the tables: nothing scheduled, nobody notified.
  auto plain = fleet::parse_inventory(kLine + kDrive, "plant.toml");
  REQUIRE(plain.ok());
  CHECK_FALSE(plain->schedule.backup_every);
  CHECK_FALSE(plain->schedule.status_every);
  CHECK(plain->notify.webhook.empty());
}

TEST_CASE("serve inventory: every bad service key is named at its file:line:column",
          "[serve][inventory]") {
  const std::string text =
      "[schedule]\nbackup_every = \"6x\"\nstatus_every = 15\nevery = \"1h\"\n"
      "[notify]\nwebhook = \"ftp://x\"\ncommand = \"mail\"\n" +
      kLine + "ignore = [\"10370\", 4]\n" + kDrive + "ignore = \"1037h\"\n";
  auto inv = fleet::parse_inventory(text, "plant.toml");
  REQUIRE_FALSE(inv.ok());
  CHECK(inv.error().message ==
        "plant.toml:4:1: unknown key 'every' in [schedule] (known: backup_every, status_every)\n"
        "plant.toml:2:16: 'backup_every': '6x' is not a duration (a whole number > 0 and a unit "
        "s, m, h or d, e.g. \"15m\", \"6h\")\n"
        "plant.toml:3:16: 'status_every' must be a string such as \"6h\"\n"
        "plant.toml:6:11: 'webhook' must be an http:// or https:// URL, not 'ftp://x'\n"
        "plant.toml:7:11: 'command' must be an absolute path to a program, not 'mail'\n"
        "plant.toml:11:11: 'ignore': '10370' is not a UPID (4 hex digits, e.g. \"1037h\")\n"
        "plant.toml:11:20: 'ignore': a value is not a UPID (4 hex digits, e.g. \"1037h\")\n"
        "plant.toml:15:10: 'ignore' must be an array of UPIDs, e.g. [\"1037h\"]");
}

TEST_CASE("serve inventory: on_replaced per line and drive, require_reason at the top",
          "[serve][inventory]") {
  auto inv = fleet::parse_inventory("require_reason = true\n" + kLine +
                                        "on_replaced = \"restore\"\n" + kDrive +
                                        "[[line.drive]]\nname = \"b\"\nid = 0x12\non_replaced = "
                                        "\"notify\"\n",
                                    "plant.toml");
  REQUIRE(inv.ok());
  CHECK(inv->require_reason);
  const auto& line = inv->lines[0];
  CHECK(fleet::restore_when_replaced(line, line.drives[0]));        // the line's
  CHECK_FALSE(fleet::restore_when_replaced(line, line.drives[1]));  // its own
  auto plain = fleet::parse_inventory(kLine + kDrive, "plant.toml");
  REQUIRE(plain.ok());
  CHECK_FALSE(plain->require_reason);
  CHECK_FALSE(fleet::restore_when_replaced(plain->lines[0], plain->lines[0].drives[0]));

  auto bad =
      fleet::parse_inventory("require_reason = \"yes\"\n" + kLine + "on_replaced = \"reflash\"\n" +
                                 kDrive + "on_replaced = true\n",
                             "plant.toml");
  REQUIRE_FALSE(bad.ok());
  CHECK(bad.error().message ==
        "plant.toml:1:18: 'require_reason' must be true or false\n"
        "plant.toml:5:15: 'on_replaced' must be \"notify\" or \"restore\", not 'reflash'\n"
        "plant.toml:9:15: 'on_replaced' must be a string");
}

}  // namespace serve_test_serve_inventory
