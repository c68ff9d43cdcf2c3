// lmcfg serve's HTTP messages (lib/web/web_message.cpp): the request
// parser's limits and refusals with their exact statuses and messages (RFC
// 9112), percent-decoding, UTF-8, the log-safe form of client text, and the
// response on the wire.
#include <catch2/catch.hpp>

#include "web/web_message.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace web_test_web_message {

using namespace lmcfg::web;
using State = RequestParser::State;

namespace {

struct Parsed {
  State state = State::need_more;
  int status = 0;
  std::string message;
  Request req;
};

Parsed parse(const std::string& bytes, Limits limits = {}) {
  RequestParser p(limits);
  Parsed r;
  r.state = p.feed(bytes);
  r.status = p.error_status();
  r.message = p.error_message();
  if (r.state == State::complete) r.req = p.request();
  return r;
}

void refused(const std::string& bytes, int status, const std::string& message, Limits limits = {}) {
  INFO(printable(bytes));
  const Parsed r = parse(bytes, limits);
  CHECK(r.state == State::error);
  CHECK(r.status == status);
  CHECK(r.message == message);
}

}  // namespace

TEST_CASE("web message: a GET with its path, query and headers", "[web][web_message]") {
  const Parsed r = parse(
      "GET /api/v1/drives/press3%2Fz/diff?from=HEAD~1&to=live&x=a+b HTTP/1.1\r\n"
      "Host: 127.0.0.1:8470\r\nUser-Agent:  curl/7.88  \r\nhost-extra: 1\r\n\r\n");
  REQUIRE(r.state == State::complete);
  CHECK(r.req.method == "GET");
  CHECK(r.req.target == "/api/v1/drives/press3%2Fz/diff?from=HEAD~1&to=live&x=a+b");
  CHECK(r.req.path == "/api/v1/drives/press3/z/diff");
  CHECK(r.req.get_param_value("from") == "HEAD~1");
  CHECK(r.req.get_param_value("x") == "a b");
  CHECK(r.req.get_header_value("host") == "127.0.0.1:8470");
  CHECK(r.req.get_header_value("USER-AGENT") == "curl/7.88");
  CHECK(r.req.version_minor == 1);
  CHECK(r.req.body.empty());
}

TEST_CASE("web message: bodies by Content-Length and chunked, in pieces of any size",
          "[web][web_message]") {
  const std::string plain =
      "POST /x HTTP/1.1\r\nHost: h\r\nContent-Length: 11\r\n\r\n{\"rev\": 1}\n";
  const std::string chunked =
      "POST /x HTTP/1.1\r\nHost: h\r\nTransfer-Encoding: chunked\r\n\r\n"
      "4;ext=1\r\n{\"re\r\n7\r\nv\": 1}\n\r\n0\r\nTrailer-A: x\r\n\r\n";
  for (const auto& bytes : {plain, chunked}) {
    for (std::size_t step : {std::size_t(1), std::size_t(3), bytes.size()}) {
      RequestParser p(Limits{});
      State s = State::need_more;
      for (std::size_t i = 0; i < bytes.size(); i += step) {
        REQUIRE(s == State::need_more);
        s = p.feed(std::string_view(bytes).substr(i, step));
      }
      REQUIRE(s == State::complete);
      CHECK(p.request().body == "{\"rev\": 1}\n");
    }
  }
}

TEST_CASE("web message: pipelined requests come one at a time", "[web][web_message]") {
  RequestParser p(Limits{});
  REQUIRE(p.feed("GET /a HTTP/1.1\r\nHost: h\r\n\r\n\r\nGET /b HTTP/1.1\r\nHost: h\r\n\r\nGET") ==
          State::complete);
  CHECK(p.request().path == "/a");
  p.next();
  REQUIRE(p.parse() == State::complete);
  CHECK(p.request().path == "/b");
  p.next();
  CHECK(p.parse() == State::need_more);
  CHECK(p.started());
  CHECK(p.feed(" /c HTTP/1.0\n\n") == State::complete);  // bare LF ends lines (RFC 9112 §2.2)
  CHECK(p.request().path == "/c");
  CHECK(p.request().version_minor == 0);
}

