// The HTTP side of lmcfg serve (lib/serve/http.cpp): --listen parsing, the
// loopback rule and its exposure checks with their exact messages, TLS files
// made by the real openssl, binding, and the REST API's routes over real HTTP
// on 127.0.0.1 (cpp-httplib's client) with the service on simulated drives.
#include <httplib.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <mutex>
#include <nlohmann/json.hpp>

#include "files.hpp"
#include "raw_http.hpp"
#include "serve/http.hpp"
#include "serve/tokens.hpp"
#include "serve_rig.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace serve_test_http {

using namespace lmcfg;
using namespace lmcfg::test;
namespace fs = std::filesystem;

namespace {

std::string listen_message(const std::string& text) {
  return "--listen '" + text +
         "' is not HOST:PORT (e.g. 127.0.0.1:8470, [::1]:8470; PORT 0..65535)";
}

nlohmann::json body_of(const httplib::Result& res) { return nlohmann::json::parse(res->body); }

}  // namespace

TEST_CASE("serve: the REST API over HTTP on 127.0.0.1", "[serve][http]") {
  Rig rig;
  rig.at(rig.now);
  Server server(*rig.service);
  httplib::Client c("127.0.0.1", server.port);

  auto res = c.Get("/api/v1/drives");
  REQUIRE(res);
  CHECK(res->status == 200);
  auto all = nlohmann::json::parse(res->body);
  REQUIRE(all.size() == 2);
  CHECK(all[0]["name"] == "press3/z");
  CHECK(all[0]["line"] == "line1");
  CHECK(all[0]["status"] == "ok");
  CHECK(all[0]["message"] == "matches the approved configuration");
  CHECK(all[0]["differences"] == 0);

  res = c.Get("/api/v1/drives/press3/x");
  REQUIRE(res);
  CHECK(res->status == 200);
  CHECK(nlohmann::json::parse(res->body)["name"] == "press3/x");

  res = c.Get("/api/v1/drives/press3/x/history");
  REQUIRE(res);
  CHECK(res->status == 200);
  CHECK(nlohmann::json::parse(res->body).size() == 1);

  res = c.Get("/api/v1/drives/press9/q");
  REQUIRE(res);
  CHECK(res->status == 404);
  CHECK(nlohmann::json::parse(res->body) ==
        nlohmann::json{{"error", "no drive named 'press9/q' in the inventory"}, {"exit_code", 2}});

  res = c.Post("/api/v1/lines/line1/backup", "", "application/json");
  REQUIRE(res);
  CHECK(res->status == 202);
  const std::string id = nlohmann::json::parse(res->body)["job"];
  rig.service->wait_idle();
  res = c.Get(("/api/v1/jobs/" + id).c_str());
  REQUIRE(res);
  auto job = nlohmann::json::parse(res->body);
  CHECK(job["state"] == "done");
  CHECK(job["drives"] == 2);
  CHECK(job["done"] == 2);
  CHECK(job["counts"]["unchanged"] == 2);

  res = c.Post("/api/v1/drives/press3/z/backup", "", "application/json");
  REQUIRE(res);
  CHECK(res->status == 202);
  rig.service->wait_idle();

  res = c.Get("/api/v1/jobs/999");
  REQUIRE(res);
  CHECK(res->status == 404);
  CHECK(nlohmann::json::parse(res->body)["error"] == "no job 999");
  res = c.Get("/api/v2/nothing");
  REQUIRE(res);
  CHECK(res->status == 404);
  CHECK(nlohmann::json::parse(res->body)["error"] == "no such resource: GET /api/v2/nothing");
  res = c.Post("/api/v1/lines/line1/backup", std::string(10000, 'x'), "application/json");
  REQUIRE(res);
  CHECK(res->status == 413);
}

