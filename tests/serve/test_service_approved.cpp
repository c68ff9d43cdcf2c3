// Approved configurations in lmcfg serve (lib/serve/service_approved.cpp,
// docs/serve.md "Approved configurations"): a position's status is against its
// approved configuration, a used spare stays in drift through backups until
// an operator approves it or the approved configuration is restored; the
// approve endpoint's refusals; the states survive a restart.
#include <httplib.h>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "serve/tokens.hpp"
#include "serve_rig.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace serve_test_service_approved {

using namespace lmcfg;
using namespace lmcfg::test;
namespace fs = std::filesystem;
using namespace std::chrono_literals;

namespace {

nlohmann::json plain(const serve::Json& j) { return nlohmann::json::parse(j.dump()); }

nlohmann::json drive(serve::Service& s, const std::string& name) {
  auto d = s.drive(name);
  REQUIRE(d.ok());
  return plain(*d);
}

nlohmann::json rom_of(const fs::path& state, const std::string& upid) {
  const auto j = nlohmann::json::parse(slurp(state));
  for (const auto& p : j["parameters"])
    if (p["upid"] == upid) return p["rom"];
  return nullptr;
}

std::string head_of(const fs::path& archive) {
  return git(archive, "rev-parse HEAD").substr(0, 40);
}

// Rig's inventory (press3/z at 11h, press3/x at 12h on a simulated line), kept
// to start a second service on the same archive.
std::string inventory_text(const fs::path& dir) {
  return "[schedule]\nbackup_every = \"6h\"\nstatus_every = \"15m\"\n[[line]]\nname = "
         "\"line1\"\nport = 'sim:" +
         (dir / "a.json").string() + "," + (dir / "b.json").string() +
         "'\nignore = [\"0020h\"]\n[[line.drive]]\nname = \"press3/z\"\nid = "
         "0x11\n[[line.drive]]\nname = \"press3/x\"\nid = 0x12\n";
}

// The simulated drive's ROM and RAM values `values` (UPID -> value), as a
// used spare holds them.
void set_sim_values(const fs::path& state, const std::map<std::string, int>& values) {
  auto j = nlohmann::json::parse(slurp(state));
  for (auto& p : j["parameters"])
    if (auto it = values.find(p["upid"].get<std::string>()); it != values.end())
      p["rom"] = p["ram"] = it->second;
  spit(state, j.dump(1));
}

std::vector<std::string> upids_of(const nlohmann::json& kept) {
  std::vector<std::string> out;
  for (const auto& k : kept) out.push_back(k.value("upid", ""));
  return out;
}

}  // namespace

