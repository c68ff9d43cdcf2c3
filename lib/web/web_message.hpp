#pragma once
// HTTP/1.1 messages of lmcfg serve's own server (docs/serve.md "Security
// model"): the request as a handler sees it, the response it fills, and the
// incremental request parser that turns a connection's bytes into requests
// under fixed limits. Nothing here touches a socket, so the parser, the
// routing and the handlers run in-process from a buffer (the fuzz target
// fuzz/fuzz_http.cpp, the tests).
//
// Every request the parser completes has: a method of token characters, a
// path that is valid UTF-8 without control characters once percent-decoded,
// query parameters that are valid UTF-8, header values of printable ASCII,
// a body within the limit whatever its transfer coding. Anything else is an
// HTTP error with a message saying what and where (RFC 9112).
#include <cstddef>
#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace lmcfg::web {

// Header names compare without regard to case (RFC 9110 §5.1).
struct CaseLess {
  bool operator()(const std::string& a, const std::string& b) const noexcept;
};
using Headers = std::multimap<std::string, std::string, CaseLess>;
using Params = std::multimap<std::string, std::string>;

struct Request {
  std::string method;  // "GET", "POST" ... (token characters)
  std::string target;  // as sent: "/api/v1/drives/a%2Fb?x=1"
  std::string path;    // percent-decoded, without the query
  Params params;       // the query's, percent-decoded ('+' is a space)
  Headers headers;
  std::string body;                  // de-chunked
  int version_minor = 1;             // HTTP/1.0 or HTTP/1.1
  std::string remote_addr;           // "127.0.0.1", "::1"
  bool tls = false;                  // it came over HTTPS
  std::vector<std::string> matches;  // the route pattern's groups, [0] the whole path

  bool has_header(const std::string& name) const { return headers.count(name) != 0; }
  // The first value of the header, "" when absent.
  std::string get_header_value(const std::string& name) const;
  bool has_param(const std::string& key) const { return params.count(key) != 0; }
  // The first value of the parameter, "" when absent.
  std::string get_param_value(const std::string& key) const;
  // The value of cookie `name` in the Cookie header (RFC 6265 §5.4: pairs
  // separated by "; "), "" when absent.
  std::string cookie(std::string_view name) const;
};

struct Response {
  int status = 200;
  Headers headers;
  std::string body;
  bool close = false;  // close the connection after this answer

  // Adds a header (several of one name stay several: Set-Cookie).
  void set_header(const std::string& name, const std::string& value);
  void set_content(std::string content, const std::string& content_type);
};

// The reason phrase of a status code ("Not Found"); "Unknown" for others.
std::string_view reason_phrase(int status);
// The response as bytes on the wire: status line, headers (Content-Length
// always; Connection: close when `res.close`), body (none for HEAD, 1xx, 204
// and 304).
std::string serialize(const Response& res, bool head_request);

// Percent-decoding; `plus_is_space` for query strings and forms
// (application/x-www-form-urlencoded). false on a malformed escape ("%G1", "%4").
bool url_decode(std::string_view in, std::string& out, bool plus_is_space);
// "a=1&b=x%20y" into `out`; false with the offending part (printable) in
// `bad` when a key or value is malformed, not valid UTF-8 or has a control
// character (tab, CR and LF in values pass with `allow_breaks`: a form's text).
bool parse_query(std::string_view query, Params& out, std::string& bad, bool allow_breaks);
// Whether `s` is valid UTF-8 (RFC 3629: no overlong forms, no surrogates,
// nothing above U+10FFFF). `where` is the byte offset of the first bad byte.
bool valid_utf8(std::string_view s, std::size_t* where = nullptr) noexcept;
// `s` with every byte that is not printable ASCII as \xNN (and '\' as \\):
// one line that is valid UTF-8 and valid in JSON, whatever a client sent.
std::string printable(std::string_view s);

// A chunked body's chunk-size line (the size and any extensions, RFC 9112
// §7.1.1) holds at most this many bytes; 400 above.
inline constexpr std::size_t kMaxChunkLine = 256;

struct Limits {
  std::size_t max_request_line = 8192;  // 414 above
  std::size_t max_head = 16384;         // request line and headers; 431 above
  std::size_t max_headers = 64;         // 431 above
  std::size_t max_body = 4096;          // 413 above, for every transfer coding
};

// One connection's bytes in, requests out, one at a time (pipelined requests
// wait in the buffer until the previous answer is written).
class RequestParser {
 public:
  enum class State { need_more, complete, error };

  explicit RequestParser(Limits limits) : limits_(limits) {}

  // Adds bytes and parses as far as they go. After `complete` the request is
  // request(); next() starts on the bytes that follow it. After `error`,
  // error_status()/error_message() say what (the connection is then closed).
  State feed(std::string_view bytes);
  // Parses what is buffered (after next()) without adding bytes.
  State parse();
  const Request& request() const { return req_; }
  Request& request() { return req_; }
  void next();
  int error_status() const { return error_status_; }
  const std::string& error_message() const { return error_message_; }
  // A complete head asked for "Expect: 100-continue" and its body is not yet in.
  bool wants_continue() const { return stage_ == Stage::body && expect_continue_ && !continued_; }
  void continued() { continued_ = true; }
  // Whether any byte of a request not yet complete is buffered (a request has begun).
  bool started() const { return !buf_.empty() || stage_ != Stage::head; }
  bool head_complete() const { return stage_ != Stage::head; }
  // Bytes buffered and not yet parsed.
  std::size_t buffered() const { return buf_.size(); }

 private:
  enum class Stage { head, body, chunk_size, chunk_data, chunk_crlf, trailers, done };
  State fail(int status, std::string message);
  State parse_head();
  State parse_request_line(std::string_view line);
  State parse_header_line(std::string_view line);
  State after_head();
  State parse_body();

  Limits limits_;
  std::string buf_;
  std::size_t pos_ = 0;         // parsed up to here in buf_
  std::size_t scan_ = 0;        // no '\n' in buf_ before here (head lines)
  std::size_t head_start_ = 0;  // where this request's head begins in buf_
  std::size_t lines_ = 0;       // head lines parsed
  Stage stage_ = Stage::head;
  Request req_;
  std::size_t content_length_ = 0, chunk_left_ = 0, trailer_bytes_ = 0;
  bool expect_continue_ = false, continued_ = false;
  int error_status_ = 0;
  std::string error_message_;
};

}  // namespace lmcfg::web