TEST_CASE("serve: bearer tokens: 401 without or with a bad token, 403 for a viewer's POST",
          "[serve][http]") {
  Rig rig;
  const std::string file = (rig.dir.path / "tokens").string();
  const auto viewer = *serve::add_token(file, "grafana", serve::Role::viewer);
  const auto op = *serve::add_token(file, "ops", serve::Role::operator_);
  Server server(*rig.service, *serve::load_tokens(file));
  httplib::Client c("127.0.0.1", server.port);

  auto res = c.Get("/api/v1/drives");
  REQUIRE(res);
  CHECK(res->status == 401);
  CHECK(nlohmann::json::parse(res->body)["error"] ==
        "a bearer token is needed (Authorization: Bearer TOKEN)");
  res = c.Get("/metrics", {{"Authorization", "Bearer " + std::string(64, '0')}});
  REQUIRE(res);
  CHECK(res->status == 401);
  CHECK(nlohmann::json::parse(res->body)["error"] == "the bearer token is not in the tokens file");
  res = c.Get("/api/v1/drives", {{"Authorization", "Bearer " + viewer}});
  REQUIRE(res);
  CHECK(res->status == 200);
  res = c.Post("/api/v1/lines/line1/backup", {{"Authorization", "Bearer " + viewer}}, "",
               "application/json");
  REQUIRE(res);
  CHECK(res->status == 403);
  CHECK(nlohmann::json::parse(res->body) ==
        nlohmann::json{{"error", "token 'grafana' has role viewer: POST needs role operator"},
                       {"exit_code", 2}});
  res = c.Post("/api/v1/lines/line1/backup", {{"Authorization", "Bearer " + op}}, "",
               "application/json");
  REQUIRE(res);
  CHECK(res->status == 202);
  rig.service->wait_idle();
}

TEST_CASE("http: parse_listen takes HOST:PORT and [IPv6]:PORT, ports 0 to 65535", "[serve][http]") {
  auto a = serve::parse_listen("127.0.0.1:8470");
  REQUIRE(a.ok());
  CHECK(a->host == "127.0.0.1");
  CHECK(a->port == 8470);
  a = serve::parse_listen("[::1]:0");
  REQUIRE(a.ok());
  CHECK(a->host == "::1");
  CHECK(a->port == 0);
  a = serve::parse_listen("localhost:65535");
  REQUIRE(a.ok());
  CHECK(a->host == "localhost");
  CHECK(a->port == 65535);
  // The port is what follows the last colon: an IPv6 address without brackets still parses.
  a = serve::parse_listen("::1:80");
  REQUIRE(a.ok());
  CHECK(a->host == "::1");
  CHECK(a->port == 80);
  a = serve::parse_listen("0.0.0.0:00080");
  REQUIRE(a.ok());
  CHECK(a->port == 80);

  for (const std::string& bad : std::vector<std::string>{
           "", "127.0.0.1", "127.0.0.1:", ":8470", "[]:8470", "127.0.0.1:65536", "127.0.0.1:99999",
           "127.0.0.1:123456", "127.0.0.1:-1", "127.0.0.1:+80", "127.0.0.1:80a", "127.0.0.1: 80",
           "127.0.0.1:http"}) {
    INFO("--listen '" << bad << "'");
    auto r = serve::parse_listen(bad);
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().code == Errc::invalid_argument);
    CHECK(r.error().message == listen_message(bad));
  }
}

TEST_CASE("http: is_loopback is 127.0.0.0/8, ::1 and localhost, not names that look like them",
          "[serve][http]") {
  for (const std::string& yes : std::vector<std::string>{
           "127.0.0.1", "127.255.255.254", "127.1.2.3", "::1", "0:0:0:0:0:0:0:1", "localhost"})
    CHECK(serve::is_loopback(yes));
  for (const std::string& no : std::vector<std::string>{
           "0.0.0.0", "10.0.0.5", "128.0.0.1", "::", "::2", "", "127.example.com",
           "127.0.0.1.nip.io", "localhost.example.com", "LOCALHOST.", "[::1]", "127.0.0.1:8470"}) {
    INFO(no);
    CHECK_FALSE(serve::is_loopback(no));
  }
}