TEST_CASE(
    "serve: a used spare stays drift through two scheduled backups, approving its "
    "configuration makes it ok",
    "[serve][service_approved][git-cli]") {
  Rig rig;
  const auto t0 = rig.now;
  const auto archive = rig.dir.path / "archive";
  rig.at(t0);  // the first backup commissions both positions
  const std::string commissioned = head_of(archive);
  auto x = drive(*rig.service, "press3/x");
  CHECK(x["status"] == "ok");
  CHECK(x["approved"] == nlohmann::json{{"rev", commissioned},
                                        {"time", "2027-01-15T08:00:00Z"},
                                        {"who", "lmcfg serve"},
                                        {"reason", "commissioning: the position's first backup"},
                                        {"ticket", nullptr},
                                        {"kind", "commissioning"}});
  CHECK(rig.take_events().empty());

  // A used spare holding another configuration goes in at press3/x.
  write_axis(rig.dir.path / "b.json", 0x12, "0010", 7);
  rig.at(t0 + 6h);  // a backup (archives the spare's file), then a drift check
  const std::string spare = head_of(archive);
  CHECK(spare != commissioned);
  auto events = rig.take_events();
  REQUIRE(events.size() == 1);
  CHECK(events[0]["event"] == "drift");
  CHECK(events[0]["drive"] == "press3/x");
  CHECK(events[0]["job"] == "backup");
  CHECK(events[0]["committed"] == spare);
  CHECK(events[0]["report"] == "/diff?name=press3%2Fx&from=" + commissioned + "&to=" + spare);
  x = drive(*rig.service, "press3/x");
  CHECK(x["status"] == "drift");
  CHECK(x["differences"] == 1);
  CHECK(x["differing"] == nlohmann::json::array({"OS 0010h: 5 -> 7"}));
  CHECK(x["message"] ==
        "1 parameter, 0 curves, 0 CT entries differ from the approved configuration");
  CHECK(x["approved"]["rev"] == commissioned);
  CHECK(drive(*rig.service, "press3/z")["status"] == "ok");

  rig.at(t0 + 12h);  // the second backup: nothing new to archive, still not approved
  CHECK(head_of(archive) == spare);
  CHECK(rig.take_events().empty());
  CHECK(drive(*rig.service, "press3/x")["status"] == "drift");

  // Refusals first: nothing recorded.
  serve::Service::ApproveRequest req{"", "maria", "", "CHG-9"};
  auto no_reason = rig.service->approve("press3/x", req);
  REQUIRE_FALSE(no_reason.ok());
  CHECK(no_reason.error().code == make_error_code(Errc::invalid_argument));
  CHECK(no_reason.error().message ==
        "approving press3/x needs a reason (why this configuration is the one the position "
        "should hold); nothing recorded");
  req.reason = "spare accepted: same mechanics, tuned by the vendor";
  req.rev = "no-such-rev";
  auto bad_rev = rig.service->approve("press3/x", req);
  REQUIRE_FALSE(bad_rev.ok());
  CHECK(bad_rev.error().code == make_error_code(Errc::not_found));
  CHECK(bad_rev.error().message.rfind("archive " + archive.string() + ": revision 'no-such-rev': ",
                                      0) == 0);
  CHECK(rig.service->approve("press9/q", req).error().message ==
        "no drive named 'press9/q' in the inventory");
  CHECK(drive(*rig.service, "press3/x")["approved"]["rev"] == commissioned);

  req.rev = "";  // HEAD: the spare's configuration as archived
  auto approved = rig.service->approve("press3/x", req);
  REQUIRE(approved.ok());
  CHECK((*approved)["rev"] == spare);
  CHECK((*approved)["who"] == "maria");
  CHECK((*approved)["ticket"] == "CHG-9");
  CHECK((*approved)["kind"] == "operator");
  rig.service->wait_idle();  // the drift check the approval queued
  x = drive(*rig.service, "press3/x");
  CHECK(x["status"] == "ok");
  CHECK(x["approved"]["rev"] == spare);
  CHECK(x["approved"]["reason"] == "spare accepted: same mechanics, tuned by the vendor");
  events = rig.take_events();
  REQUIRE(events.size() == 1);
  CHECK(events[0]["event"] == "recovered");
  CHECK(events[0]["previous"] == "drift");
  // git reads the record: an annotated tag on the approved commit.
  CHECK(git(archive, "cat-file -t refs/lmcfg/approved/press3/x") == "tag\n");
  CHECK(git(archive, "rev-parse 'refs/lmcfg/approved/press3/x^{commit}'").substr(0, 40) == spare);
}

TEST_CASE("serve: restoring the approved configuration over a used spare makes it ok",
          "[serve][service_approved][git-cli]") {
  Rig rig;
  const auto t0 = rig.now;
  const auto archive = rig.dir.path / "archive";
  rig.at(t0);
  const std::string commissioned = head_of(archive);
  write_axis(rig.dir.path / "b.json", 0x12, "0010", 7);
  rig.at(t0 + 6h);  // archived, in drift
  const std::string spare = head_of(archive);
  REQUIRE(drive(*rig.service, "press3/x")["status"] == "drift");
  rig.take_events();

  // No revision named: the approved configuration, not the latest backup.
  auto planned = rig.service->plan("press3/x", "", "ops");
  REQUIRE(planned.ok());
  CHECK((*planned)["rev"] == "approved");
  CHECK((*planned)["commit"] == commissioned);
  serve::Service::ExecuteRequest er;
  er.plan_id = (*planned)["plan_id"];
  er.audit = {"ops", "spare back to the commissioned tuning", ""};
  auto job = rig.service->execute(er);
  REQUIRE(job.ok());
  rig.service->wait_idle();
  CHECK(rom_of(rig.dir.path / "b.json", "0010") == 5);
  CHECK(drive(*rig.service, "press3/x")["status"] == "ok");
  CHECK(git(archive, "log -1 --format=%s") == "fleet restore: press3/x <- press3/x.json at " +
                                                  commissioned.substr(0, 12) +
                                                  " (approved): restored and verified\n");

  // The next backup archives the restored state; the drift check agrees: ok.
  rig.at(t0 + 12h);
  auto x = drive(*rig.service, "press3/x");
  CHECK(x["status"] == "ok");
  CHECK(x["approved"]["rev"] == commissioned);
  for (const auto& e : rig.take_events()) CHECK(e["event"] != "drift");

  // A revision named explicitly that is not the approved one: restored, and in drift.
  auto other = rig.service->plan("press3/x", spare, "ops");
  REQUIRE(other.ok());
  CHECK((*other)["rev"] == spare);
  er.plan_id = (*other)["plan_id"];
  REQUIRE(rig.service->execute(er).ok());
  rig.service->wait_idle();
  CHECK(rom_of(rig.dir.path / "b.json", "0010") == 7);
  x = drive(*rig.service, "press3/x");
  CHECK(x["status"] == "drift");
  CHECK(x["message"] == "restored from press3/x.json@" + spare.substr(0, 12) +
                            ", which is not the approved configuration (approved: " +
                            commissioned.substr(0, 12) + ")");
  rig.at(t0 + 12h + 15min);  // the drift check counts the differences
  x = drive(*rig.service, "press3/x");
  CHECK(x["status"] == "drift");
  CHECK(x["differences"] == 1);
}

