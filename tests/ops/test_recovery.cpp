// Recovery records (lib/ops/recovery.cpp): where they live, how a drive is
// named on the host, the file written and read back, and the messages of a
// record that is damaged or cannot be written or deleted.
#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>

#include "files.hpp"
#include "ops/recovery.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace ops_test_recovery {

using namespace lmcfg;
namespace fs = std::filesystem;

namespace {

// Sets (or unsets, with nullopt) an environment variable for one scope and
// puts the previous value back afterwards.
class EnvVar {
 public:
  EnvVar(const char* name, std::optional<std::string> value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    if (value)
      lmcfg::test::set_env(name, value->c_str());
    else
      lmcfg::test::unset_env(name);
  }
  ~EnvVar() {
    if (old_)
      lmcfg::test::set_env(name_, old_->c_str());
    else
      lmcfg::test::unset_env(name_);
  }
  EnvVar(const EnvVar&) = delete;
  EnvVar& operator=(const EnvVar&) = delete;

 private:
  const char* name_;
  std::optional<std::string> old_;
};

}  // namespace

TEST_CASE("recovery: the directory is $XDG_STATE_HOME/lmcfg, else $HOME/.local/state/lmcfg",
          "[recovery]") {
  {
    EnvVar xdg("XDG_STATE_HOME", "/var/tmp/state");
    EnvVar home("HOME", "/home/op");
    auto d = ops::recovery_dir();
    REQUIRE(d.ok());
    CHECK(*d == fs::path("/var/tmp/state/lmcfg"));
  }
  {
    // A relative $XDG_STATE_HOME is invalid (XDG Base Directory specification): ignored.
    EnvVar xdg("XDG_STATE_HOME", "state");
    EnvVar home("HOME", "/home/op");
    auto d = ops::recovery_dir();
    REQUIRE(d.ok());
    CHECK(*d == fs::path("/home/op/.local/state/lmcfg"));
  }
  {
    EnvVar xdg("XDG_STATE_HOME", std::nullopt);
    EnvVar home("HOME", "");
    auto d = ops::recovery_dir();
    REQUIRE_FALSE(d.ok());
    CHECK(d.error().code == Errc::file_error);
    CHECK(d.error().message ==
          "no place for the recovery record: neither $XDG_STATE_HOME (absolute) nor $HOME is set");
  }
}

TEST_CASE("recovery: a drive is its port with every other character as _ and its MACID in hex",
          "[recovery]") {
  CHECK(ops::drive_key("/dev/ttyUSB0", 0x11) == "_dev_ttyUSB0-11h");
  CHECK(ops::drive_key("tcp://10.0.0.7:4001", 0x0A) == "tcp___10.0.0.7_4001-0Ah");
  CHECK(ops::drive_key("sim:a.json,b.json", 0xFF) == "sim_a.json_b.json-FFh");
  CHECK(ops::drive_key("", 0) == "-00h");
  EnvVar xdg("XDG_STATE_HOME", "/s");
  auto p = ops::recovery_path("restore", "/dev/ttyUSB0", 0x11);
  REQUIRE(p.ok());
  CHECK(*p == fs::path("/s/lmcfg/restore-_dev_ttyUSB0-11h.json"));
  auto l = ops::recovery_path("link", "/dev/ttyS1", 0x3F);
  REQUIRE(l.ok());
  CHECK(*l == fs::path("/s/lmcfg/link-_dev_ttyS1-3Fh.json"));
}