TEST_CASE("http: check_exposure: loopback alone, other hosts need tokens and TLS, both TLS files",
          "[serve][http]") {
  serve::HttpOptions o;
  o.listen = {"127.0.0.1", 8470};
  CHECK(serve::check_exposure(o, "127.0.0.1:8470").ok());
  o.listen = {"::1", 8470};
  CHECK(serve::check_exposure(o, "[::1]:8470").ok());

  o.listen = {"0.0.0.0", 8470};
  auto r = serve::check_exposure(o, "0.0.0.0:8470");
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == Errc::invalid_argument);
  CHECK(r.error().message ==
        "--listen 0.0.0.0:8470 is not a loopback address: serving other hosts needs --tokens and "
        "--tls-cert/--tls-key (missing: --tokens and --tls-cert/--tls-key; docs/serve.md "
        "\"Security model\")");
  o.tokens = std::vector<serve::TokenEntry>{};
  r = serve::check_exposure(o, "0.0.0.0:8470");
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().message ==
        "--listen 0.0.0.0:8470 is not a loopback address: serving other hosts needs --tokens and "
        "--tls-cert/--tls-key (missing: --tls-cert/--tls-key; docs/serve.md \"Security model\")");
  o.tokens.reset();
  o.tls_cert = "c.pem";
  o.tls_key = "k.pem";
  r = serve::check_exposure(o, "0.0.0.0:8470");
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().message ==
        "--listen 0.0.0.0:8470 is not a loopback address: serving other hosts needs --tokens and "
        "--tls-cert/--tls-key (missing: --tokens; docs/serve.md \"Security model\")");
  o.tokens = std::vector<serve::TokenEntry>{};
  CHECK(serve::check_exposure(o, "0.0.0.0:8470").ok());

  // A name that starts like a loopback address is another host.
  o.tokens.reset();
  o.tls_cert.clear();
  o.tls_key.clear();
  o.listen = {"127.example.com", 8470};
  r = serve::check_exposure(o, "127.example.com:8470");
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().message.rfind("--listen 127.example.com:8470 is not a loopback address", 0) == 0);

  // One TLS file without the other, on any address.
  o.listen = {"127.0.0.1", 8470};
  for (bool cert : {true, false}) {
    o.tls_cert = cert ? "c.pem" : "";
    o.tls_key = cert ? "" : "k.pem";
    r = serve::check_exposure(o, "127.0.0.1:8470");
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().code == Errc::invalid_argument);
    CHECK(r.error().message ==
          "--tls-cert and --tls-key go together (the certificate and its private key)");
  }
}

// HTTPS: OpenSSL's; the Windows build has none (lib/web/web_tls_win32.cpp).
#ifndef _WIN32
// A self-signed certificate for 127.0.0.1 and its key, made by openssl as an
// operator would (an EC key: quick to make); NAME-cert.pem, NAME-key.pem.
void make_certificate(const fs::path& dir, const std::string& name) {
  const std::string cmd = "cd '" + dir.string() +
                          "' && openssl req -x509 -newkey ec -pkeyopt "
                          "ec_paramgen_curve:prime256v1 -nodes -keyout " +
                          name + "-key.pem -out " + name +
                          "-cert.pem -days 2 -subj /CN=127.0.0.1 -addext "
                          "subjectAltName=IP:127.0.0.1 >openssl.txt 2>&1";
  REQUIRE(std::system(cmd.c_str()) == 0);
}

TEST_CASE(
    "http: check_tls_files loads an openssl certificate, refuses missing files and a "
    "key of another certificate",
    "[serve][http]") {
  ScratchDir d("http-tls");
  serve::HttpOptions o;
  CHECK(serve::check_tls_files(o).ok());  // no TLS: nothing to check

  make_certificate(d.path, "a");
  make_certificate(d.path, "b");
  const std::string cert = (d.path / "a-cert.pem").string();
  o.tls_cert = cert;
  o.tls_key = (d.path / "a-key.pem").string();
  CHECK(serve::check_tls_files(o).ok());

  auto refused = [&](const std::string& c, const std::string& k) {
    o.tls_cert = c;
    o.tls_key = k;
    auto r = serve::check_tls_files(o);
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().code == Errc::file_error);
    CHECK(r.error().message == "--tls-cert " + c + " / --tls-key " + k +
                                   ": cannot load them as a PEM certificate and its private "
                                   "key (readable files, the key matching the certificate)");
  };
  refused(cert, (d.path / "b-key.pem").string());    // another certificate's key
  refused(cert, (d.path / "missing.pem").string());  // no such file
  refused((d.path / "a-key.pem").string(), cert);    // swapped
  spit(d.path / "empty.pem", "");
  refused((d.path / "empty.pem").string(), (d.path / "a-key.pem").string());
}