TEST_CASE(
    "serve: a used spare with other communication settings, restored from the approved "
    "configuration, stays ok through two scheduled backups, and the plan says what stays different",
    "[serve][service_approved][matching][git-cli]") {
  Rig rig;
  const auto t0 = rig.now;
  rig.at(t0);  // commissioned: baud rate and MACID by parameter (200Eh = 2, 206Ch = 3)
  // The spare's switches choose its baud rate and MACID (200Eh, 206Ch at
  // their defaults), 2012h holds another code, OS 0010h another value.
  write_axis(rig.dir.path / "b.json", 0x12, "0010", 7);
  set_sim_values(rig.dir.path / "b.json", {{"200E", 1}, {"2012", 8}, {"206C", 1}});
  // ... and Appl 3020h (SINT32) at -1000, which the plan writes back to its default.
  {
    auto j = nlohmann::json::parse(slurp(rig.dir.path / "b.json"));
    for (auto& p : j["parameters"])
      if (p["upid"] == "3020") p["rom"] = p["ram"] = 4294966296u;
    spit(rig.dir.path / "b.json", j.dump(1));
  }
  rig.at(t0 + 6h);
  auto x = drive(*rig.service, "press3/x");
  CHECK(x["status"] == "drift");
  CHECK(x["differing"] ==
        nlohmann::json::array({"OS 0010h: 5 -> 7", "Appl 3020h: default 0 -> -1000"}));
  const std::vector<std::string> comm{"200E", "2012", "206C"};
  CHECK(upids_of(x["kept"]) == comm);
  rig.take_events();

  // Before the write: the plan writes 0010h and says which values stay, and why.
  auto planned = rig.service->plan("press3/x", "", "ops");
  REQUIRE(planned.ok());
  const auto p = plain(*planned);
  CHECK(p["nothing_to_do"] == false);
  CHECK(upids_of(p["kept"]) == comm);
  // The drive's -1000 keeps its sign on the plan, as on the position.
  bool signed_shown = false;
  for (const auto& st : p["steps"])
    if (st.value("upid", "") == "3020") signed_shown = st["old"] == "-1000" && st["new"] == "0";
  CHECK(signed_shown);
  // The database names no default here: the file's side says so (a real database knows it).
  CHECK(p["kept"][1]["configuration"] == "its default (not known)");
  CHECK(p["kept"][1]["drive"].get<std::string>().rfind("8", 0) == 0);
  CHECK(p["kept"][1]["by"] == "communication");
  CHECK(p["kept"][1]["remedy"].get<std::string>().rfind(
            "Nothing needs doing while the drive answers on its line.", 0) == 0);
  serve::Service::ExecuteRequest er;
  er.plan_id = p["plan_id"];
  er.audit = {"ops", "spare back to the commissioned tuning", ""};
  auto job = rig.service->execute(er);
  REQUIRE(job.ok());
  rig.service->wait_idle();

  // After it: restored and verified, the same three values listed as kept.
  auto done = rig.service->job(*job);
  REQUIRE(done.ok());
  const auto j = plain(*done);
  CHECK(j["outcome"] == "restored and verified");
  CHECK(upids_of(j["kept"]) == comm);
  x = drive(*rig.service, "press3/x");
  CHECK(x["status"] == "ok");
  CHECK(upids_of(x["kept"]) == comm);

  // Two scheduled backups (each with its drift check): ok, never drift.
  for (auto t : {t0 + 12h, t0 + 18h}) {
    rig.at(t);
    x = drive(*rig.service, "press3/x");
    CHECK(x["status"] == "ok");
    CHECK(x["message"] ==
          "matches the approved configuration; 3 value(s) differ that the drive keeps by policy "
          "(listed as kept)");
    CHECK(upids_of(x["kept"]) == comm);
    for (const auto& e : rig.take_events()) CHECK(e["event"] != "drift");
  }
  // Planning again agrees: nothing to write, the same values kept.
  auto again = rig.service->plan("press3/x", "", "ops");
  REQUIRE(again.ok());
  CHECK(plain(*again)["nothing_to_do"] == true);
  CHECK(upids_of(plain(*again)["kept"]) == comm);
}

