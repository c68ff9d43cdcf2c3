#pragma once
// The HTTP side of lmcfg serve as a fuzz entry, shared by the libFuzzer
// target (fuzz/fuzz_http.cpp) and the regression test
// (tests/serve/test_http_fuzz.cpp): raw bytes of one connection go through
// the real parser, Host/Origin checks, routes and handlers of an HttpServer
// over a real Service (in-process, no socket), without tokens or with them.
// Invariants: the process survives; every answer is an HTTP/1.1 response
// whose Content-Length is its body's; a JSON answer parses.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "../tests/support/files.hpp"
#include "fleet/inventory.hpp"
#include "link/port.hpp"
#include "serve/http.hpp"
#include "serve/service.hpp"
#include "serve/sha256.hpp"

namespace lmcfg::fuzz {

[[noreturn]] inline void http_fail(const char* what, const std::string& detail = {}) {
  std::fprintf(stderr, "fuzz invariant violated: %s %s\n", what, detail.c_str());
  std::abort();
}

// A service over one line whose port does not exist (its jobs fail at once,
// as a line with its adapter unplugged), on an archive of its own, and its
// HTTP side bound on 127.0.0.1 (never served: answer() is called directly).
// The token "fuzz-operator" has role operator, "fuzz-viewer" viewer.
struct HttpTarget {
  std::filesystem::path dir;
  std::unique_ptr<serve::Service> service;
  std::unique_ptr<serve::HttpServer> http;
  ~HttpTarget() {
    http.reset();
    service.reset();
    std::error_code ec;
    lmcfg::test::remove_tree(dir, ec);
  }

  explicit HttpTarget(bool tokens) {
    namespace fs = std::filesystem;
    static int made = 0;
    dir = fs::temp_directory_path() /
          ("lmcfg-fuzz-http-" + std::to_string(::getpid()) + "-" + std::to_string(made++));
    lmcfg::test::remove_tree(dir);
    fs::create_directories(dir);
    auto inv = fleet::parse_inventory(
        "[[line]]\nname = \"line1\"\nport = \"/nonexistent/lmcfg-fuzz-tty\"\n"
        "[[line.drive]]\nname = \"press3/z\"\nid = 0x11\n"
        "[[line.drive]]\nname = \"press3/x\"\nid = 0x12\n",
        "plant.toml");
    if (!inv.ok()) http_fail("inventory", inv.error().message);
    serve::ServiceOptions so;
    so.inventory = *inv;
    so.archive = (dir / "archive").string();
    for (const auto& l : inv->lines) {
      link::LinkSpec spec;
      spec.port = *link::parse_port(l.port);
      so.links.push_back(spec);
    }
    auto s = serve::Service::create(std::move(so));
    if (!s.ok()) http_fail("service", s.error().message);
    service = std::move(s).value();
    serve::HttpOptions ho;
    ho.listen = {"127.0.0.1", 0};
    ho.exit_code = [](const Error&) { return 4; };
    ho.allowed_hosts = {"fuzz"};  // the seeds' Host (the bound port is not known to them)
    if (tokens)
      ho.tokens = std::vector<serve::TokenEntry>{
          {"op", serve::Role::operator_, serve::sha256_hex("fuzz-operator")},
          {"viewer", serve::Role::viewer, serve::sha256_hex("fuzz-viewer")}};
    http = std::make_unique<serve::HttpServer>(*service, ho);
    auto port = http->bind();
    if (!port.ok()) http_fail("bind", port.error().message);
  }
};

// Checks the answers: a sequence of HTTP/1.1 responses, each with its body.
inline void check_answers(std::string_view out) {
  while (!out.empty()) {
    if (out.substr(0, 9) != "HTTP/1.1 ")
      http_fail("not a response", std::string(out.substr(0, 40)));
    const auto head_end = out.find("\r\n\r\n");
    if (head_end == std::string_view::npos) http_fail("no end of head");
    const std::string_view head = out.substr(0, head_end);
    std::size_t length = 0;
    const auto cl = head.find("\r\nContent-Length: ");
    if (cl != std::string_view::npos) length = std::stoul(std::string(head.substr(cl + 18, 12)));
    // A HEAD answer has a Content-Length and no body: the next answer (or
    // nothing) follows its head. No body of lmcfg's begins with "HTTP/1.1 ".
    const bool bodiless = out.size() == head_end + 4 || out.substr(head_end + 4, 9) == "HTTP/1.1 ";
    if (bodiless) length = 0;
    if (out.size() < head_end + 4 + length) http_fail("body shorter than Content-Length");
    const std::string_view body = out.substr(head_end + 4, length);
    if (!bodiless && head.find("\r\nContent-Type: application/json") != std::string_view::npos &&
        nlohmann::json::parse(body, nullptr, false).is_discarded())
      http_fail("a JSON answer that does not parse", std::string(body.substr(0, 200)));
    out.remove_prefix(head_end + 4 + length);
  }
}

// Byte 0: bit 0 tokens, bit 1 TLS (as the server marks HTTPS requests); the
// rest is what one client sent on one connection.
inline void http_entry(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return;
  static HttpTarget plain(false), with_tokens(true);
  HttpTarget& t = (data[0] & 1) ? with_tokens : plain;
  const std::string_view bytes(reinterpret_cast<const char*>(data + 1), size - 1);
  check_answers(t.http->answer(bytes, "127.0.0.1", (data[0] & 2) != 0));
}

}  // namespace lmcfg::fuzz
