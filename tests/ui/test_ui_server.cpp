// lmcfg ui's HTTP side in-process (ui/server.hpp): the token, Host, Origin
// and CSRF checks, and the whole flow against simulated drives: find, back
// up, compare with factory defaults, restore onto a used spare through the
// plan, the spare then identical, undo.
#include <catch2/catch.hpp>
#include <filesystem>

#include "files.hpp"
#include "ops/recovery.hpp"
#include "report/report.hpp"
#include "serve/console.hpp"
#include "subprocess.hpp"
#include "ui/upload.hpp"
#include "ui_rig.hpp"
#include "vanish_link.hpp"

namespace ui_test_ui_server {

using namespace lmcfg;
using test::UiRig;
namespace fs = std::filesystem;

std::string copy_fixture(const UiRig& rig, const char* name) {
  const fs::path to = rig.dir() / name;
  fs::copy_file(fs::path(LMCFG_SOURCE_DIR) / "tests/fixtures/sim" / name, to,
                fs::copy_options::overwrite_existing);
  return "sim:" + to.string();
}

// The drive's key from a finished find.
std::string found_key(const ui::Json& job) {
  REQUIRE(job["state"] == "done");
  REQUIRE(job["result"]["found"].size() == 1);
  return job["result"]["found"][0].get<std::string>();
}

TEST_CASE("ui server: the token becomes a cookie, nothing is served without it", "[ui_server]") {
  UiRig rig("ui-token");
  SECTION("the printed address sets the cookie and leaves the token out of the address") {
    auto a = rig.get("/drive?key=x&token=T0KEN", false);
    CHECK(a.status == 303);
    CHECK(a.header("location") == "/drive?key=x");
    CHECK(a.header("set-cookie").find("HttpOnly; SameSite=Strict; Path=/") != std::string::npos);
  }
  SECTION("no cookie, a wrong token, a wrong cookie: 403 and how to open the page") {
    auto none = rig.get("/", false);
    CHECK(none.status == 403);
    CHECK(none.body.find("id=\"need-token\"") != std::string::npos);
    CHECK(rig.get("/?token=WRONG", false).status == 403);
    auto forged =
        rig.raw("GET / HTTP/1.1\r\nHost: " + rig.host() + "\r\nCookie: lmcfg_ui=0000\r\n\r\n");
    CHECK(forged.status == 403);
    CHECK(rig.get("/api/v1/drives", false).status == 403);
  }
  SECTION("with the cookie the connect page, with the console's security headers") {
    auto a = rig.get("/");
    CHECK(a.status == 200);
    CHECK(a.body.find("<h1>Connect a drive</h1>") != std::string::npos);
    CHECK(a.header("content-security-policy").find("default-src 'none'") != std::string::npos);
    CHECK(a.header("x-content-type-options") == "nosniff");
    CHECK(rig.get("/console.css", false).status == 200);
  }
}

TEST_CASE("ui server: Host, Origin and CSRF are checked as lmcfg serve checks them",
          "[ui_server]") {
  UiRig rig("ui-checks");
  SECTION("another Host name (DNS rebinding): 421") {
    auto a =
        rig.raw("GET / HTTP/1.1\r\nHost: evil.example:80\r\nCookie: " + rig.cookie() + "\r\n\r\n");
    CHECK(a.status == 421);
    CHECK(a.body.find("the Host header 'evil.example:80' is not this service's address") !=
          std::string::npos);
  }
  SECTION("a POST from another site: 403 before any route") {
    auto a = rig.post("/find", {{"port", "sim:x.json"}}, "Sec-Fetch-Site: cross-site\r\n");
    CHECK(a.status == 403);
    CHECK(a.body.find("cross-site request refused: Sec-Fetch-Site is 'cross-site'") !=
          std::string::npos);
    auto b = rig.post("/find", {{"port", "sim:x.json"}}, "Origin: http://evil.example\r\n");
    CHECK(b.status == 403);
    CHECK(b.body.find("Origin 'http://evil.example' is not this service's origin") !=
          std::string::npos);
  }
  SECTION("a form without this page's CSRF value: 403, nothing started") {
    auto a = rig.post("/find", {{"port", "sim:x.json"}, {"csrf", "nope"}});
    CHECK(a.status == 403);
    CHECK(a.body.find("the form&#39;s CSRF token is missing or not this page&#39;s") !=
          std::string::npos);
    CHECK(rig.desk().jobs().empty());
  }
  SECTION("a form that is not a form: 415") {
    auto a = rig.raw("POST /find HTTP/1.1\r\nHost: " + rig.host() + "\r\nCookie: " + rig.cookie() +
                     "\r\nContent-Type: text/plain\r\nContent-Length: 2\r\n\r\nab");
    CHECK(a.status == 415);
  }
  SECTION("a file name with a path: refused") {
    auto a = rig.get("/files/..%2Fstate");
    CHECK(a.status == 400);
  }
}

TEST_CASE("ui server: find, back up, compare, restore onto a used spare, undo",
          "[ui_server][ui_flow]") {
  UiRig rig("ui-flow");
  const std::string original = copy_fixture(rig, "commissioned-axis.json");
  const std::string spare = copy_fixture(rig, "used-spare.json");

  const auto find = [&](const std::string& port) {
    return found_key(rig.finish(
        rig.post("/find", {{"port", port}, {"baud", "57600"}, {"from", "16"}, {"to", "18"}})));
  };
  const std::string a = find(original);
  auto page = rig.get("/drive?key=" + test::form_encode(a));
  REQUIRE(page.status == 200);
  CHECK(page.body.find("id=\"identity\"") != std::string::npos);
  CHECK(page.body.find("id=\"no-backups\"") != std::string::npos);

  auto backed = rig.finish(rig.post("/backup", {{"key", a}}));
  REQUIRE(backed["state"] == "done");
  const std::string file = backed["result"]["file"];
  CHECK(file.rfind(a + "-", 0) == 0);
  CHECK(fs::exists(rig.dir() / "backups" / file));
  auto download = rig.get("/files/" + test::form_encode(file));
  CHECK(download.status == 200);
  CHECK(download.header("content-disposition") == "attachment; filename=\"" + file + "\"");
  CHECK(download.body.find("\"format\"") != std::string::npos);
  CHECK(rig.get("/drive?key=" + test::form_encode(a)).body.find(file) != std::string::npos);
  auto report = rig.get("/report?file=" + test::form_encode(file));
  CHECK(report.status == 200);
  CHECK(report.body.find("tr class=\"param\"") != std::string::npos);
  CHECK(report.header("content-security-policy") ==
        std::string(serve::Console::report_security_policy()));
  CHECK(rig.get("/report?file=..%2Fx.json").status == 400);

  auto vs_defaults = rig.finish(rig.post("/compare", {{"key", a}, {"against", "defaults"}}));
  REQUIRE(vs_defaults["state"] == "done");
  CHECK(vs_defaults["result"]["identical"] == false);
  auto diff_page = rig.get("/compare?job=" + vs_defaults["id"].get<std::string>());
  CHECK(diff_page.status == 200);
  CHECK(diff_page.body.find("data-kind=\"parameter\"") != std::string::npos);

  const std::string b = find(spare);
  auto planned = rig.finish(rig.post("/plan", {{"key", b}, {"file", file}}));
  REQUIRE(planned["state"] == "done");
  const std::string plan_id = planned["result"]["plan_id"];
  auto plan_page = rig.get("/plan?id=" + plan_id);
  REQUIRE(plan_page.status == 200);
  CHECK(plan_page.body.find("id=\"verdict\"") != std::string::npos);
  CHECK(plan_page.body.find("not factory-fresh") != std::string::npos);
  CHECK(plan_page.body.find("id=\"execute\"") != std::string::npos);

  SECTION("a write without a reason is refused, the plan kept") {
    auto a2 = rig.post("/execute", {{"plan", plan_id}, {"reason", ""}});
    CHECK(a2.status == 400);
    CHECK(rig.get("/plan?id=" + plan_id).status == 200);
  }
  SECTION("restored, then identical; undo puts the spare back") {
    auto written = rig.finish(
        rig.post("/execute",
                 {{"plan", plan_id}, {"reason", "spare for axis 1"}, {"skip_incompatible", "1"}}));
    INFO(written.dump(2));
    REQUIRE(written["state"] == "done");
    CHECK(written["result"]["undo_command"].get<std::string>().find("lmcfg undo --port") == 0);
    auto job_page = rig.get("/job?id=" + written["id"].get<std::string>());
    CHECK(job_page.body.find("id=\"undo-saved\"") != std::string::npos);
    CHECK(rig.get("/plan?id=" + plan_id).status == 404);  // one use

    auto same = rig.finish(rig.post("/compare", {{"key", b}, {"against", file}}));
    INFO(same.dump(2));
    CHECK(same["result"]["identical"] == true);

    auto drive_page = rig.get("/drive?key=" + test::form_encode(b));
    CHECK(drive_page.body.find("spare for axis 1") != std::string::npos);  // the journal

    auto undo_plan = rig.finish(rig.post("/undo", {{"key", b}}));
    REQUIRE(undo_plan["state"] == "done");
    auto undone = rig.finish(
        rig.post("/execute", {{"plan", undo_plan["result"]["plan_id"].get<std::string>()},
                              {"reason", "back as it was"}}));
    REQUIRE(undone["state"] == "done");
    CHECK(undone["kind"] == "undo");
    auto differs = rig.finish(rig.post("/compare", {{"key", b}, {"against", file}}));
    CHECK(differs["result"]["identical"] == false);
  }
}

TEST_CASE("ui server: Quit stops nothing half way", "[ui_server]") {
  bool quit = false;
  test::ScratchDir dir("ui-quit");
  ::setenv("XDG_STATE_HOME", (dir.path / "state").string().c_str(), 1);
  ui::DeskOptions o;
  o.folder = dir.path / "b";
  auto desk = ui::Desk::create(std::move(o));
  REQUIRE(desk.ok());
  ui::UiOptions uo;
  uo.token = "T";
  uo.on_quit = [&quit] { quit = true; };
  SECTION("a loopback address only") {
    uo.host = "0.0.0.0";
    ui::UiServer s(**desk, uo);
    auto bound = s.bind();
    REQUIRE_FALSE(bound.ok());
    CHECK(bound.error().message ==
          "'0.0.0.0' is not a loopback address: lmcfg ui serves this computer only (127.0.0.1, "
          "::1 or localhost)");
  }
  SECTION("the address printed carries the token") {
    ui::UiServer s(**desk, uo);
    REQUIRE(s.bind().ok());
    CHECK(s.url().rfind("http://127.0.0.1:", 0) == 0);
    CHECK(s.url().substr(s.url().size() - 9) == "/?token=T");
  }
  ::unsetenv("XDG_STATE_HOME");
}

TEST_CASE("ui server: a drive that vanishes mid-write: what it holds, and the way out",
          "[ui_server][ui_flow]") {
  UiRig rig("ui-vanish");
  const std::string original = copy_fixture(rig, "commissioned-axis.json");
  const std::string spare_file = copy_fixture(rig, "used-spare.json").substr(4);
  const std::string spare = "simvanish:" + spare_file;
  const auto find = [&](const std::string& port) {
    return found_key(rig.finish(
        rig.post("/find", {{"port", port}, {"baud", "57600"}, {"from", "16"}, {"to", "18"}})));
  };
  const std::string a = find(original);
  const std::string file = rig.finish(rig.post("/backup", {{"key", a}}))["result"]["file"];
  const std::string b = find(spare);
  auto planned = rig.finish(rig.post("/plan", {{"key", b}, {"file", file}}));
  REQUIRE(planned["state"] == "done");
  const long plan_writes = test::last_session_writes();
  // The execution re-reads what the plan read, saves the undo record, then
  // writes: the link goes a few telegrams into the writes.
  test::vanish().fail_after = plan_writes + 40;
  auto failed =
      rig.finish(rig.post("/execute", {{"plan", planned["result"]["plan_id"].get<std::string>()},
                                       {"reason", "spare"},
                                       {"skip_incompatible", "1"}}));
  test::vanish().fail_after = -1;
  INFO(failed.dump(2));
  REQUIRE(failed["state"] == "failed");
  // "failed" is said once the job has ended and freed its port, so the way
  // out below may start at once (it met "port ... is busy" when it was not).
  CHECK_FALSE(failed["finished"].is_null());
  CHECK(failed["message"].get<std::string>().find("vanished") != std::string::npos);
  CHECK(failed["drive_state"].get<std::string>().rfind("partially configured", 0) == 0);
  auto page = rig.get("/job?id=" + failed["id"].get<std::string>());
  CHECK(page.body.find("The drive is partially configured") != std::string::npos);
  CHECK(page.body.find("plan the restore again") != std::string::npos);
  // The CLI's recovery record is there: `lmcfg restore` would finish it too.
  CHECK(fs::exists(*ops::recovery_path("restore", spare, 0x11)));
  // The way out: plan again, write again; the drive then reads identical.
  auto again = rig.finish(rig.post("/plan", {{"key", b}, {"file", file}}));
  REQUIRE(again["state"] == "done");
  auto written =
      rig.finish(rig.post("/execute", {{"plan", again["result"]["plan_id"].get<std::string>()},
                                       {"reason", "spare, again"},
                                       {"skip_incompatible", "1"}}));
  INFO(written.dump(2));
  REQUIRE(written["state"] == "done");
  CHECK_FALSE(fs::exists(*ops::recovery_path("restore", spare, 0x11)));
  auto same = rig.finish(rig.post("/compare", {{"key", b}, {"against", file}}));
  CHECK(same["result"]["identical"] == true);
}

TEST_CASE("ui server: a drive over LinUDP is asked at its address, then backed up",
          "[ui_server][ui_flow]") {
  UiRig rig("ui-linudp");
  const std::string state = copy_fixture(rig, "commissioned-axis.json").substr(4);
  test::Child sim(std::vector<std::string>{LMCFG_TOOL_PATH, "sim", "--linudp", "--udp",
                                           "127.0.0.1:0", "--state", state, "--fast"});
  const std::string url = "linudp://127.0.0.1:" + sim.read_line();
  (void)sim.read_line();
  auto found = rig.finish(rig.post("/find", {{"port", url}}));
  INFO(found.dump(2));
  REQUIRE(found["kind"] == "connect");  // no scan: the address names the drive
  const std::string key = found_key(found);
  auto page = rig.get("/drive?key=" + test::form_encode(key));
  CHECK(page.body.find("Operation Enabled") != std::string::npos);
  auto backed = rig.finish(rig.post("/backup", {{"key", key}}));
  INFO(backed.dump(2));
  REQUIRE(backed["state"] == "done");
  CHECK(fs::exists(rig.dir() / "backups" / backed["result"]["file"].get<std::string>()));
}

}  // namespace ui_test_ui_server

