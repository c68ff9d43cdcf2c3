// docs/reliability.md promises 8 and 9 (bad input, failed backups) through the real tool binary
// (LMCFG_TOOL_PATH) and the built-in simulated drive (--port sim:STATE.json, copied to a temp dir):
// every bad input gives one clear message naming the problem and where it is,
// the documented exit code (2 invalid input, 3 plan refused), no write
// telegram on the wire (the --trace TX lines, decoded) and no file written or
// changed. A backup that fails midway leaves an existing file byte-identical;
// restore never modifies its input file.
#include <sys/wait.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "client/client.hpp"
#include "codec/frame.hpp"
#include "common/bytes.hpp"
#include "common/result.hpp"
#include "files.hpp"
#include "sim/state_file.hpp"
#include "subprocess.hpp"
#include "trace_support.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace tools_test_reliability_cli {

using namespace lmcfg;
using test::slurp;
using test::spit;
using test::traced_requests;
using test::traced_writes;
namespace fs = std::filesystem;

namespace {

struct BadFile {
  const char* file;
  Errc code;
  bool schema_rejects;
  const char* message;
};
const BadFile kBadFiles[] = {
#include "../fixtures/config/bad/expected.inc"
};

using Run = test::ToolRun;

// Runs `lmcfg ARGS` in `dir`; stdout and stderr to files, recovery records
// (ops/recovery.hpp) inside the test's directory.
Run tool(const fs::path& dir, const std::string& args) { return test::run_tool_in(dir, args); }

struct TempDir : test::ScratchDir {
  TempDir() : ScratchDir("rel") {
    fs::create_directories(path / "bad");
    fs::copy_file(fs::path(LMCFG_SOURCE_DIR) / "tests/fixtures/sim/used-spare.json",
                  path / "spare.json");
    fs::copy_file(fs::path(LMCFG_SOURCE_DIR) / "tests/fixtures/sim/commissioned-axis.json",
                  path / "axis.json");
  }
};

sim::DriveState state_of(const fs::path& p) {
  auto s = sim::load_state(p.string());
  REQUIRE(s.ok());
  return std::move(s).value();
}
bool same_config(const sim::DriveState& a, const sim::DriveState& b) {
  return a.params == b.params && a.curves_flash == b.curves_flash && a.ct_flash == b.ct_flash &&
         a.curves_ram == b.curves_ram && a.ct_ram == b.ct_ram;
}

// A good backup of the commissioned axis, made by the tool itself.
std::string good_backup(TempDir& d) {
  auto r = tool(d.path, "backup --port sim:axis.json -q -o good.json");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  return slurp(d.path / "good.json");
}

}  // namespace

TEST_CASE("cli: every bad configuration file is refused before the link opens",
          "[reliability][cli]") {
  TempDir d;
  const auto spare_before = state_of(d.path / "spare.json");
  std::size_t n = 0;
  for (const auto& b : kBadFiles) {
    DYNAMIC_SECTION(b.file) {
      const fs::path src = fs::path(LMCFG_SOURCE_DIR) / "tests/fixtures/config/bad" / b.file;
      fs::copy_file(src, d.path / "bad" / b.file, fs::copy_options::overwrite_existing);
      const std::string before = slurp(d.path / "bad" / b.file);
      fs::remove(d.path / "t.trace");
      auto r = tool(
          d.path, std::string("restore bad/") + b.file + " --port sim:spare.json --trace t.trace");
      INFO(r.err);
      CHECK(r.exit_code == 2);
      CHECK(r.err ==
            std::string("lmcfg restore: ") + b.message + "\n");  // one clear line: what and where
      CHECK(traced_writes(d.path / "t.trace") == 0);
      CHECK(slurp(d.path / "bad" / b.file) == before);
      CHECK(same_config(state_of(d.path / "spare.json"), spare_before));
      // diff reads the same file the same way.
      auto df = tool(d.path, std::string("diff defaults bad/") + b.file);
      CHECK(df.exit_code == 2);
      CHECK(df.err == std::string("lmcfg diff: ") + b.message + "\n");
      ++n;
    }
  }
  CHECK(n <= std::size(kBadFiles));
}