TEST_CASE("http: HTTPS with an openssl certificate answers a client that trusts it",
          "[serve][http]") {
  ScratchDir d("http-https");
  make_certificate(d.path, "s");
  Rig rig;
  auto o = Server::options();
  o.tls_cert = (d.path / "s-cert.pem").string();
  o.tls_key = (d.path / "s-key.pem").string();
  Server server(*rig.service, o);
  httplib::SSLClient c("127.0.0.1", server.port);
  c.set_ca_cert_path((d.path / "s-cert.pem").string().c_str());
  c.enable_server_certificate_verification(true);
  auto res = c.Get("/api/v1/drives");
  REQUIRE(res);
  CHECK(res->status == 200);
  CHECK(body_of(res).size() == 2);
  // Plain HTTP on the HTTPS port gets no HTTP answer.
  httplib::Client plain("127.0.0.1", server.port);
  plain.set_read_timeout(2);
  auto p = plain.Get("/api/v1/drives");
  CHECK((!p || p->status != 200));
}

#endif

TEST_CASE("http: a stop at any moment of the start ends serve()", "[serve][http]") {
  Rig rig;
  // Stopped before serve() begins: serve() returns at once.
  {
    serve::HttpServer h(*rig.service, Server::options());
    REQUIRE(h.bind().ok());
    h.stop();
    h.serve();  // returns: the test would hang here otherwise
  }
  // Stopped while the serving thread starts (a SIGTERM right after the start):
  // each server's destructor joins its thread, which has ended.
  for (int i = 0; i < 50; ++i) Server s(*rig.service);
  // Stopped while serving, after an answer.
  Server served(*rig.service);
  CHECK(httplib::Client("127.0.0.1", served.port).Get("/api/v1/drives"));
}

TEST_CASE("http: bind names the address it cannot listen on, and unloadable TLS files",
          "[serve][http]") {
  Rig rig;
  Server first(*rig.service);
  auto o = Server::options();
  o.listen = {"127.0.0.1", first.port};
  serve::HttpServer second(*rig.service, o);
  auto r = second.bind();
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == Errc::io_error);
  CHECK(r.error().message == "cannot listen on 127.0.0.1:" + std::to_string(first.port) +
                                 " (address in use or not on this host)");

  o.listen = {"127.0.0.1", 0};
  o.tls_cert = (rig.dir.path / "no-cert.pem").string();
  o.tls_key = (rig.dir.path / "no-key.pem").string();
  serve::HttpServer tls(*rig.service, o);
  r = tls.bind();
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == Errc::file_error);
  CHECK(r.error().message == "--tls-cert " + o.tls_cert + " / --tls-key " + o.tls_key +
                                 ": cannot load them as a PEM certificate and its private key "
                                 "(readable files, the key matching the certificate)");
}

TEST_CASE("http: bodies and parameters are checked: 400 with the message and exit code 2",
          "[serve][http]") {
  Rig rig;
  rig.at(rig.now);
  Server server(*rig.service);
  httplib::Client c("127.0.0.1", server.port);
  auto error = [](const std::string& message, int code) {
    return nlohmann::json{{"error", message}, {"exit_code", code}};
  };

  auto res = c.Post("/api/v1/drives/press3/z/plan", "[1,2]", "application/json");
  REQUIRE(res);
  CHECK(res->status == 400);
  CHECK(res->get_header_value("Content-Type") == "application/json");
  CHECK(body_of(res) == error("the request body is not a JSON object", 2));
  res = c.Post("/api/v1/drives/press3/z/plan", "{not json", "application/json");
  REQUIRE(res);
  CHECK(res->status == 400);
  CHECK(body_of(res) == error("the request body is not a JSON object", 2));
  res = c.Post("/api/v1/drives/press3/z/plan", R"({"rev": 5})", "application/json");
  REQUIRE(res);
  CHECK(res->status == 400);
  CHECK(body_of(res) == error("\"rev\" must be a string", 2));

  res = c.Post("/api/v1/plans/0123abcd/execute", R"({"reason": ["a"]})", "application/json");
  REQUIRE(res);
  CHECK(res->status == 400);
  CHECK(body_of(res) == error("\"reason\" must be a string", 2));
  res = c.Post("/api/v1/plans/0123abcd/execute", R"({"reason": "r", "ticket": 7})",
               "application/json");
  REQUIRE(res);
  CHECK(body_of(res) == error("\"ticket\" must be a string", 2));
  res = c.Post("/api/v1/plans/0123abcd/execute", R"({"reason": "r", "skip_incompatible": "yes"})",
               "application/json");
  REQUIRE(res);
  CHECK(res->status == 400);
  CHECK(body_of(res) == error("\"skip_incompatible\" must be true or false", 2));
  // Well-formed, but no such plan: the service's not_found is a 404.
  res = c.Post("/api/v1/plans/0123abcd/execute", R"({"reason": null, "skip_incompatible": true})",
               "application/json");
  REQUIRE(res);
  CHECK(res->status == 404);
  CHECK(body_of(res) == error("no plan '0123abcd'", 2));
  // A plan id is lower-case hex: anything else is no route at all.
  res = c.Post("/api/v1/plans/XYZ/execute", "", "application/json");
  REQUIRE(res);
  CHECK(res->status == 404);
  CHECK(body_of(res) == error("no such resource: POST /api/v1/plans/XYZ/execute", 2));

  res = c.Get("/api/v1/drives/press3/z/diff");
  REQUIRE(res);
  CHECK(res->status == 400);
  CHECK(body_of(res) == error("from=REV is needed (to=REV or to=live, default live)", 2));
  res = c.Get("/api/v1/drives/press3/z/report?rev=nosuchrev");
  REQUIRE(res);
  CHECK(res->status == 404);
  res = c.Get("/api/v1/drives/press3/z/report");
  REQUIRE(res);
  CHECK(res->status == 200);
  CHECK(res->get_header_value("Content-Type") == "text/html; charset=utf-8");

  // The body limit is HttpOptions::max_body (4096 bytes by default).
  res = c.Post("/api/v1/drives/press3/z/plan", "{\"rev\":\"" + std::string(4200, 'a') + "\"}",
               "application/json");
  REQUIRE(res);
  CHECK(res->status == 413);
  CHECK(body_of(res) ==
        error("the request body has 4210 bytes, more than the 4096 this service accepts", 2));
}

