// HTTPS of lmcfg serve (lib/web/web_tls.cpp): the files' loading with its
// message, and the protocol policy checked with the real `openssl s_client`:
// TLS 1.3 and TLS 1.2 with forward-secret AEAD suites are accepted, older
// protocols and other TLS 1.2 suites are refused.
#include <catch2/catch.hpp>
#include <cstdio>
#include <filesystem>
#include <thread>

#include "files.hpp"
#include "web/web_server.hpp"
#include "web/web_tls.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace web_test_web_tls {

using namespace lmcfg;
using namespace lmcfg::web;
namespace fs = std::filesystem;

namespace {

void make_certificate(const fs::path& dir) {
  const std::string cmd = "cd '" + dir.string() +
                          "' && openssl req -x509 -newkey ec -pkeyopt "
                          "ec_paramgen_curve:prime256v1 -nodes -keyout key.pem -out cert.pem "
                          "-days 2 -subj /CN=127.0.0.1 >openssl.txt 2>&1";
  REQUIRE(std::system(cmd.c_str()) == 0);
}

// Whether `openssl s_client ARGS` completes a handshake with the server.
bool handshake(int port, const std::string& args) {
  const std::string cmd =
      "echo | timeout 10 openssl s_client -connect 127.0.0.1:" + std::to_string(port) + " " + args +
      " >/dev/null 2>&1";
  return std::system(cmd.c_str()) == 0;
}

}  // namespace

TEST_CASE("web tls: files that do not load are named, with what is expected", "[web][web_tls]") {
  test::ScratchDir dir("web-tls-files");
  make_certificate(dir.path);
  const std::string cert = (dir.path / "cert.pem").string(), key = (dir.path / "key.pem").string();
  CHECK(TlsContext::load(cert, key).ok());
  for (const auto& [c, k] : std::vector<std::pair<std::string, std::string>>{
           {cert, cert}, {key, key}, {cert, "/nonexistent/key.pem"}, {"/nonexistent", key}}) {
    auto r = TlsContext::load(c, k);
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().code == Errc::file_error);
    CHECK(r.error().message == "--tls-cert " + c + " / --tls-key " + k +
                                   ": cannot load them as a PEM certificate and its private key "
                                   "(readable files, the key matching the certificate)");
  }
}

TEST_CASE("web tls: TLS 1.3, TLS 1.2 with ECDHE and AEAD only (checked with openssl s_client)",
          "[web][web_tls]") {
  test::ScratchDir dir("web-tls-policy");
  make_certificate(dir.path);
  auto ctx = TlsContext::load((dir.path / "cert.pem").string(), (dir.path / "key.pem").string());
  REQUIRE(ctx.ok());
  ServerOptions o;
  o.tls = *ctx;
  o.handle = [](Request&, Response& res) { res.set_content("ok\n", "text/plain"); };
  Server server(std::move(o));
  auto port = server.bind("127.0.0.1", 0);
  REQUIRE(port.ok());
  std::thread t([&] { server.serve(); });
  CHECK(handshake(*port, "-tls1_3"));
  CHECK(handshake(*port, "-tls1_2 -cipher ECDHE-ECDSA-AES128-GCM-SHA256"));
  CHECK(handshake(*port, "-tls1_2 -cipher ECDHE-ECDSA-CHACHA20-POLY1305"));
  CHECK_FALSE(handshake(*port, "-tls1_2 -cipher ECDHE-ECDSA-AES128-SHA256"));  // not AEAD
  CHECK_FALSE(handshake(*port, "-tls1_2 -cipher ECDHE-ECDSA-AES256-SHA"));     // CBC
  CHECK_FALSE(handshake(*port, "-tls1_1"));
  // A plain-HTTP client on the TLS port fails its handshake; the server goes on.
  CHECK(std::system(("curl -s -m 5 -o /dev/null http://127.0.0.1:" + std::to_string(*port) + "/")
                        .c_str()) != 0);
  CHECK(
      std::system(("curl -s -k -m 5 -o /dev/null https://127.0.0.1:" + std::to_string(*port) + "/")
                      .c_str()) == 0);
  server.stop();
  t.join();
}

}  // namespace web_test_web_tls