TEST_CASE("cli: files the drive cannot take are refused by the plan, nothing written",
          "[reliability][cli]") {
  TempDir d;
  const std::string good = good_backup(d);
  struct Case {
    const char* name;
    std::function<void(nlohmann::json&)> spoil;
    int exit_code;
    const char* expected;  // in stderr
  };
  auto mc = [](nlohmann::json& j) -> nlohmann::json& {
    for (auto& l : j["parameters"])
      if (l["layer"] == 2) return l["params"];
    throw std::runtime_error("no MC layer in the backup");
  };
  const std::vector<Case> cases{
      {"unknown UPID",
       [&](auto& j) {
         mc(j).push_back({{"upid", "1EEE"}, {"value", 1}});
       },
       3, "MC 1EEEh: UPID does not exist on the target (not in its MC UPID list, §10.3)"},
      {"read-only UPID (address usage from the UPID database)",
       [&](auto& j) {
         for (auto& l : j["parameters"])
           if (l["layer"] == 3) l["params"].push_back({{"upid", "2136"}, {"value", 1}});
       },
       3,
       "Intf 2136h: read-only on the target (the UPID database's address usage 1001h has no ROM "
       "write bit)"},
      {"read-only UPID (address usage from the target's UPID list)",
       [&](auto& j) {
         for (auto& l : j["parameters"])
           if (l["layer"] == 1) l["params"].push_back({{"upid", "0E00"}, {"value", 1}});
       },
       3,
       "OS 0E00h: read-only on the target (the target's address usage 1001h has no ROM write bit)"},
      {"value out of range for its type",
       [&](auto& j) {
         for (auto& p : mc(j))
           if (p["upid"] == "13A2") p["value"] = 0x10000;
       },
       3, "value 10000h does not fit type UINT16"},
      {"wrong type", [&](auto& j) { mc(j)[0]["type"] = 6; }, 3,
       "type differs: the file has SINT32"},
      {"command table entry of the wrong size",
       [&](auto& j) {
         auto& raw = j["command_table"][0]["raw"];
         raw.erase(raw.size() - 1);
       },
       3, "bytes, expected 64"},
  };
  for (const auto& c : cases) {
    DYNAMIC_SECTION(c.name) {
      auto j = nlohmann::json::parse(good);
      c.spoil(j);
      spit(d.path / "spoiled.json", j.dump(2));
      const std::string before = slurp(d.path / "spoiled.json");
      const auto spare_before = state_of(d.path / "spare.json");
      fs::remove(d.path / "t.trace");
      auto r = tool(d.path, "restore spoiled.json --port sim:spare.json --trace t.trace");
      INFO(r.err);
      CHECK(r.exit_code == c.exit_code);
      CHECK(r.err.find(c.expected) != std::string::npos);
      CHECK(traced_writes(d.path / "t.trace") == 0);
      CHECK(slurp(d.path / "spoiled.json") == before);
      CHECK(same_config(state_of(d.path / "spare.json"), spare_before));
    }
  }
}