TEST_CASE("recovery: a record is written as docs/restore.md shows it and read back", "[recovery]") {
  test::ScratchDir dir("recovery");
  // The directory does not exist yet: saving creates it.
  const fs::path path = dir.path / "lmcfg" / "default-_dev_ttyUSB0-11h.json";
  ops::RecoveryRecord rec{
      "default", "/dev/ttyUSB0", 0x11, "2026-11-23T16:00:00Z", {{0x200E, 2}, {0x2076, 0x11}}, "",
      {}};
  REQUIRE(ops::save_recovery(path, rec).ok());
  CHECK(test::slurp(path) ==
        "{\n"
        "  \"command\": \"default\",\n"
        "  \"port\": \"/dev/ttyUSB0\",\n"
        "  \"macid\": 17,\n"
        "  \"created\": \"2026-11-23T16:00:00Z\",\n"
        "  \"keep\": [\n"
        "    {\n"
        "      \"upid\": \"200E\",\n"
        "      \"value\": 2\n"
        "    },\n"
        "    {\n"
        "      \"upid\": \"2076\",\n"
        "      \"value\": 17\n"
        "    }\n"
        "  ]\n"
        "}\n");
  auto back = ops::load_recovery(path);
  REQUIRE(back.ok());
  REQUIRE(back->has_value());
  const auto& r = **back;
  CHECK(r.command == "default");
  CHECK(r.port == "/dev/ttyUSB0");
  CHECK(r.macid == 0x11);
  CHECK(r.created == "2026-11-23T16:00:00Z");
  CHECK(r.expect.empty());
  REQUIRE(r.keep.size() == 2);
  CHECK(r.keep[0].upid == 0x200E);
  CHECK(r.keep[0].value == 2);
  CHECK(r.keep[1].upid == 0x2076);
  CHECK(r.keep[1].value == 0x11);

  // `expect` only when set; a record with nothing to keep has an empty list.
  ops::RecoveryRecord link{
      "link", "/dev/ttyS1", 0x3F, "2026-11-23T16:00:00Z", {}, "--baud 115200 --id 0x3F", {}};
  const fs::path lpath = dir.path / "lmcfg" / "link.json";
  REQUIRE(ops::save_recovery(lpath, link).ok());
  const auto text = test::slurp(lpath);
  CHECK(text.find("\"expect\": \"--baud 115200 --id 0x3F\",\n  \"keep\": []") != std::string::npos);
  auto lback = ops::load_recovery(lpath);
  REQUIRE(lback.ok());
  REQUIRE(lback->has_value());
  CHECK((*lback)->expect == "--baud 115200 --id 0x3F");
  CHECK((*lback)->keep.empty());

  // The example of docs/restore.md, as a person would find it on disk.
  const fs::path doc = dir.path / "doc.json";
  test::spit(doc,
             "{\"command\": \"default\", \"port\": \"/dev/ttyUSB0\", \"macid\": 17,\n"
             " \"created\": \"2026-11-23T16:00:00Z\", \"keep\": [{\"upid\": \"200E\", "
             "\"value\": 2}]}\n");
  auto d = ops::load_recovery(doc);
  REQUIRE(d.ok());
  REQUIRE(d->has_value());
  REQUIRE((*d)->keep.size() == 1);
  CHECK((*d)->keep[0].upid == 0x200E);
  CHECK((*d)->keep[0].value == 2);

  // Deleted once finished; deleting a record that is gone is no error.
  REQUIRE(ops::remove_recovery(path).ok());
  CHECK_FALSE(fs::exists(path));
  CHECK(ops::remove_recovery(path).ok());
}

TEST_CASE("recovery: no record is nullopt, a damaged one an error naming the file", "[recovery]") {
  test::ScratchDir dir("recovery-damaged");
  auto none = ops::load_recovery(dir.path / "absent.json");
  REQUIRE(none.ok());
  CHECK_FALSE(none->has_value());

  const fs::path bad = dir.path / "bad.json";
  test::spit(bad, "{\"command\": \"default\", \"port\": \"/dev/ttyUSB0\"}");
  auto r = ops::load_recovery(bad);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == Errc::parse_error);
  const std::string& m = r.error().message;
  CHECK(m.rfind(bad.string() + ": damaged recovery record (", 0) == 0);
  CHECK(m.find("macid") != std::string::npos);  // the missing member
  const std::string tail = "); expected the JSON lmcfg wrote. Inspect it, then delete it to go on";
  REQUIRE(m.size() > tail.size());
  CHECK(m.substr(m.size() - tail.size()) == tail);

  test::spit(bad, "not json");
  auto t = ops::load_recovery(bad);
  REQUIRE_FALSE(t.ok());
  CHECK(t.error().code == Errc::parse_error);
  CHECK(t.error().message.rfind(bad.string() + ": damaged recovery record (", 0) == 0);
}

