// lmcfg serve as a process: the loopback-only refusal, token add, and a real
// service on an ephemeral port queried with curl, stopped by SIGTERM (exit 0).
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <thread>

#include "files.hpp"
#include "ops/recovery.hpp"
#include "serve_rig.hpp"
#include "subprocess.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace tools_test_serve_cli {

using namespace lmcfg;
namespace fs = std::filesystem;

namespace {

std::string curl(const fs::path& dir, const std::string& args) {
  const std::string cmd = "cd '" + dir.string() + "' && curl -s " + args + " > curl.txt";
  if (std::system(cmd.c_str()) != 0) return "curl failed";
  return test::slurp(dir / "curl.txt");
}

// A plant of one simulated drive (the commissioned axis) named press/a on line l1.
void write_plant(const fs::path& dir, const std::string& tables = "") {
  fs::copy_file(std::string(LMCFG_SOURCE_DIR) + "/tests/fixtures/sim/commissioned-axis.json",
                dir / "a.json");
  test::spit(dir / "plant.toml",
             tables + "[[line]]\nname = \"l1\"\nport = \"sim:" + (dir / "a.json").string() +
                 "\"\n[[line.drive]]\nname = \"press/a\"\nid = 0x11\n");
}

}  // namespace

TEST_CASE(
    "serve cli: refuses a non-loopback --listen without tokens and TLS, bad TLS files, bad "
    "roles, token add prints a token once",
    "[serve][cli]") {
  test::ScratchDir d("serve-cli");
  write_plant(d.path);
  auto r = test::run_tool_in(d.path, "serve plant.toml --archive arch --listen 0.0.0.0:8470");
  CHECK(r.exit_code == 2);
  CHECK(r.err ==
        "lmcfg serve: --listen 0.0.0.0:8470 is not a loopback address: serving other hosts needs "
        "--tokens and --tls-cert/--tls-key (missing: --tokens and --tls-cert/--tls-key; "
        "docs/serve.md \"Security model\")\n");
  CHECK_FALSE(fs::exists(d.path / "arch"));
  // Tokens alone do not make another address acceptable: the tokens would
  // cross the network in clear.
  REQUIRE(
      test::run_tool_in(d.path, "serve token add ops --role operator --tokens tokens").exit_code ==
      0);
  r = test::run_tool_in(d.path,
                        "serve plant.toml --archive arch --listen 10.0.0.5:8470 --tokens tokens");
  CHECK(r.exit_code == 2);
  CHECK(r.err ==
        "lmcfg serve: --listen 10.0.0.5:8470 is not a loopback address: serving other hosts needs "
        "--tokens and --tls-cert/--tls-key (missing: --tls-cert/--tls-key; docs/serve.md "
        "\"Security model\")\n");
  r = test::run_tool_in(d.path,
                        "serve plant.toml --archive arch --listen 0.0.0.0:8470 --tls-cert c.pem "
                        "--tls-key k.pem");
  CHECK(r.exit_code == 2);
  CHECK(r.err.find("(missing: --tokens; ") != std::string::npos);
  r = test::run_tool_in(d.path, "serve plant.toml --archive arch --tls-cert c.pem");
  CHECK(r.exit_code == 2);
  CHECK(r.err ==
        "lmcfg serve: --tls-cert and --tls-key go together (the certificate and its private "
        "key)\n");
  r = test::run_tool_in(d.path, "serve plant.toml --archive arch --tls-cert c.pem --tls-key k.pem");
  CHECK(r.exit_code == 2);
  CHECK(r.err ==
        "lmcfg serve: --tls-cert c.pem / --tls-key k.pem: cannot load them as a PEM certificate "
        "and its private key (readable files, the key matching the certificate)\n");
  CHECK_FALSE(fs::exists(d.path / "arch"));
  r = test::run_tool_in(d.path, "serve plant.toml --archive arch --listen 127.0.0.1");
  CHECK(r.exit_code == 2);
  CHECK(r.err ==
        "lmcfg serve: --listen '127.0.0.1' is not HOST:PORT (e.g. 127.0.0.1:8470, [::1]:8470; "
        "PORT 0..65535)\n");
  r = test::run_tool_in(d.path, "serve --archive arch");
  CHECK(r.exit_code == 2);
  CHECK(r.err == "lmcfg serve: INVENTORY and --archive DIR are needed (see lmcfg serve --help)\n");
  r = test::run_tool_in(d.path, "serve token add ops --role admin --tokens tokens2");
  CHECK(r.exit_code == 2);
  CHECK(r.err == "lmcfg serve token add: role 'admin' is not one of viewer, operator\n");
  CHECK_FALSE(fs::exists(d.path / "tokens2"));
  r = test::run_tool_in(d.path, "serve token add ops2 --role operator --tokens tokens2");
  CHECK(r.exit_code == 0);
  REQUIRE(r.out.size() == 65);
  CHECK(test::slurp(d.path / "tokens2").find(r.out.substr(0, 64)) == std::string::npos);
  CHECK(test::slurp(d.path / "tokens2").rfind("ops2 operator ", 0) == 0);
}