TEST_CASE("web message: the body limit holds for every transfer coding (RFC 9112 §6)",
          "[web][web_message]") {
  refused("POST /x HTTP/1.1\r\nHost: h\r\nContent-Length: 4097\r\n\r\n", 413,
          "the request body has 4097 bytes, more than the 4096 this service accepts");
  refused("POST /x HTTP/1.1\r\nHost: h\r\nContent-Length: 99999999999999999999\r\n\r\n", 400,
          "Content-Length '99999999999999999999' is not a number of bytes");
  // A 128 MB chunked upload is refused at its first chunk's size line.
  refused("POST /x HTTP/1.1\r\nHost: h\r\nTransfer-Encoding: chunked\r\n\r\n8000000\r\n", 413,
          "the request body is larger than the 4096 bytes this service accepts");
  // ... and many small chunks at the one that goes over.
  std::string many = "POST /x HTTP/1.1\r\nHost: h\r\nTransfer-Encoding: chunked\r\n\r\n";
  for (int i = 0; i < 5; ++i) many += "400\r\n" + std::string(1024, 'a') + "\r\n";
  refused(many, 413, "the request body is larger than the 4096 bytes this service accepts");
  refused("POST /x HTTP/1.1\r\nHost: h\r\nTransfer-Encoding: chunked\r\n\r\nFFFFFFFFF\r\n", 400,
          "the chunk size 'FFFFFFFFF' is not a hex number");
  refused(
      "POST /x HTTP/1.1\r\nHost: h\r\nTransfer-Encoding: chunked\r\n\r\n" + std::string(300, '1'),
      400, "a chunk size line longer than 256 bytes");
  refused("POST /x HTTP/1.1\r\nHost: h\r\nTransfer-Encoding: chunked\r\n\r\n1\r\nab\r\n", 400,
          "a chunk's data is not followed by CRLF");
  std::string trailer = "POST /x HTTP/1.1\r\nHost: h\r\nTransfer-Encoding: chunked\r\n\r\n0\r\n";
  for (int i = 0; i < 400; ++i) trailer += "T: " + std::string(40, 'x') + "\r\n";
  refused(trailer, 431, "the chunked body's trailer is larger than 16384 bytes");
}

TEST_CASE("web message: a chunk size line holds 256 bytes however its bytes arrive",
          "[web][web_message]") {
  const std::string head = "POST /x HTTP/1.1\r\nHost: h\r\nTransfer-Encoding: chunked\r\n\r\n";
  // "1;" and an extension: 256 bytes of line pass, 257 do not (CRLF not counted).
  const auto body = [&](std::size_t line) {
    return head + "1;" + std::string(line - 2, 'e') + "\r\na\r\n0\r\n\r\n";
  };
  for (std::size_t step : {std::size_t(1), std::size_t(7), std::size_t(100000)}) {
    INFO("pieces of " << step << " bytes");
    const auto feed = [&](const std::string& bytes) {
      RequestParser p(Limits{});
      State s = State::need_more;
      for (std::size_t i = 0; i < bytes.size() && s == State::need_more; i += step)
        s = p.feed(std::string_view(bytes).substr(i, step));
      return std::make_pair(s, p.error_message());
    };
    const auto fits = feed(body(256));
    CHECK(fits.first == State::complete);
    for (const std::string& bytes : {body(257), body(300), body(4000)}) {
      const auto over = feed(bytes);
      CHECK(over.first == State::error);
      CHECK(over.second == "a chunk size line longer than 256 bytes");
    }
  }
  // A line that ends in CR with its LF still to come is not over the limit by the CR.
  RequestParser p(Limits{});
  CHECK(p.feed(head + "1;" + std::string(254, 'e') + "\r") == State::need_more);
  CHECK(p.feed("\na\r\n0\r\n\r\n") == State::complete);
  CHECK(p.request().body == "a");
}

TEST_CASE("web message: smuggling shapes are refused (RFC 9112 §6.3, §5.2)", "[web][web_message]") {
  refused("POST /x HTTP/1.1\r\nHost: h\r\nContent-Length: 3\r\nTransfer-Encoding: chunked\r\n\r\n",
          400, "both Transfer-Encoding and Content-Length (RFC 9112 §6.3)");
  refused("POST /x HTTP/1.1\r\nHost: h\r\nContent-Length: 3\r\nContent-Length: 4\r\n\r\n", 400,
          "two different Content-Length headers");
  refused("POST /x HTTP/1.1\r\nHost: h\r\nTransfer-Encoding: gzip, chunked\r\n\r\n", 501,
          "Transfer-Encoding 'gzip, chunked' is not supported (only chunked)");
  refused("POST /x HTTP/1.0\r\nTransfer-Encoding: chunked\r\n\r\n", 400,
          "Transfer-Encoding in an HTTP/1.0 request");
  refused("GET /x HTTP/1.1\r\nHost: h\r\n folded\r\n\r\n", 400,
          "a header line begins with white space (obsolete line folding, RFC 9112 §5.2)");
  refused("GET /x HTTP/1.1\r\nHost : h\r\n\r\n", 400,
          "the header name 'Host ' is not a token (RFC 9110 §5.1)");
  refused("GET /x HTTP/1.1\r\nHost: h\rX: y\r\n\r\n", 400,
          "a CR byte inside a line of the request head (RFC 9112 §2.2)");
  refused("GET /x HTTP/1.1\r\n\r\n", 400,
          "an HTTP/1.1 request without a Host header (RFC 9112 §3.2)");
  refused("GET /x HTTP/1.1\r\nHost: a\r\nHost: b\r\n\r\n", 400, "more than one Host header");
  refused("GET /x HTTP/1.1\r\nHost: h\r\nExpect: 200-ok\r\n\r\n", 417,
          "Expect: '200-ok' is not supported (only 100-continue)");
}