TEST_CASE(
    "http: each request logged, 503 once the service stops, exit code 70 without the "
    "CLI's mapping",
    "[serve][http]") {
  Rig rig;
  std::mutex mu;
  std::vector<std::string> log;
  auto o = Server::options();
  o.exit_code = nullptr;
  o.log = [&](const std::string& s) {
    std::lock_guard<std::mutex> lock(mu);
    log.push_back(s);
  };
  {
    Server server(*rig.service, o);
    httplib::Client c("127.0.0.1", server.port);

    auto res = c.Get("/api/v1/drives/press9/q");
    REQUIRE(res);
    CHECK(res->status == 404);
    CHECK(body_of(res) == nlohmann::json{{"error", "no drive named 'press9/q' in the inventory"},
                                         {"exit_code", 70}});
    // A request the server answers itself keeps its own exit code 2.
    res = c.Get("/nothing");
    REQUIRE(res);
    CHECK(body_of(res)["exit_code"] == 2);

    rig.service->stop();
    res = c.Post("/api/v1/drives/press3/z/backup", "", "application/json");
    REQUIRE(res);
    CHECK(res->status == 503);
    CHECK(body_of(res) == nlohmann::json{{"error", "the service is stopping"}, {"exit_code", 70}});
  }  // the server stopped: every request's line is logged (after its answer)
  std::lock_guard<std::mutex> lock(mu);
  // (each line is logged after its answer is sent: sorted, not in order)
  std::sort(log.begin(), log.end());
  CHECK(log == std::vector<std::string>{"http 127.0.0.1 GET /api/v1/drives/press9/q 404",
                                        "http 127.0.0.1 GET /nothing 404",
                                        "http 127.0.0.1 POST /api/v1/drives/press3/z/backup 503"});
}