TEST_CASE("recovery: a value that does not fit its field is damage, never written truncated",
          "[recovery]") {
  test::ScratchDir dir("recovery-fields");
  const fs::path bad = dir.path / "bad.json";
  const std::string tail = "); expected the JSON lmcfg wrote. Inspect it, then delete it to go on";
  auto damaged = [&](const std::string& macid, const std::string& keep) {
    test::spit(bad, "{\"command\": \"default\", \"port\": \"p\", \"macid\": " + macid +
                        ", \"created\": \"x\", \"keep\": [{\"upid\": \"200E\", \"value\": 2}, " +
                        keep + "]}");
    auto r = ops::load_recovery(bad);
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().code == Errc::parse_error);
    return r.error().message;
  };
  const std::string head = bad.string() + ": damaged recovery record (";
  // A UPID of five digits would otherwise be written to 2345h.
  CHECK(damaged("17", R"({"upid": "12345", "value": 2})") ==
        head + "keep[1].upid is \"12345\", expected 4 hexadecimal digits (\"200E\")" + tail);
  CHECK(damaged("17", R"({"upid": "zz", "value": 2})") ==
        head + "keep[1].upid is \"zz\", expected 4 hexadecimal digits (\"200E\")" + tail);
  CHECK(damaged("17", R"({"upid": 8206, "value": 2})") ==
        head + "keep[1].upid is 8206, expected 4 hexadecimal digits (\"200E\")" + tail);
  // A negative value would otherwise be written as 4294967295.
  CHECK(damaged("17", R"({"upid": "2012", "value": -1})") ==
        head + "keep[1].value is -1, expected an integer 0..4294967295" + tail);
  CHECK(damaged("17", R"({"upid": "2012", "value": 4294967296})") ==
        head + "keep[1].value is 4294967296, expected an integer 0..4294967295" + tail);
  CHECK(damaged("17", R"({"upid": "2012", "value": 2.5})") ==
        head + "keep[1].value is 2.5, expected an integer 0..4294967295" + tail);
  // A MACID of 300 would otherwise be read as 2Ch.
  CHECK(damaged("300", R"({"upid": "2012", "value": 8})") ==
        head + "macid is 300, expected an integer 0..255" + tail);
}

TEST_CASE("recovery: a directory that cannot be created or a record that cannot be deleted",
          "[recovery]") {
  test::ScratchDir dir("recovery-unwritable");
  // A file where the directory should be.
  const fs::path blocker = dir.path / "lmcfg";
  test::spit(blocker, "");
  ops::RecoveryRecord rec{"restore", "/dev/ttyUSB0", 0x11, "2026-11-23T16:00:00Z", {}, "", {}};
  auto s = ops::save_recovery(blocker / "restore-_dev_ttyUSB0-11h.json", rec);
  REQUIRE_FALSE(s.ok());
  CHECK(s.error().code == Errc::file_error);
  CHECK(s.error().message.rfind(blocker.string() + ": cannot create the recovery directory: ", 0) ==
        0);

  // A non-empty directory in place of the record: fs::remove fails.
  const fs::path stuck = dir.path / "stuck.json";
  fs::create_directories(stuck / "inside");
  auto r = ops::remove_recovery(stuck);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == Errc::file_error);
  CHECK(r.error().message.rfind(stuck.string() + ": cannot delete the finished recovery record: ",
                                0) == 0);
}

}  // namespace ops_test_recovery