TEST_CASE("cli: absurd option values are refused with exit 2 and nothing on the wire",
          "[reliability][cli]") {
  TempDir d;
  const std::string good = good_backup(d);
  spit(d.path / "existing.json", good);
  fs::create_directories(d.path / "adir");
  fs::create_directories(d.path / "adir.json");
  struct Case {
    const char* args;
    const char* expected;
  };
  const std::vector<Case> cases{
      // (--baud is checked for serial ports; the simulated drive takes its line
      // settings from its state file and ignores --baud.)
      {"backup --port /dev/lmcfg-no-such-tty --baud 0 -o out.json", "baud"},
      {"backup --port sim:spare.json --id 300 -o out.json",
       "--id '300' is not a MACID 0..255 (0x00..0xFF)"},
      {"backup --port sim:spare.json --id 0x1FF -o out.json", "--id '0x1FF' is not a MACID"},
      {"backup --port sim:spare.json -o adir.json",
       "output 'adir.json' is a directory; name a file"},
      {"backup --port sim:spare.json -o out.txt", "out.txt"},
      {"backup --port sim:spare.json --timeout-ms 0 -o out.json",
       "--timeout-ms 0 is outside 1..60000"},
      {"backup --port sim:spare.json --settle-ms 0 -o out.json",
       "--settle-ms 0 is outside 1..60000"},
      {"backup --port sim:spare.json --retries 99 -o out.json", "--retries 99 is outside 0..10"},
      {"backup --port sim:spare.json --agreeing-reads 0 -o out.json",
       "--agreeing-reads '0' is not auto or 1..5"},
      {"backup --port sim:spare.json --agreeing-reads twice -o out.json",
       "--agreeing-reads 'twice' is not auto or 1..5"},
      {"backup --port sim:spare.json --checksum sha1 -o out.json",
       "checksum 'sha1' is not one of none, add, crc, crc-ffff, crc-0000"},
      {"backup --port sim:spare.json --parity maybe -o out.json",
       "parity 'maybe' is not one of none, even, odd"},
      {"backup --port sim:spare.json --layers os,xyz -o out.json",
       "--layers: 'xyz' is not one of os, mc, intf, appl"},
      {"restore existing.json --port /dev/lmcfg-no-such-tty --baud 0", "baud"},
      {"restore existing.json --port sim:spare.json --id 300", "--id '300' is not a MACID"},
      {"restore missing.json --port sim:spare.json", "missing.json"},
      {"restore existing.json --port sim:spare.json --include-comm --reconnect-baud 12345",
       "--reconnect-baud: unsupported baud rate 12345"},
      {"restore existing.json --port sim:spare.json --include-comm --reconnect-id 0x100",
       "--reconnect-id '0x100' is not a MACID 0..255 (0x00..0xFF)"},
      {"restore existing.json --port sim:spare.json --include-comm --reconnect-checksum md5",
       "--reconnect-checksum: checksum 'md5' is not one of none, add, crc, crc-ffff, crc-0000"},
      {"restore adir --port sim:spare.json", "adir"},
      {"diff existing.json drive --port sim:spare.json --id 300", "--id '300' is not a MACID"},
  };
  const auto spare_before = state_of(d.path / "spare.json");
  for (const auto& c : cases) {
    DYNAMIC_SECTION(c.args) {
      fs::remove(d.path / "t.trace");
      const std::string before = slurp(d.path / "existing.json");
      auto r = tool(d.path, std::string(c.args) + " --trace t.trace");
      INFO(r.err);
      CHECK(r.exit_code == 2);
      CHECK(r.err.find(c.expected) != std::string::npos);
      // One message line (CLI11 errors may add a "Run with --help" hint line).
      CHECK(r.err.find("lmcfg") != std::string::npos);
      CHECK(traced_writes(d.path / "t.trace") == 0);
      CHECK_FALSE(fs::exists(d.path / "out.json"));
      CHECK(slurp(d.path / "existing.json") == before);
      CHECK(same_config(state_of(d.path / "spare.json"), spare_before));
    }
  }
}

TEST_CASE("cli: a backup that fails midway leaves the existing file byte-identical",
          "[reliability][cli]") {
  TempDir d;
  const std::string old = good_backup(d);
  // A drive whose Appl layer holds no modified parameter and that refuses
  // the empty list (C4): the backup has read three layers, then fails.
  auto j = nlohmann::json::parse(slurp(d.path / "axis.json"));
  j["options"]["empty_list_state"] = "C4";
  for (auto& p : j["parameters"]) {
    if (p["upid"].get<std::string>().rfind('3', 0) != 0 || !p.contains("default")) continue;
    p["rom"] = p["default"];
    p["ram"] = p["default"];
  }
  spit(d.path / "refusing.json", j.dump(2));
  auto r = tool(d.path, "backup --port sim:refusing.json -o good.json --trace t.trace");
  INFO(r.err);
  CHECK(r.exit_code == 5);  // the drive refused
  CHECK(r.err.find("lmcfg backup: ") == 0);
  CHECK(slurp(d.path / "good.json") == old);
  CHECK(traced_writes(d.path / "t.trace") == 0);
  // No temporary file left behind next to it.
  std::size_t files = 0;
  for (const auto& e : fs::directory_iterator(d.path))
    files += e.path().filename().string().find("good.json") != std::string::npos;
  CHECK(files == 1);
  // A drive that does not answer at all (wrong MACID): communication failure, file kept.
  auto t = tool(d.path, "backup --port sim:axis.json --id 0x22 --timeout-ms 5 -o good.json");
  CHECK(t.exit_code == 4);
  CHECK(slurp(d.path / "good.json") == old);
}