TEST_CASE("serve cli: a running service answers curl with a token and stops on SIGTERM with 0",
          "[serve][cli]") {
  test::ScratchDir d("serve-run");
  write_plant(d.path, "[schedule]\nbackup_every = \"1d\"\n");
  auto tok = test::run_tool_in(d.path, "serve token add ops --role operator --tokens tokens");
  REQUIRE(tok.exit_code == 0);
  const std::string token = tok.out.substr(0, 64);
  test::Child serve({LMCFG_TOOL_PATH, "serve", (d.path / "plant.toml").string(), "--archive",
                     (d.path / "arch").string(), "--listen", "127.0.0.1:0", "--tokens",
                     (d.path / "tokens").string(), "--db", LMCFG_DB_PATH});
  const std::string url = serve.read_line();
  REQUIRE(url.rfind("http://127.0.0.1:", 0) == 0);
  CHECK(curl(d.path, "-o /dev/null -w '%{http_code}' " + url + "/api/v1/drives") == "401");
  // The first scheduled backup runs at start: wait (bounded) for it.
  nlohmann::json drive;
  for (int i = 0; i < 100; ++i) {
    drive = nlohmann::json::parse(
        curl(d.path, "-H 'Authorization: Bearer " + token + "' " + url + "/api/v1/drives/press/a"));
    if (drive["status"] != "unknown") break;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  CHECK(drive["status"] == "ok");
  CHECK(drive["line"] == "l1");
  CHECK(fs::exists(d.path / "arch" / "press" / "a.json"));
  const auto history =
      nlohmann::json::parse(curl(d.path, "-H 'Authorization: Bearer " + token + "' " + url +
                                             "/api/v1/drives/press/a/history"));
  REQUIRE(history.size() == 1);
  CHECK(history[0]["message"].get<std::string>().rfind(
            "fleet backup: 0 changed, 0 unchanged, 1 new", 0) == 0);
  CHECK(serve.stop() == 0);
}

TEST_CASE(
    "serve cli: HTTPS with a self-signed certificate answers curl --cacert, on loopback and on "
    "every address with tokens",
    "[serve][cli][tls]") {
  test::ScratchDir d("serve-tls");
  write_plant(d.path, "[schedule]\nbackup_every = \"1d\"\n");
  // A certificate for 127.0.0.1 made by the real openssl, as an operator would.
  const std::string req =
      "cd '" + d.path.string() +
      "' && openssl req -x509 -newkey rsa:2048 -nodes -keyout key.pem -out cert.pem -days 2 "
      "-subj /CN=127.0.0.1 -addext subjectAltName=IP:127.0.0.1 >openssl.txt 2>&1";
  REQUIRE(std::system(req.c_str()) == 0);
  const std::string cert = (d.path / "cert.pem").string(), key = (d.path / "key.pem").string();
  {
    test::Child serve({LMCFG_TOOL_PATH, "serve", (d.path / "plant.toml").string(), "--archive",
                       (d.path / "arch").string(), "--listen", "127.0.0.1:0", "--tls-cert", cert,
                       "--tls-key", key, "--db", LMCFG_DB_PATH});
    const std::string url = serve.read_line();
    REQUIRE(url.rfind("https://127.0.0.1:", 0) == 0);
    const auto drives =
        nlohmann::json::parse(curl(d.path, "--cacert cert.pem " + url + "/api/v1/drives"));
    REQUIRE(drives.size() == 1);
    CHECK(drives[0]["name"] == "press/a");
    // Without the certificate curl does not trust it (exit 60); plain HTTP gets no answer.
    CHECK(std::system(("curl -s -o /dev/null " + url + "/api/v1/drives").c_str()) != 0);
    std::string plain = url;
    plain.replace(0, 5, "http");
    CHECK(curl(d.path, "-o /dev/null -w '%{http_code}' " + plain + "/api/v1/drives") != "200");
    CHECK(serve.stop() == 0);
  }
  auto tok = test::run_tool_in(d.path, "serve token add grafana --role viewer --tokens tokens");
  REQUIRE(tok.exit_code == 0);
  const std::string token = tok.out.substr(0, 64);
  test::Child serve({LMCFG_TOOL_PATH, "serve", (d.path / "plant.toml").string(), "--archive",
                     (d.path / "arch").string(), "--listen", "0.0.0.0:0", "--tokens",
                     (d.path / "tokens").string(), "--tls-cert", cert, "--tls-key", key, "--db",
                     LMCFG_DB_PATH});
  const std::string url = serve.read_line();
  REQUIRE(url.rfind("https://0.0.0.0:", 0) == 0);
  const std::string local = "https://127.0.0.1:" + url.substr(url.rfind(':') + 1);
  CHECK(curl(d.path, "--cacert cert.pem -o /dev/null -w '%{http_code}' " + local + "/metrics") ==
        "401");
  CHECK(curl(d.path, "--cacert cert.pem -o /dev/null -w '%{http_code}' -H 'Authorization: Bearer " +
                         token + "' " + local + "/metrics") == "200");
  CHECK(curl(d.path,
             "--cacert cert.pem -o /dev/null -w '%{http_code}' --data '' -H "
             "'Authorization: Bearer " +
                 token + "' " + local + "/api/v1/lines/l1/backup") == "403");
  CHECK(serve.stop() == 0);
}

TEST_CASE(
    "serve cli: kill -9 or SIGTERM during an automatic restore, the restart resumes it, git fsck "
    "is clean and the drive converges to the archive",
    "[serve][cli][replaced]") {
  const int signal = GENERATE(SIGKILL, SIGTERM);
  INFO("signal " << signal);
  test::ScratchDir d("serve-kill");
  // The archive holds the commissioned axis at press/a (a backup through the in-process sim).
  write_plant(d.path);
  auto backup = test::run_tool_in(d.path, "fleet backup plant.toml --archive arch");
  REQUIRE(backup.exit_code == 0);
  const std::string archived = test::git(d.path / "arch", "rev-parse HEAD").substr(0, 12);
  // A factory-fresh drive now answers there: `lmcfg sim` in real time on a pty, slow flash
  // saves and reset, so the restore takes seconds and the kill lands in its middle.
  test::write_fresh_axis(d.path / "fresh.json", 0x11);
  auto fresh = nlohmann::json::parse(test::slurp(d.path / "fresh.json"));
  fresh["timing_us"] = {{"flash_save", 1500000}, {"reset", 2000000}, {"start", 1000000}};
  test::spit(d.path / "fresh.json", fresh.dump(1));
  test::Child drive({LMCFG_TOOL_PATH, "sim", "--pty", "--state", (d.path / "fresh.json").string()});
  const std::string tty = drive.read_line();
  (void)drive.read_line();  // the link options
  REQUIRE(tty.rfind("/dev/pts/", 0) == 0);
  test::spit(d.path / "serve.toml",
             "[schedule]\nbackup_every = \"1d\"\nstatus_every = \"2s\"\n[[line]]\nname = "
             "\"l1\"\nport = \"" +
                 tty +
                 "\"\non_replaced = \"restore\"\n[[line.drive]]\nname = \"press/a\"\nid = "
                 "0x11\n");
  const std::vector<std::string> argv{LMCFG_TOOL_PATH,
                                      "serve",
                                      (d.path / "serve.toml").string(),
                                      "--archive",
                                      (d.path / "arch").string(),
                                      "--listen",
                                      "127.0.0.1:0"};
  const fs::path state = d.path / "arch" / ".git" / "lmcfg-serve";
  {
    test::Child serve(argv);
    REQUIRE(serve.read_line().rfind("http://127.0.0.1:", 0) == 0);
    // The restore's recovery record exists from its first write to its last step.
    bool writing = false;
    for (int i = 0; i < 600 && !writing; ++i) {
      writing = fs::exists(state / "lmcfg" / ("restore-" + ops::drive_key(tty, 0x11) + ".json"));
      if (!writing) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    REQUIRE(writing);
    // The line's port is the service's while it uses it.
    auto busy = test::run_tool_in(d.path, "info --port " + tty);
    CHECK(busy.exit_code == 4);
    CHECK(busy.err.find("port " + tty + " is in use by lmcfg serve (PID " +
                        std::to_string(serve.pid()) + ")") != std::string::npos);
    std::this_thread::sleep_for(std::chrono::milliseconds(700));
    if (signal == SIGKILL) {
      REQUIRE(::kill(serve.pid(), SIGKILL) == 0);
      serve.stop();  // reaps it
    } else {
      // The telegram in flight completes, the restore stops as on Ctrl-C, exit 0.
      CHECK(serve.stop() == 0);
    }
  }
  CHECK(fs::exists(state / "pending" / "l1-11h.json"));
  test::git(d.path / "arch", "fsck --no-progress");
  if (signal == SIGKILL) {
    // Killed before its outcome: nothing recorded yet.
    CHECK(test::git(d.path / "arch", "rev-parse HEAD").substr(0, 12) == archived);
  } else {
    // Stopped after its first write: recorded as failed, with the reason.
    const std::string body = test::git(d.path / "arch", "log -1 --format=%B");
    CHECK(body.find("(automatic: factory-fresh drive found)\n\nfailed\n") != std::string::npos);
  }

  test::Child serve(argv);
  const std::string url = serve.read_line();
  REQUIRE(url.rfind("http://127.0.0.1:", 0) == 0);
  // The restore is resumed first (again at the next run while the drive, left resetting or
  // saving to flash by the kill, does not answer yet), then the drift check finds the drive
  // matching the archive.
  const std::string restored = "fleet restore: press/a <- press/a.json at " + archived +
                               " (automatic: factory-fresh drive found)\n";
  nlohmann::json drive_state;
  std::string subject;
  for (int i = 0; i < 600; ++i) {
    drive_state = nlohmann::json::parse(curl(d.path, url + "/api/v1/drives/press/a"));
    subject = test::git(d.path / "arch", "log -1 --format=%s");
    if (subject == restored && drive_state["status"] == "ok" &&
        drive_state["last_attempt"]["job"] == "status")
      break;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  INFO(drive_state.dump());
  CHECK(subject == restored);
  CHECK(drive_state["status"] == "ok");
  CHECK(drive_state["last_attempt"]["job"] == "status");
  CHECK_FALSE(fs::exists(state / "pending" / "l1-11h.json"));
  CHECK(test::git(d.path / "arch", "log -1 --format=%b").find("restored and verified") !=
        std::string::npos);
  // A live diff waits for the line's worker; while the line is busy it answers
  // 503 with Retry-After, and asking again gets the read's answer.
  nlohmann::json diff;
  for (int i = 0; i < 60; ++i) {
    diff = nlohmann::json::parse(
        curl(d.path, "'" + url + "/api/v1/drives/press/a/diff?from=HEAD&to=live'"));
    if (diff.contains("differences")) break;
    std::this_thread::sleep_for(std::chrono::seconds(1));
  }
  INFO(diff.dump());
  REQUIRE(diff.contains("differences"));
  CHECK(diff["differences"].empty());
  test::git(d.path / "arch", "fsck --no-progress");
  CHECK(serve.stop() == 0);
}

}  // namespace tools_test_serve_cli