TEST_CASE("serve: statuses and last backups survive a restart of the service",
          "[serve][service_approved]") {
  ServiceRig rig("serve-restart");
  write_axis(rig.dir.path / "a.json", 0x11);
  write_axis(rig.dir.path / "b.json", 0x12);
  const auto options = [](serve::ServiceOptions& o) { o.exit_code = exit_code_of; };
  rig.start(inventory_text(rig.dir.path), options);
  const auto t0 = rig.now;
  rig.at(t0);  // backup and drift check
  write_axis(rig.dir.path / "b.json", 0x12, "0010", 7);
  rig.at(t0 + 6h);  // press3/x: archived, in drift
  rig.take_events();
  const auto before = plain(rig.service->drives());
  REQUIRE(before[1]["status"] == "drift");
  REQUIRE(before[0]["last_backup"] == "2027-01-15T14:00:00Z");

  rig.service.reset();  // stopped (a restart; a kill leaves the same files)
  rig.now = t0 + 6h + 1min;
  rig.start(inventory_text(rig.dir.path), options);
  const auto after = plain(rig.service->drives());
  CHECK(after == before);
  // The same state is not notified twice across the restart.
  rig.at(t0 + 6h + 15min);
  CHECK(rig.take_events().empty());
  CHECK(drive(*rig.service, "press3/x")["status"] == "drift");
}

TEST_CASE(
    "serve: a service started on an archive without a states file takes the last backups "
    "from the archive's history",
    "[serve][service_approved]") {
  ServiceRig rig("serve-restart-history");
  write_axis(rig.dir.path / "a.json", 0x11);
  write_axis(rig.dir.path / "b.json", 0x12);
  rig.start(inventory_text(rig.dir.path));
  rig.at(rig.now);
  rig.service.reset();
  fs::remove(rig.dir.path / "archive/.git/lmcfg-serve/states.json");
  rig.start(inventory_text(rig.dir.path));
  const auto z = drive(*rig.service, "press3/z");
  CHECK(z["status"] == "unknown");
  CHECK(z["message"] == "not read since the service started");
  // The commit time of the first backup (git's clock, not the test's): a time, not null.
  CHECK(z["last_backup"].is_string());
  CHECK(z["approved"]["kind"] == "commissioning");
}

TEST_CASE("http: approve's reason and ticket pass the text rules: 400 naming the field",
          "[serve][service_approved][http][git-cli]") {
  Rig rig;
  rig.at(rig.now);
  const std::string commissioned = head_of(rig.dir.path / "archive");
  Server server(*rig.service);
  httplib::Client c("127.0.0.1", server.port);
  const std::string path = "/api/v1/drives/press3/z/approve";
  const std::string rest = "): give one line without control characters";
  const std::vector<std::pair<nlohmann::json, std::string>> refused{
      {{{"reason", "fix\r\nOperator: mallory"}},
       "reason contains a control character (0x0D at offset 3" + rest},
      {{{"reason", "red \x1B[31m"}},
       "reason contains a control character (0x1B at offset 4" + rest},
      {{{"reason", "bell\x07"}}, "reason contains a control character (0x07 at offset 4" + rest},
      {{{"reason", std::string("nul\0x", 5)}},
       "reason contains a control character (0x00 at offset 3" + rest},
      {{{"reason", std::string(3000, 'r')}},
       "reason is 3000 bytes long, at most 200 are accepted: shorten it"},
      {{{"reason", "r"}, {"ticket", "T-1\nOperator: mallory"}},
       "ticket contains a control character (0x0A at offset 3" + rest},
      {{{"reason", "r"}, {"ticket", std::string(65, 't')}},
       "ticket is 65 bytes long, at most 64 are accepted: shorten it"},
  };
  for (const auto& [body, message] : refused) {
    INFO(body.dump());
    auto res = c.Post(path.c_str(), body.dump(), "application/json");
    REQUIRE(res);
    CHECK(res->status == 400);
    CHECK(nlohmann::json::parse(res->body) == nlohmann::json{{"error", message}, {"exit_code", 2}});
  }
  // Nothing recorded: the commissioning approval stands.
  CHECK((*rig.service->drive("press3/z"))["approved"]["rev"] == commissioned);
  CHECK((*rig.service->drive("press3/z"))["approved"]["kind"] == "commissioning");
}