// docs/reliability.md: auto reads each value twice on a link without checksum
// (three once it corrupted an answer); --agreeing-reads N fixes N.
TEST_CASE("cli: --agreeing-reads fixes the reads per value, and the backup says so",
          "[reliability][cli]") {
  TempDir d;
  const auto telegrams = [&](const char* trace) {
    return test::traced_requests(d.path / trace).size();
  };
  auto two = tool(d.path, "backup --port sim:axis.json -o two.json --trace two.trace");
  INFO(two.err);
  REQUIRE(two.exit_code == 0);
  CHECK(two.err.find("backup: no checksum on this link: each value read twice; enable CRC on the "
                     "drive (§15) to halve backup time\n") != std::string::npos);
  auto three = tool(d.path,
                    "backup --port sim:axis.json -o three.json --trace three.trace "
                    "--agreeing-reads 3");
  INFO(three.err);
  REQUIRE(three.exit_code == 0);
  CHECK(three.err.find("backup: no checksum on this link: each value read until 3 reads agreed "
                       "(--agreeing-reads 3)\n") != std::string::npos);
  auto one = tool(d.path,
                  "backup --port sim:axis.json -o one.json --trace one.trace "
                  "--agreeing-reads 1");
  INFO(one.err);
  REQUIRE(one.exit_code == 0);
  CHECK(one.err.find("backup: no checksum on this link and --agreeing-reads 1: a flipped bit in a "
                     "value goes into the file undetected; enable CRC on the drive (§15)\n") !=
        std::string::npos);
  // The same configuration each time; the reads follow the option. Empty
  // curve IDs take min(N, 2) reads (two flips away from a curve's answer), an
  // empty modified list at least two passes whatever N.
  CHECK(tool(d.path, "diff two.json three.json").exit_code == 0);
  CHECK(tool(d.path, "diff two.json one.json").exit_code == 0);
  const std::size_t t1 = telegrams("one.trace"), t2 = telegrams("two.trace"),
                    t3 = telegrams("three.trace");
  CHECK(t2 >= 2 * t1);
  CHECK(t3 > t2);
  CHECK(t3 < 3 * t1);
}

TEST_CASE("cli: restore never modifies its input file", "[reliability][cli]") {
  TempDir d;
  good_backup(d);
  const std::string before = slurp(d.path / "good.json");
  const auto mtime = fs::last_write_time(d.path / "good.json");
  auto dry = tool(d.path, "restore good.json --port sim:spare.json --dry-run -q --trace t.trace");
  CHECK(dry.exit_code == 0);
  CHECK(traced_writes(d.path / "t.trace") == 0);
  auto r = tool(d.path, "restore good.json --port sim:spare.json -q --yes");
  INFO(r.err);
  CHECK(r.exit_code == 0);
  // An interrupted one too (drive answers nothing: wrong MACID).
  auto bad = tool(d.path, "restore good.json --port sim:spare.json --id 0x22 --timeout-ms 5 -q");
  CHECK(bad.exit_code == 4);
  CHECK(slurp(d.path / "good.json") == before);
  CHECK(fs::last_write_time(d.path / "good.json") == mtime);
  // And the restored spare now backs up to the same configuration.
  auto again =
      tool(d.path, "diff good.json drive --port sim:spare.json --ignore-metadata --ignore-unit");
  INFO(again.out << again.err);
  CHECK(again.exit_code == 0);
}