TEST_CASE("web message: the request line", "[web][web_message]") {
  refused("GET /x\r\n\r\n", 400, "the request line is not METHOD TARGET HTTP/1.1: 'GET /x'");
  refused("G(T /x HTTP/1.1\r\n\r\n", 400, "the request method 'G(T' is not a method name");
  refused("GET /x HTTP/2.0\r\n\r\n", 505,
          "the HTTP version 'HTTP/2.0' is not supported (HTTP/1.1 or HTTP/1.0)");
  refused("GET http://evil/x HTTP/1.1\r\n\r\n", 400,
          "the request target 'http://evil/x' is not a path beginning with '/'");
  refused("GET /a\xFF HTTP/1.1\r\n\r\n", 400,
          "the request target has the byte 0xFF at offset 2 (RFC 3986: percent-encode it)");
  refused("GET /%FF HTTP/1.1\r\nHost: h\r\n\r\n", 400,
          "the request path '/%FF' is not valid UTF-8 once decoded (byte 1)");
  refused("GET /%C0%AF HTTP/1.1\r\nHost: h\r\n\r\n", 400,  // an overlong '/'
          "the request path '/%C0%AF' is not valid UTF-8 once decoded (byte 1)");
  refused("GET /a%0Ab HTTP/1.1\r\n\r\n", 400, "the request path '/a%0Ab' has a control character");
  refused("GET /a%G0 HTTP/1.1\r\n\r\n", 400, "the request path '/a%G0' has a malformed %-escape");
  refused("GET /x?rev=%FF HTTP/1.1\r\n\r\n", 400,
          "the query parameter 'rev=%FF' is malformed, not valid UTF-8 or has a control "
          "character");
  refused("GET /x?rev=a%0Ab HTTP/1.1\r\n\r\n", 400,
          "the query parameter 'rev=a%0Ab' is malformed, not valid UTF-8 or has a control "
          "character");
}

TEST_CASE("web message: head limits: request line, head size, header count", "[web][web_message]") {
  refused("GET /" + std::string(9000, 'a'), 414, "the request line is longer than 8192 bytes");
  refused("GET /" + std::string(9000, 'a') + " HTTP/1.1\r\n", 414,
          "the request line is longer than 8192 bytes");
  std::string big = "GET / HTTP/1.1\r\nHost: h\r\n";
  for (int i = 0; i < 20; ++i)
    big += "X-" + std::to_string(i) + ": " + std::string(1000, 'v') + "\r\n";
  refused(big, 431, "the request head is larger than 16384 bytes");
  // One header byte at a time, never a line end: the same limit.
  refused("GET / HTTP/1.1\r\nX: " + std::string(17000, 'v'), 431,
          "the request head is larger than 16384 bytes");
  std::string many = "GET / HTTP/1.1\r\nHost: h\r\n";
  for (int i = 0; i < 64; ++i) many += "X: 1\r\n";
  refused(many, 431, "more than 64 header lines");
  refused("GET / HTTP/1.1\r\nHost: h\r\nX-Name: caf\xC3\xA9\r\n\r\n", 400,
          "the header 'X-Name' has the byte 0xC3: header values must be printable ASCII");
}

TEST_CASE("web message: every byte 0x00-0xFF in a path, a header and a query value",
          "[web][web_message]") {
  // Whatever the byte, the parser answers complete or a 4xx/5xx with a
  // message that is one line of valid UTF-8: never an exception, never raw bytes.
  for (int b = 0; b < 256; ++b) {
    const std::string byte(1, static_cast<char>(b));
    char enc[4];
    std::snprintf(enc, sizeof enc, "%%%02X", b);
    for (const std::string& bytes :
         {"GET /a" + byte + "b HTTP/1.1\r\nHost: h\r\n\r\n",
          "GET /a" + std::string(enc) + "b HTTP/1.1\r\nHost: h\r\n\r\n",
          "GET /a?rev=" + std::string(enc) + " HTTP/1.1\r\nHost: h\r\n\r\n",
          "GET /a HTTP/1.1\r\nHost: h\r\nX: a" + byte + "b\r\n\r\n",
          "POST /a HTTP/1.1\r\nHost: h\r\nContent-Length: 3\r\n\r\na" + byte + "b"}) {
      INFO(printable(bytes));
      const Parsed r = parse(bytes);
      if (r.state == State::error) {
        CHECK(r.status >= 400);
        CHECK(valid_utf8(r.message));
        CHECK(r.message.find_first_of("\r\n") == std::string::npos);
      } else {
        CHECK(r.state == State::complete);
        CHECK(valid_utf8(r.req.path));
        for (const auto& [k, v] : r.req.params) CHECK(valid_utf8(v));
      }
    }
  }
}