TEST_CASE("http: a viewer may HEAD and GET, any case of Bearer, the token's name is who asked",
          "[serve][http]") {
  Rig rig;
  rig.at(rig.now);
  const std::string file = (rig.dir.path / "tokens").string();
  const auto viewer = *serve::add_token(file, "grafana", serve::Role::viewer);
  const auto op = *serve::add_token(file, "night-shift", serve::Role::operator_);
  Server server(*rig.service, *serve::load_tokens(file));
  httplib::Client c("127.0.0.1", server.port);

  auto res = c.Head("/metrics", {{"Authorization", "Bearer " + viewer}});
  REQUIRE(res);
  CHECK(res->status == 200);
  // RFC 7235 §2.1: the scheme's name is case-insensitive; it needs its blank.
  res = c.Get("/metrics", {{"Authorization", "bearer " + viewer}});
  REQUIRE(res);
  CHECK(res->status == 200);
  res = c.Get("/metrics", {{"Authorization", "BEARER " + viewer}});
  REQUIRE(res);
  CHECK(res->status == 200);
  res = c.Get("/metrics", {{"Authorization", "Bearer" + viewer}});
  REQUIRE(res);
  CHECK(res->status == 401);
  CHECK(res->get_header_value("WWW-Authenticate") == "Bearer");
  res = c.Get("/metrics", {{"Authorization", "Basic Z3JhZmFuYTp4"}});
  REQUIRE(res);
  CHECK(res->status == 401);
  res = c.Get("/metrics", {{"Authorization", "Bearer " + viewer + "x"}});
  REQUIRE(res);
  CHECK(res->status == 401);
  CHECK(res->get_header_value("WWW-Authenticate") == "Bearer error=\"invalid_token\"");

  res = c.Post("/api/v1/drives/press3/z/backup", {{"Authorization", "Bearer " + op}}, "",
               "application/json");
  REQUIRE(res);
  CHECK(res->status == 202);
  const std::string id = body_of(res)["job"];
  rig.service->wait_idle();
  res = c.Get(("/api/v1/jobs/" + id).c_str(), {{"Authorization", "Bearer " + viewer}});
  REQUIRE(res);
  CHECK(body_of(res)["who"] == "night-shift");
}

namespace {
// The JSON error of a raw answer (its body after the head).
nlohmann::json raw_body(const std::string& answer) {
  const auto at = answer.find("\r\n\r\n");
  REQUIRE(at != std::string::npos);
  return nlohmann::json::parse(answer.substr(at + 4));
}
std::string status_line(const std::string& answer) { return answer.substr(0, answer.find("\r\n")); }
}  // namespace

TEST_CASE("http: without tokens only this service's own Host names are served (421)",
          "[serve][http]") {
  Rig rig;
  rig.at(rig.now);
  Server server(*rig.service);
  const std::string port = std::to_string(server.port);
  auto ask = [&](const std::string& host) {
    RawClient c(server.port);
    c.send("GET /api/v1/drives HTTP/1.1\r\nHost: " + host + "\r\nConnection: close\r\n\r\n");
    return c.response(5000);
  };
  for (const std::string& host :
       std::vector<std::string>{"127.0.0.1:" + port, "localhost:" + port, "LOCALHOST:" + port})
    CHECK(status_line(ask(host)) == "HTTP/1.1 200 OK");
  // DNS rebinding: evil.example resolves to 127.0.0.1, the browser sends its own name.
  for (const std::string& host :
       std::vector<std::string>{"evil.example:" + port, "127.0.0.1", "127.0.0.1:1",
                                "127.0.0.2:" + port, "[::1]:" + port}) {
    INFO(host);
    const std::string a = ask(host);
    CHECK(status_line(a) == "HTTP/1.1 421 Misdirected Request");
    CHECK(raw_body(a) ==
          nlohmann::json{{"error", "the Host header '" + host +
                                       "' is not this service's address (127.0.0.1:" + port +
                                       "): without --tokens only requests to the listen address "
                                       "are served, so that a web page cannot reach the drives "
                                       "through another name"},
                         {"exit_code", 2}});
  }
  // The console's pages too.
  RawClient c(server.port);
  c.send("GET / HTTP/1.1\r\nHost: evil.example\r\n\r\n");
  CHECK(status_line(c.response(5000)) == "HTTP/1.1 421 Misdirected Request");
}