TEST_CASE("cli: db devicenet shows seed 000 commands, a bad ID is exit 2, an undefined one a note",
          "[reliability][cli][db]") {
  TempDir d;
  auto one = tool(d.path, "db devicenet 0x11 --json");
  REQUIRE(one.exit_code == 0);
  auto j = nlohmann::json::parse(one.out);
  CHECK(j["name"] == "Set Position Setpoint");
  CHECK(j["value"]["unit"] == "mm");
  auto bad = tool(d.path, "db devicenet zz");
  CHECK(bad.exit_code == 2);
  CHECK(bad.err == "lmcfg db devicenet: 'zz' is not a command ID 00..7F (hex: 11, 0x11, 11h)\n");
  auto undefined = tool(d.path, "db devicenet 7F");
  CHECK(undefined.exit_code == 0);
  CHECK(
      undefined.out ==
      "DeviceNet command 7Fh: not in the database (seed 000 §5.2 Table 5-1 does not define it)\n");
  auto all = tool(d.path, "db devicenet --params --json");
  REQUIRE(all.exit_code == 0);
  CHECK(nlohmann::json::parse(all.out).size() == 13);
}

TEST_CASE("cli: get and set ask the drive what the database does not know, and say so",
          "[reliability][cli]") {
  TempDir d;
  // 0020h is not in the database; the drive reports UINT32.
  auto get = tool(d.path, "get 0020 --port sim:axis.json --rom");
  CHECK(get.exit_code == 0);
  CHECK(get.out == "0020 (not in database) [ROM] = 1000\n");
  CHECK(get.err == "lmcfg get: 0020 is not in the database; asked the drive: type UINT32\n");
  // 11F2h is named by the database but not typed: SINT16 from the drive, shown signed.
  auto neg = tool(d.path, "set 11F2 -20 --port sim:axis.json");
  CHECK(neg.exit_code == 0);
  CHECK(neg.out == "11F2 Phase Angle [RAM] = -20\n");
  CHECK(neg.err ==
        "lmcfg set: 11F2 is only partly described by the database; asked the drive: type SINT16, "
        "min, max\n");
  // The drive's own limits are applied before anything is written.
  auto out_of_range = tool(d.path, "set 11F2 -40000 --port sim:axis.json -q --trace t.trace");
  CHECK(out_of_range.exit_code == 2);
  CHECK(out_of_range.err == "lmcfg set: value -40000 is outside the SINT16 range -32768..32767\n");
  CHECK(traced_writes(d.path / "t.trace") == 0);
  // A UPID the drive does not know either: the refusal names the request.
  auto unknown = tool(d.path, "get 5555 --port sim:axis.json");
  CHECK(unknown.exit_code == 5);
  CHECK(unknown.err ==
        "lmcfg get: drive 11h refused ID 11h parameter (main 03h sub 00h), 2 data byte(s) for UPID "
        "5555h: C8h "
        "parameter unknown UPID\n"
        // LinRS §15: after a refusal, the drive's error state with its text.
        "lmcfg get: after the refusal: drive state: 8 Operation Enabled (state var 08C2h), status "
        "word 4C37h; actual error: No Error\n");
}

// ---- Restore you can trust (LinRS §10, §11, §12; docs/restore.md) ----

namespace {

std::size_t count_requests(const std::vector<codec::Telegram>& ts, std::uint8_t main,
                           std::optional<std::uint8_t> sub = std::nullopt, bool writes = false) {
  return static_cast<std::size_t>(std::count_if(ts.begin(), ts.end(), [&](const auto& t) {
    return t.main == main && (!sub || t.sub == *sub) && (!writes || codec::is_write_request(t));
  }));
}

// Sets one field of a parameter in a simulator state file.
void set_param_field(const fs::path& state, const char* upid, const char* field, std::uint32_t v) {
  auto j = nlohmann::json::parse(slurp(state));
  bool found = false;
  for (auto& p : j["parameters"])
    if (p["upid"] == upid) {
      p[field] = v;
      found = true;
    }
  REQUIRE(found);
  spit(state, j.dump(2));
}

}  // namespace