namespace ui_test_ui_server {

// The failure page's text of a message (the page escapes it).
void says(const test::UiAnswer& a, const std::string& message) {
  INFO(a.body);
  CHECK(a.body.find(report::html_escape(message)) != std::string::npos);
}

TEST_CASE("ui server: a file from this computer: kept in the folder, compared, restored",
          "[ui_server][ui_flow][ui_upload]") {
  UiRig rig("ui-upload");
  const std::string original = copy_fixture(rig, "commissioned-axis.json");
  const std::string spare = copy_fixture(rig, "used-spare.json");
  const auto find = [&](const std::string& port) {
    return found_key(rig.finish(
        rig.post("/find", {{"port", port}, {"baud", "57600"}, {"from", "16"}, {"to", "18"}})));
  };
  const std::string a = find(original);
  const std::string b = find(spare);
  const std::string backup = rig.finish(rig.post("/backup", {{"key", a}}))["result"]["file"];
  // The backup, as if carried over on a stick and chosen in the file field.
  const std::string content = test::slurp(rig.dir() / "backups" / backup);
  fs::remove(rig.dir() / "backups" / backup);

  auto page = rig.get("/drive?key=" + test::form_encode(b));
  CHECK(page.body.find("enctype=\"multipart/form-data\"") != std::string::npos);
  CHECK(page.body.find("<option value=\"drive:" + report::html_escape(a) + "\">") !=
        std::string::npos);

  auto compared = rig.finish(rig.upload({{"key", b}, {"then", "compare"}}, "axis 1.json", content));
  INFO(compared.dump(2));
  REQUIRE(compared["state"] == "done");
  CHECK(compared["result"]["against"] == "axis 1.json");
  CHECK(compared["result"]["identical"] == false);
  CHECK(test::slurp(rig.dir() / "backups" / "axis 1.json") == content);

  auto planned = rig.finish(rig.upload({{"key", b}, {"then", "plan"}}, "axis 1.json", content));
  REQUIRE(planned["state"] == "done");
  CHECK(planned["result"]["file"] == "axis 1.json");  // the same bytes: the same file
  auto plan_page = rig.get("/plan?id=" + planned["result"]["plan_id"].get<std::string>());
  CHECK(plan_page.body.find("Restore <code class=\"wrap\">axis 1.json</code>") !=
        std::string::npos);
  auto written =
      rig.finish(rig.post("/execute", {{"plan", planned["result"]["plan_id"].get<std::string>()},
                                       {"reason", "from the laptop"},
                                       {"skip_incompatible", "1"}}));
  INFO(written.dump(2));
  REQUIRE(written["state"] == "done");
  auto same = rig.finish(rig.post("/compare", {{"key", b}, {"against", "axis 1.json"}}));
  CHECK(same["result"]["identical"] == true);
  // Another drive found: the spare now holds what the original holds.
  auto drives = rig.finish(rig.post("/compare", {{"key", b}, {"against", "drive:" + a}}));
  INFO(drives.dump(2));
  REQUIRE(drives["state"] == "done");
  CHECK(drives["result"]["identical"] == true);
  CHECK(rig.get("/compare?job=" + drives["id"].get<std::string>()).body.find("drive " + a) !=
        std::string::npos);

  // Other bytes under a name the folder holds: kept beside it.
  std::string changed = content;
  changed += "\n";
  auto beside = rig.finish(rig.upload({{"key", b}, {"then", "compare"}}, "axis 1.json", changed));
  REQUIRE(beside["state"] == "done");
  CHECK(beside["result"]["against"] == "axis 1-2.json");
  CHECK(test::slurp(rig.dir() / "backups" / "axis 1.json") == content);
}

TEST_CASE("ui server: a file from this computer that cannot be taken: what is wrong",
          "[ui_server][ui_upload]") {
  UiRig rig("ui-upload-bad");
  const std::string key = "sim__x-11h";
  const std::string drive = "/drive?key=" + key;
  const auto files = [&] {
    std::vector<std::string> n;
    for (const auto& e : fs::directory_iterator(rig.dir() / "backups"))
      n.push_back(e.path().filename().string());
    return n;
  };
  SECTION("not a configuration file") {
    auto a = rig.upload({{"key", key}, {"then", "compare"}}, "notes.json", "shopping list\n");
    CHECK(a.status == 400);
    says(a,
         "'notes.json' is not a configuration file lmcfg reads (notes.json:1:1: syntax error while "
         "parsing value - invalid literal; last read: 's'); choose a file "
         "that lmcfg backup or this page wrote (JSON or XML)");
    auto x = rig.upload({{"key", key}, {"then", "plan"}}, "axis.xml", "{\"format\": 2}");
    CHECK(x.status == 400);
    says(x,
         "'axis.xml' is not a configuration file lmcfg reads (axis.xml:1:14: XML syntax error: No "
         "document element found); choose a file "
         "that lmcfg backup or this page wrote (JSON or XML)");
  }
  SECTION("too large") {
    auto a = rig.upload({{"key", key}, {"then", "compare"}}, "big.json",
                        std::string(ui::kMaxUpload + 1, ' '));
    CHECK(a.status == 400);
    says(a,
         "'big.json' has 4194305 bytes, more than lmcfg ui takes (4194304 bytes): a "
         "drive's configuration file is far smaller; check that this is one");
    auto huge = rig.upload({{"key", key}, {"then", "compare"}}, "huge.json",
                           std::string(ui::kMaxUpload + ui::kUploadFraming, ' '));
    CHECK(huge.status == 413);
  }
  SECTION("a name that is not one file name of the folder") {
    for (const std::string n : {"../state/x.json", ".hidden.json", "axis.txt", "C:\\x.json", ""}) {
      INFO(n);
      auto a = rig.upload({{"key", key}, {"then", "compare"}}, n, "{}");
      CHECK(a.status == 400);
      says(a, "'" + n +
                  "' is not a name lmcfg ui keeps in the backup folder: a file name ending "
                  "in .json or .xml, without folders, ':' or a leading dot; rename the file "
                  "and choose it again");
    }
  }
  SECTION("no file, or a form that is not the page's") {
    auto none = rig.upload({{"key", key}, {"then", "compare"}}, "", "");
    CHECK(none.status == 400);
    says(none,
         "no file chosen: choose a configuration file (.json or .xml) on this "
         "computer");
    auto forged = rig.upload({{"key", key}, {"then", "compare"}, {"csrf", "nope"}}, "a.json", "{}");
    CHECK(forged.status == 403);
    says(forged,
         "the form's CSRF token is missing or not this page's: reload the page and "
         "try again");
    auto cross = rig.upload({{"key", key}, {"then", "compare"}}, "a.json", "{}",
                            "Origin: http://evil.example\r\n");
    CHECK(cross.status == 403);
    auto odd = rig.upload({{"key", key}, {"then", "delete"}}, "a.json", "{}");
    CHECK(odd.status == 400);
    says(odd,
         "the form asks for 'delete' after the upload, not 'compare' or 'plan': send the "
         "file from the drive's page");
    auto plain = rig.post("/upload", {{"key", key}});
    CHECK(plain.status == 415);
    says(plain, "a file must be sent as multipart/form-data");
    auto cut =
        rig.raw("POST /upload HTTP/1.1\r\nHost: " + rig.host() + "\r\nCookie: " + rig.cookie() +
                "\r\nContent-Type: multipart/form-data; boundary=b\r\nContent-Length: "
                "12\r\n\r\n--b\r\nabcdefg");
    CHECK(cut.status == 400);
    says(cut,
         "the upload is not a form the page sends (no closing boundary): choose the "
         "file again on the drive's page and send it from there");
  }
  CHECK(files().empty());  // nothing kept
}

}  // namespace ui_test_ui_server