TEST_CASE("web message: UTF-8 per RFC 3629", "[web][web_message]") {
  CHECK(valid_utf8(""));
  CHECK(valid_utf8("press3/z-axis"));
  CHECK(
      valid_utf8("Stra\xC3\x9F"
                 "e \xE2\x82\xAC \xF0\x9F\x94\xA7"));
  std::size_t at = 99;
  CHECK_FALSE(valid_utf8("ab\xFF", &at));
  CHECK(at == 2);
  CHECK_FALSE(valid_utf8("\xC0\x80"));          // overlong NUL
  CHECK_FALSE(valid_utf8("\xE0\x80\xAF"));      // overlong '/'
  CHECK_FALSE(valid_utf8("\xED\xA0\x80"));      // a surrogate
  CHECK_FALSE(valid_utf8("\xF4\x90\x80\x80"));  // above U+10FFFF
  CHECK_FALSE(valid_utf8("\xE2\x82"));          // cut short
  CHECK(printable("GET /a\n\xFF\\") == "GET /a\\x0A\\xFF\\\\");
}

TEST_CASE("web message: percent-decoding and queries", "[web][web_message]") {
  std::string out;
  CHECK(url_decode("a%2Fb+c", out, false));
  CHECK(out == "a/b+c");
  CHECK(url_decode("a%2fb+c", out, true));
  CHECK(out == "a/b c");
  CHECK_FALSE(url_decode("%4", out, false));
  CHECK_FALSE(url_decode("%", out, false));
  Params p;
  std::string bad;
  CHECK(parse_query("a=1&&b=&c&reason=two%0Alines", p, bad, true));
  CHECK(p.size() == 4);
  CHECK(p.find("c")->second.empty());
  CHECK(p.find("reason")->second == "two\nlines");
  p.clear();
  CHECK_FALSE(parse_query("reason=two%0Alines", p, bad, false));
  CHECK(bad == "reason=two%0Alines");
  CHECK_FALSE(parse_query("x=%00", p, bad, true));
}

TEST_CASE("web message: the response on the wire", "[web][web_message]") {
  Response r;
  r.status = 404;
  r.set_content("{}\n", "application/json");
  r.set_header("Set-Cookie", "a=1");
  r.set_header("Set-Cookie", "b=2");
  r.set_header("X-Evil", "a\r\nInjected: yes");
  r.set_header("Content-Length", "999");  // the server's own
  const std::string wire = serialize(r, false);
  CHECK(wire ==
        "HTTP/1.1 404 Not Found\r\nContent-Type: application/json\r\nSet-Cookie: a=1\r\n"
        "Set-Cookie: b=2\r\nX-Evil: aInjected: yes\r\nContent-Length: 3\r\n\r\n{}\n");
  r.close = true;
  CHECK(serialize(r, true) ==
        "HTTP/1.1 404 Not Found\r\nContent-Type: application/json\r\nSet-Cookie: a=1\r\n"
        "Set-Cookie: b=2\r\nX-Evil: aInjected: yes\r\nContent-Length: 3\r\nConnection: "
        "close\r\n\r\n");
  Response none;
  none.status = 204;
  CHECK(serialize(none, false) == "HTTP/1.1 204 No Content\r\n\r\n");
}

TEST_CASE("web: a request's cookie by name (RFC 6265 §5.4 pairs), absent is empty",
          "[web][web_message]") {
  lmcfg::web::Request r;
  CHECK(r.cookie("a").empty());
  r.headers.emplace("Cookie", "lmcfg_session=abc; lmcfg_signin=x=y;  other=1");
  CHECK(r.cookie("lmcfg_session") == "abc");
  CHECK(r.cookie("lmcfg_signin") == "x=y");
  CHECK(r.cookie("other") == "1");
  CHECK(r.cookie("lmcfg") == "");
  CHECK(r.cookie("session") == "");
}

}  // namespace web_test_web_message