TEST_CASE(
    "seed003 §10 05h 05h/06h: the plan takes min/max from the target, a lower max is "
    "refused by dry run and real run, zero write telegrams",
    "[reliability][cli][restore]") {
  TempDir d;
  good_backup(d);  // 13A2h = 40 in the file
  set_param_field(d.path / "spare.json", "13A2", "max", 30);
  const auto spare_before = state_of(d.path / "spare.json");
  for (const char* extra : {" --dry-run", " --yes"}) {
    DYNAMIC_SECTION(extra) {
      fs::remove(d.path / "t.trace");
      auto r = tool(d.path,
                    std::string("restore good.json --port sim:spare.json --trace t.trace") + extra);
      INFO(r.err);
      CHECK(r.exit_code == 3);
      CHECK(r.err.find("MC 13A2h") != std::string::npos);
      CHECK(r.err.find("(as the target reports it, §10 05h 05h/06h)") != std::string::npos);
      CHECK(traced_writes(d.path / "t.trace") == 0);
      CHECK(same_config(state_of(d.path / "spare.json"), spare_before));
    }
  }
}

TEST_CASE("restore of a drive's own backup onto it: nothing to do, no write, MC never stopped",
          "[reliability][cli][restore]") {
  TempDir d;
  good_backup(d);
  const auto before = state_of(d.path / "axis.json");
  auto r = tool(d.path, "restore good.json --port sim:axis.json --yes --trace t.trace");
  INFO(r.err);
  CHECK(r.exit_code == 0);
  CHECK(r.out == "nothing to do: the drive already matches good.json\n");
  const auto sent = traced_requests(d.path / "t.trace");
  CHECK(traced_writes(d.path / "t.trace") == 0);
  CHECK(count_requests(sent, 0x06) == 0);        // no MC stop, start or reset (§13)
  CHECK(count_requests(sent, 0x04, 0x00) == 0);  // no curve flash save (§11)
  CHECK(count_requests(sent, 0x08, 0x00) == 0);  // no command table flash save (§12)
  CHECK(same_config(state_of(d.path / "axis.json"), before));
  CHECK(state_of(d.path / "axis.json").mc_running);
  // JSON: the same outcome as a structured report.
  auto j = tool(d.path, "restore good.json --port sim:axis.json --yes --json");
  CHECK(j.exit_code == 0);
  CHECK(nlohmann::json::parse(j.out)["outcome"] == "nothing to do");
}

TEST_CASE("restore onto a drive that differs in one curve: only that curve, one curve flash save",
          "[reliability][cli][restore]") {
  TempDir d;
  good_backup(d);
  auto j = nlohmann::json::parse(slurp(d.path / "axis.json"));
  const int changed_id = j["curves"]["flash"][0]["id"];
  for (const char* where : {"flash", "ram"}) {  // the simulator's state file keeps both
    auto& data = j["curves"][where][0]["data"];
    REQUIRE(j["curves"][where][0]["id"] == changed_id);
    std::string hex = data.get<std::string>();
    hex[1] = hex[1] == '1' ? '2' : '1';  // one setpoint differs
    data = hex;
  }
  spit(d.path / "other.json", j.dump(2));
  auto r = tool(d.path, "restore good.json --port sim:other.json --yes --trace t.trace");
  INFO(r.err);
  INFO(r.out);
  CHECK(r.exit_code == 0);
  const auto sent = traced_requests(d.path / "t.trace");
  CHECK(count_requests(sent, 0x05, 0x01) == 0);                // no ROM write
  CHECK(count_requests(sent, 0x08, std::nullopt, true) == 0);  // command table: reads only
  CHECK(count_requests(sent, 0x04, 0x00) == 1);                // one curve flash save
  CHECK(count_requests(sent, 0x04, 0x01) == 0);                // no "delete all curves"
  CHECK(count_requests(sent, 0x04, 0x02) == 1);                // that curve deleted ...
  CHECK(count_requests(sent, 0x04, 0x04) == 1);                // ... and added again
  CHECK(count_requests(sent, 0x06, 0x01) + count_requests(sent, 0x06, 0x02) == 0);  // no reset
  for (const auto& t : sent)
    if (t.main == 0x04 && (t.sub == 0x02 || t.sub == 0x04)) {
      REQUIRE(t.data.size() >= 2);
      CHECK(t.data[0] + 256 * t.data[1] == changed_id);
    }
  const auto after = state_of(d.path / "other.json");
  CHECK(after.curves_flash == state_of(d.path / "axis.json").curves_flash);
  CHECK(after.mc_running);
}