TEST_CASE(
    "http: a state-changing request from another origin is refused (403), API bodies are JSON "
    "(415)",
    "[serve][http]") {
  Rig rig;
  rig.at(rig.now);
  Server server(*rig.service);
  const std::string own = "127.0.0.1:" + std::to_string(server.port);
  auto post = [&](const std::string& path, const std::string& headers, const std::string& body) {
    RawClient c(server.port);
    c.send("POST " + path + " HTTP/1.1\r\nHost: " + own + "\r\nConnection: close\r\n" + headers +
           "Content-Length: " + std::to_string(body.size()) + "\r\n\r\n" + body);
    return c.response(5000);
  };
  std::string a = post("/api/v1/lines/line1/backup", "Origin: http://evil.example\r\n", "");
  CHECK(status_line(a) == "HTTP/1.1 403 Forbidden");
  CHECK(raw_body(a)["error"] ==
        "cross-origin request refused: Origin 'http://evil.example' is not "
        "this service's origin 'http://" +
            own + "'");
  a = post("/backup", "Origin: null\r\nContent-Type: application/x-www-form-urlencoded\r\n",
           "name=press3%2Fz");
  CHECK(status_line(a) == "HTTP/1.1 403 Forbidden");
  a = post("/api/v1/lines/line1/backup",
           "Sec-Fetch-Site: cross-site\r\nOrigin: http://" + own + "\r\n", "");
  CHECK(status_line(a) == "HTTP/1.1 403 Forbidden");
  CHECK(raw_body(a)["error"] ==
        "cross-site request refused: Sec-Fetch-Site is 'cross-site', a "
        "state-changing request must come from this service's own pages");
  // A browser's own form under Referrer-Policy: no-referrer: "Origin: null",
  // and Sec-Fetch-Site, which a page cannot set, says same-origin.
  a = post("/backup",
           "Origin: null\r\nSec-Fetch-Site: same-origin\r\nContent-Type: "
           "application/x-www-form-urlencoded\r\n",
           "name=press3%2Fz");
  CHECK(status_line(a) == "HTTP/1.1 403 Forbidden");  // the console's CSRF check, not the origin's
  CHECK(a.find("CSRF") != std::string::npos);
  // A plain cross-site form's text/plain body never reaches a route.
  a = post("/api/v1/drives/press3/z/plan", "Content-Type: text/plain\r\n", "{\"rev\": \"\"}");
  CHECK(status_line(a) == "HTTP/1.1 415 Unsupported Media Type");
  CHECK(raw_body(a)["error"] == "the request body must be application/json, not 'text/plain'");
  a = post("/api/v1/drives/press3/z/plan", "", "{\"rev\": \"\"}");
  CHECK(status_line(a) == "HTTP/1.1 415 Unsupported Media Type");
  // The same origin, and curl without Origin: served.
  a = post("/api/v1/lines/line1/backup",
           "Origin: http://" + own + "\r\nSec-Fetch-Site: same-origin\r\n", "");
  CHECK(status_line(a) == "HTTP/1.1 202 Accepted");
  a = post("/api/v1/lines/line1/backup", "Content-Type: application/json; charset=utf-8\r\n", "");
  CHECK(status_line(a) == "HTTP/1.1 202 Accepted");
  rig.service->wait_idle();
}

TEST_CASE(
    "http: every byte 0x00-0xFF in a path, a header and a body field, the service answers after "
    "each",
    "[serve][http]") {
  Rig rig;
  rig.at(rig.now);
  Server server(*rig.service);
  const std::string host = "Host: 127.0.0.1:" + std::to_string(server.port) + "\r\n";
  int answered = 0;
  for (int b = 0; b < 256; ++b) {
    const std::string byte(1, static_cast<char>(b));
    char enc[4];
    std::snprintf(enc, sizeof enc, "%%%02X", b);
    const std::string body =
        std::string("{\"reason\": \"a") + byte + "b\", \"rev\": \"" + enc + "\"}";
    for (const std::string& request : std::vector<std::string>{
             "GET /api/v1/drives/" + std::string(enc) + "x HTTP/1.1\r\n" + host + "\r\n",
             "GET /api/v1/drives/a" + byte + "x HTTP/1.1\r\n" + host + "\r\n",
             "GET /api/v1/drives/press3/z/diff?to=HEAD&from=" + std::string(enc) + " HTTP/1.1\r\n" +
                 host + "\r\n",
             "GET /api/v1/drives HTTP/1.1\r\n" + host + "X-Any: a" + byte + "b\r\n\r\n",
             "POST /api/v1/plans/0123abcd/execute HTTP/1.1\r\n" + host +
                 "Content-Type: application/json\r\nContent-Length: " +
                 std::to_string(body.size()) + "\r\n\r\n" + body,
             "POST /execute HTTP/1.1\r\n" + host +
                 "Content-Type: application/x-www-form-urlencoded\r\nContent-Length: "
                 "25\r\n\r\nplan=0123abcd&reason=a" +
                 enc}) {
      RawClient c(server.port);
      c.send(request);
      const std::string a = c.response(5000);
      INFO(web::printable(request) << " -> " << web::printable(a));
      REQUIRE(a.rfind("HTTP/1.1 ", 0) == 0);
      ++answered;
    }
  }
  CHECK(answered == 256 * 6);
  // ... and it still answers.
  httplib::Client c("127.0.0.1", server.port);
  auto res = c.Get("/api/v1/drives");
  REQUIRE(res);
  CHECK(res->status == 200);
}

}  // namespace serve_test_http