TEST_CASE(
    "http: POST /api/v1/drives/{name}/approve: viewer 403, reason required 400, bad revision "
    "404, approved 200, then GET shows it",
    "[serve][service_approved][http][git-cli]") {
  Rig rig;
  rig.at(rig.now);
  const std::string commissioned = head_of(rig.dir.path / "archive");
  const std::string file = (rig.dir.path / "tokens").string();
  const auto viewer = *serve::add_token(file, "grafana", serve::Role::viewer);
  const auto op = *serve::add_token(file, "ana", serve::Role::operator_);
  Server server(*rig.service, *serve::load_tokens(file));
  httplib::Client c("127.0.0.1", server.port);
  const httplib::Headers as_viewer{{"Authorization", "Bearer " + viewer}};
  const httplib::Headers as_op{{"Authorization", "Bearer " + op}};
  const std::string path = "/api/v1/drives/press3/z/approve";

  auto res = c.Post(path.c_str(), as_viewer, "{\"reason\": \"x\"}", "application/json");
  REQUIRE(res);
  CHECK(res->status == 403);
  CHECK(nlohmann::json::parse(res->body) ==
        nlohmann::json{{"error", "token 'grafana' has role viewer: POST needs role operator"},
                       {"exit_code", 2}});

  res = c.Post(path.c_str(), as_op, "{\"rev\": \"HEAD\"}", "application/json");
  REQUIRE(res);
  CHECK(res->status == 400);
  CHECK(nlohmann::json::parse(res->body) ==
        nlohmann::json{{"error",
                        "approving press3/z needs a reason (why this configuration is the one "
                        "the position should hold); nothing recorded"},
                       {"exit_code", 2}});

  res = c.Post(path.c_str(), as_op, "{\"reason\": 5}", "application/json");
  REQUIRE(res);
  CHECK(res->status == 400);
  CHECK(nlohmann::json::parse(res->body)["error"] == "\"reason\" must be a string");

  res = c.Post(path.c_str(), as_op, "{\"rev\": \"HEAD~7\", \"reason\": \"r\"}", "application/json");
  REQUIRE(res);
  CHECK(res->status == 404);
  CHECK(nlohmann::json::parse(res->body)["exit_code"] == 2);

  res = c.Post("/api/v1/drives/press9/q/approve", as_op, "{\"reason\": \"r\"}", "application/json");
  REQUIRE(res);
  CHECK(res->status == 404);
  CHECK(nlohmann::json::parse(res->body)["error"] == "no drive named 'press9/q' in the inventory");

  res = c.Post(path.c_str(), as_op,
               "{\"rev\": \"HEAD\", \"reason\": \"re-commissioned after the rebuild\", "
               "\"ticket\": \"T-3\"}",
               "application/json");
  REQUIRE(res);
  CHECK(res->status == 200);
  const auto a = nlohmann::json::parse(res->body);
  CHECK(a["rev"] == commissioned);  // resolved to the commit id
  CHECK(a["who"] == "ana");
  CHECK(a["ticket"] == "T-3");
  CHECK(a["job"].is_string());
  rig.service->wait_idle();

  res = c.Get("/api/v1/drives/press3/z", as_viewer);
  REQUIRE(res);
  const auto d = nlohmann::json::parse(res->body);
  CHECK(d["status"] == "ok");
  CHECK(d["approved"]["who"] == "ana");
  CHECK(d["approved"]["reason"] == "re-commissioned after the rebuild");
  CHECK(d["approved"]["time"] == "2027-01-15T08:00:00Z");
}

TEST_CASE("serve: /metrics counts positions per status against the approved configuration",
          "[serve][service_approved][metrics]") {
  Rig rig;
  rig.at(rig.now);
  write_axis(rig.dir.path / "b.json", 0x12, "0010", 7);
  rig.at(rig.now + 6h);  // archived, still drift
  const std::string text = rig.service->metrics();
  CHECK(text.find("lmcfg_drives{status=\"ok\"} 1\n") != std::string::npos);
  CHECK(text.find("lmcfg_drives{status=\"drift\"} 1\n") != std::string::npos);
  CHECK(text.find("lmcfg_drives{status=\"unknown\"} 0\n") != std::string::npos);
  CHECK(text.find("lmcfg_drive_drift{drive=\"press3/x\",line=\"line1\"} 1\n") != std::string::npos);
}

}  // namespace serve_test_service_approved