TEST_CASE("restore without --yes and without a terminal: exit 2, nothing written",
          "[reliability][cli][restore]") {
  TempDir d;
  good_backup(d);
  const auto spare_before = state_of(d.path / "spare.json");
  auto r = tool(d.path, "restore good.json --port sim:spare.json --trace t.trace");
  CHECK(r.exit_code == 2);
  CHECK(r.err.find("refusing to restore good.json onto a drive without --yes when stdin is not a "
                   "terminal; nothing written") != std::string::npos);
  CHECK(traced_writes(d.path / "t.trace") == 0);
  CHECK(same_config(state_of(d.path / "spare.json"), spare_before));
}

TEST_CASE(
    "restore and default --json validate against schemas/report-restore and report-default "
    "(real ajv), restore steps are items with UPID, old and new",
    "[reliability][cli][restore][json]") {
  TempDir d;
  good_backup(d);
  auto valid = [&](const char* schema, const std::string& json) {
    spit(d.path / "report.json", json);
    const auto ajv = fs::path(LMCFG_SOURCE_DIR) / "tools/node/node_modules/.bin/ajv";
    const auto s = fs::path(LMCFG_SOURCE_DIR) / "schemas" / schema;
    const std::string cmd = "'" + ajv.string() + "' validate --spec=draft2020 --strict=true -s '" +
                            s.string() + "' -d '" + (d.path / "report.json").string() +
                            "' >/dev/null 2>&1";
    return std::system(cmd.c_str()) == 0;
  };
  auto dry = tool(d.path, "restore good.json --port sim:spare.json --dry-run --json");
  INFO(dry.err);
  REQUIRE(dry.exit_code == 0);
  CHECK(valid("report-restore.schema.json", dry.out));
  const auto j = nlohmann::json::parse(dry.out);
  CHECK(j["outcome"] == "dry run");
  bool saw_write = false;
  for (const auto& s : j["steps"])
    if (s["action"] == "write_rom" && s["upid"] == "13A2") {
      saw_write = true;
      CHECK(s["old"]["raw"] == 25);  // the spare's value
      CHECK(s["new"]["raw"] == 40);  // the file's
    }
  CHECK(saw_write);
  auto real = tool(d.path, "restore good.json --port sim:spare.json --yes --json");
  INFO(real.err);
  CHECK(real.exit_code == 0);
  CHECK(valid("report-restore.schema.json", real.out));
  CHECK(nlohmann::json::parse(real.out)["outcome"] == "restored and verified");
  auto again = tool(d.path, "restore good.json --port sim:spare.json --yes --json");
  CHECK(valid("report-restore.schema.json", again.out));
  CHECK(nlohmann::json::parse(again.out)["outcome"] == "nothing to do");
  CHECK_FALSE(valid("report-restore.schema.json", "{\"outcome\": \"done\"}"));  // the schema bites
  auto def = tool(d.path, "default --port sim:spare.json --layers intf --yes --json");
  INFO(def.err);
  CHECK(def.exit_code == 0);
  CHECK(valid("report-default.schema.json", def.out));
  const auto kept = nlohmann::json::parse(def.out)["kept"];
  CHECK_FALSE(kept.empty());  // the spare's LinRS source selects, written back
  for (const auto& k : kept)
    CHECK(
        (k["upid"] == "200E" || k["upid"] == "2012" || k["upid"] == "206C" || k["upid"] == "2076"));
}

}  // namespace tools_test_reliability_cli
