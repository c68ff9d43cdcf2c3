#include "web/web_message.hpp"

#include <algorithm>
#include <cstdio>

#include "common/bytes.hpp"
#include "common/text.hpp"

namespace lmcfg::web {

namespace {

char lower(char c) { return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c; }

// RFC 9110 §5.6.2: tchar.
bool is_tchar(unsigned char c) {
  if ((c >= '0' && c <= '9') || (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z')) return true;
  return std::string_view("!#$%&'*+-.^_`|~").find(static_cast<char>(c)) != std::string_view::npos;
}
bool is_token(std::string_view s) {
  return !s.empty() && std::all_of(s.begin(), s.end(),
                                   [](char c) { return is_tchar(static_cast<unsigned char>(c)); });
}

std::string_view trim_ows(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

std::string byte_hex(unsigned char c) {
  char b[8];
  std::snprintf(b, sizeof b, "0x%02X", c);
  return b;
}

// The first control character (C0 or DEL) in `s`, or npos; `allow_breaks`
// lets tab, CR and LF pass (a form's text area).
std::size_t find_control(std::string_view s, bool allow_breaks) {
  for (std::size_t i = 0; i < s.size(); ++i) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (allow_breaks && (c == '\t' || c == '\r' || c == '\n')) continue;
    if (c < 0x20 || c == 0x7F) return i;
  }
  return std::string_view::npos;
}

}  // namespace

bool CaseLess::operator()(const std::string& a, const std::string& b) const noexcept {
  return std::lexicographical_compare(a.begin(), a.end(), b.begin(), b.end(),
                                      [](char x, char y) { return lower(x) < lower(y); });
}

std::string Request::get_header_value(const std::string& name) const {
  auto it = headers.find(name);
  return it == headers.end() ? "" : it->second;
}

std::string Request::get_param_value(const std::string& key) const {
  auto it = params.find(key);
  return it == params.end() ? "" : it->second;
}

std::string Request::cookie(std::string_view name) const {
  const std::string header = get_header_value("Cookie");
  std::size_t pos = 0;
  while (pos < header.size()) {
    auto end = header.find(';', pos);
    if (end == std::string::npos) end = header.size();
    std::string_view part(header.data() + pos, end - pos);
    while (!part.empty() && part.front() == ' ') part.remove_prefix(1);
    if (part.size() > name.size() && part.substr(0, name.size()) == name &&
        part[name.size()] == '=')
      return std::string(part.substr(name.size() + 1));
    pos = end + 1;
  }
  return "";
}

void Response::set_header(const std::string& name, const std::string& value) {
  headers.emplace(name, value);
}

void Response::set_content(std::string content, const std::string& content_type) {
  body = std::move(content);
  headers.erase("Content-Type");
  headers.emplace("Content-Type", content_type);
}

std::string_view reason_phrase(int status) {
  switch (status) {
    case 100:
      return "Continue";
    case 200:
      return "OK";
    case 202:
      return "Accepted";
    case 204:
      return "No Content";
    case 303:
      return "See Other";
    case 304:
      return "Not Modified";
    case 400:
      return "Bad Request";
    case 401:
      return "Unauthorized";
    case 403:
      return "Forbidden";
    case 404:
      return "Not Found";
    case 405:
      return "Method Not Allowed";
    case 408:
      return "Request Timeout";
    case 409:
      return "Conflict";
    case 411:
      return "Length Required";
    case 413:
      return "Content Too Large";
    case 414:
      return "URI Too Long";
    case 415:
      return "Unsupported Media Type";
    case 417:
      return "Expectation Failed";
    case 421:
      return "Misdirected Request";
    case 429:
      return "Too Many Requests";
    case 431:
      return "Request Header Fields Too Large";
    case 500:
      return "Internal Server Error";
    case 501:
      return "Not Implemented";
    case 503:
      return "Service Unavailable";
    case 505:
      return "HTTP Version Not Supported";
    default:
      return "Unknown";
  }
}

namespace {
// A header name or value as it may go on the wire: whatever a handler put
// there (a Location built from a client's text), no byte of it can end the
// line and start another header (response splitting).
std::string header_text(const std::string& v) {
  std::string out;
  for (const char ch : v) {
    const auto c = static_cast<unsigned char>(ch);
    if (c == '\t' || (c >= 0x20 && c != 0x7F)) out.push_back(ch);
  }
  return out;
}
}  // namespace

std::string serialize(const Response& res, bool head_request) {
  std::string out = "HTTP/1.1 " + std::to_string(res.status) + " " +
                    std::string(reason_phrase(res.status)) + "\r\n";
  for (const auto& [k, v] : res.headers) {
    if (iequals(k, "Content-Length") || iequals(k, "Connection") || iequals(k, "Transfer-Encoding"))
      continue;  // the server's own
    out += header_text(k) + ": " + header_text(v) + "\r\n";
  }
  const bool no_body = res.status < 200 || res.status == 204 || res.status == 304;
  if (!no_body) out += "Content-Length: " + std::to_string(res.body.size()) + "\r\n";
  if (res.close) out += "Connection: close\r\n";
  out += "\r\n";
  if (!no_body && !head_request) out += res.body;
  return out;
}

namespace {
int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}
}  // namespace

bool url_decode(std::string_view in, std::string& out, bool plus_is_space) {
  out.clear();
  out.reserve(in.size());
  for (std::size_t i = 0; i < in.size(); ++i) {
    const char c = in[i];
    if (c == '%') {
      if (in.size() - i < 3) return false;
      const int hi = hex_value(in[i + 1]), lo = hex_value(in[i + 2]);
      if (hi < 0 || lo < 0) return false;
      out.push_back(static_cast<char>(hi * 16 + lo));
      i += 2;
    } else if (c == '+' && plus_is_space) {
      out.push_back(' ');
    } else {
      out.push_back(c);
    }
  }
  return true;
}

bool valid_utf8(std::string_view s, std::size_t* where) noexcept {
  const std::size_t at = invalid_utf8_at(s);
  if (where && at != std::string_view::npos) *where = at;
  return at == std::string_view::npos;
}

std::string printable(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (const char ch : s) {
    const auto c = static_cast<unsigned char>(ch);
    if (c == '\\') {
      out += "\\\\";
    } else if (c >= 0x20 && c < 0x7F) {
      out.push_back(ch);
    } else {
      char b[5];
      std::snprintf(b, sizeof b, "\\x%02X", c);
      out += b;
    }
  }
  return out;
}

namespace {
// One key or value of a query or form, decoded and checked.
bool query_part(std::string_view raw, std::string& out, bool allow_breaks) {
  return url_decode(raw, out, true) && valid_utf8(out) &&
         find_control(out, allow_breaks) == std::string::npos;
}
}  // namespace

bool parse_query(std::string_view query, Params& out, std::string& bad, bool allow_breaks) {
  std::size_t pos = 0;
  while (pos <= query.size()) {
    auto end = query.find('&', pos);
    if (end == std::string_view::npos) end = query.size();
    const std::string_view part = query.substr(pos, end - pos);
    pos = end + 1;
    if (part.empty()) continue;
    const auto eq = part.find('=');
    const std::string_view k = part.substr(0, eq);
    const std::string_view v =
        eq == std::string_view::npos ? std::string_view() : part.substr(eq + 1);
    std::string key, value;
    if (!query_part(k, key, false)) {
      bad = printable(k);
      return false;
    }
    if (!query_part(v, value, allow_breaks)) {
      bad = printable(part);
      return false;
    }
    out.emplace(std::move(key), std::move(value));
  }
  return true;
}

// ---- the parser

RequestParser::State RequestParser::fail(int status, std::string message) {
  stage_ = Stage::done;
  error_status_ = status;
  error_message_ = std::move(message);
  return State::error;
}

RequestParser::State RequestParser::feed(std::string_view bytes) {
  if (error_status_) return State::error;
  buf_.append(bytes.data(), bytes.size());
  return parse();
}

void RequestParser::next() {
  buf_.erase(0, pos_);
  pos_ = 0;
  scan_ = 0;
  head_start_ = 0;
  lines_ = 0;
  stage_ = Stage::head;
  req_ = Request{};
  content_length_ = chunk_left_ = trailer_bytes_ = 0;
  expect_continue_ = continued_ = false;
}

RequestParser::State RequestParser::parse() {
  if (error_status_) return State::error;
  if (stage_ == Stage::done) return State::complete;
  if (stage_ == Stage::head) {
    State s = parse_head();
    if (s != State::complete) return s;
    s = after_head();
    if (s != State::complete || stage_ == Stage::done) return s;
  }
  return parse_body();
}

// The head, line by line as they complete: the request line, then headers up
// to the empty line. RFC 9112 §2.2: a lone LF ends a line as CRLF does; a CR
// elsewhere is an error.
RequestParser::State RequestParser::parse_head() {
  while (true) {
    if (lines_ == 0) {
      // RFC 9112 §2.2: empty lines before the request line are ignored.
      while (pos_ < buf_.size() && (buf_[pos_] == '\r' || buf_[pos_] == '\n') &&
             (buf_[pos_] == '\n' || (pos_ + 1 < buf_.size() && buf_[pos_ + 1] == '\n')))
        pos_ += buf_[pos_] == '\r' ? 2 : 1;
      head_start_ = pos_;
      scan_ = std::max(scan_, pos_);
    }
    const auto nl = buf_.find('\n', scan_);
    if (nl == std::string::npos) {
      scan_ = buf_.size();
      const std::size_t line_len = buf_.size() - pos_;
      if (lines_ == 0 && line_len > limits_.max_request_line)
        return fail(414, "the request line is longer than " +
                             std::to_string(limits_.max_request_line) + " bytes");
      if (buf_.size() - head_start_ > limits_.max_head)
        return fail(
            431, "the request head is larger than " + std::to_string(limits_.max_head) + " bytes");
      return State::need_more;
    }
    std::string_view line(buf_.data() + pos_, nl - pos_);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos_ = scan_ = nl + 1;
    if (lines_ == 0 && line.size() > limits_.max_request_line)
      return fail(414, "the request line is longer than " +
                           std::to_string(limits_.max_request_line) + " bytes");
    if (pos_ - head_start_ > limits_.max_head)
      return fail(431,
                  "the request head is larger than " + std::to_string(limits_.max_head) + " bytes");
    if (line.find('\r') != std::string_view::npos)
      return fail(400, "a CR byte inside a line of the request head (RFC 9112 §2.2)");
    if (lines_++ == 0) {
      if (parse_request_line(line) == State::error) return State::error;
      continue;
    }
    if (line.empty()) return State::complete;
    if (parse_header_line(line) == State::error) return State::error;
  }
}

RequestParser::State RequestParser::parse_request_line(std::string_view line) {
  const auto sp1 = line.find(' ');
  const auto sp2 = sp1 == std::string_view::npos ? sp1 : line.find(' ', sp1 + 1);
  if (sp2 == std::string_view::npos || line.find(' ', sp2 + 1) != std::string_view::npos)
    return fail(400, "the request line is not METHOD TARGET HTTP/1.1: '" + printable(line) + "'");
  const std::string_view method = line.substr(0, sp1);
  const std::string_view target = line.substr(sp1 + 1, sp2 - sp1 - 1);
  const std::string_view version = line.substr(sp2 + 1);
  if (!is_token(method) || method.size() > 16)
    return fail(400, "the request method '" + printable(method) + "' is not a method name");
  if (version == "HTTP/1.1") {
    req_.version_minor = 1;
  } else if (version == "HTTP/1.0") {
    req_.version_minor = 0;
  } else {
    return fail(505, "the HTTP version '" + printable(version) +
                         "' is not supported (HTTP/1.1 or HTTP/1.0)");
  }
  if (target.empty() || target[0] != '/')
    return fail(400,
                "the request target '" + printable(target) + "' is not a path beginning with '/'");
  for (std::size_t i = 0; i < target.size(); ++i) {
    const auto c = static_cast<unsigned char>(target[i]);
    if (c <= 0x20 || c >= 0x7F)
      return fail(400, "the request target has the byte " + byte_hex(c) + " at offset " +
                           std::to_string(i) + " (RFC 3986: percent-encode it)");
  }
  req_.method = std::string(method);
  req_.target = std::string(target);
  const auto q = target.find('?');
  const std::string_view raw_path = target.substr(0, q);
  std::size_t where = 0;
  if (!url_decode(raw_path, req_.path, false))
    return fail(400, "the request path '" + printable(raw_path) + "' has a malformed %-escape");
  if (!valid_utf8(req_.path, &where))
    return fail(400, "the request path '" + printable(raw_path) +
                         "' is not valid UTF-8 once decoded (byte " + std::to_string(where) + ")");
  if (find_control(req_.path, false) != std::string::npos)
    return fail(400, "the request path '" + printable(raw_path) + "' has a control character");
  if (q != std::string_view::npos) {
    std::string bad;
    if (!parse_query(target.substr(q + 1), req_.params, bad, false))
      return fail(400, "the query parameter '" + bad +
                           "' is malformed, not valid UTF-8 or has a control character");
  }
  return State::complete;
}

RequestParser::State RequestParser::parse_header_line(std::string_view line) {
  if (line.front() == ' ' || line.front() == '\t')
    return fail(400,
                "a header line begins with white space (obsolete line folding, RFC 9112 "
                "§5.2)");
  const auto colon = line.find(':');
  if (colon == std::string_view::npos)
    return fail(400, "the header line '" + printable(line.substr(0, 64)) + "' has no ':'");
  const std::string_view name = line.substr(0, colon);
  if (!is_token(name))
    return fail(400, "the header name '" + printable(name) + "' is not a token (RFC 9110 §5.1)");
  const std::string_view value = trim_ows(line.substr(colon + 1));
  for (const char ch : value) {
    const auto c = static_cast<unsigned char>(ch);
    if (c != '\t' && (c < 0x20 || c >= 0x7F))
      return fail(400, "the header '" + std::string(name) + "' has the byte " + byte_hex(c) +
                           ": header values must be printable ASCII");
  }
  if (req_.headers.size() >= limits_.max_headers)
    return fail(431, "more than " + std::to_string(limits_.max_headers) + " header lines");
  req_.headers.emplace(std::string(name), std::string(value));
  return State::complete;
}

// What the head says about the body (RFC 9112 §6), and Host (§3.2).
RequestParser::State RequestParser::after_head() {
  const auto hosts = req_.headers.count("Host");
  if (hosts > 1) return fail(400, "more than one Host header");
  if (hosts == 0 && req_.version_minor == 1)
    return fail(400, "an HTTP/1.1 request without a Host header (RFC 9112 §3.2)");
  const bool has_te = req_.has_header("Transfer-Encoding");
  const auto lengths = req_.headers.equal_range("Content-Length");
  if (has_te && lengths.first != lengths.second)
    return fail(400, "both Transfer-Encoding and Content-Length (RFC 9112 §6.3)");
  if (has_te) {
    if (req_.version_minor == 0) return fail(400, "Transfer-Encoding in an HTTP/1.0 request");
    if (req_.headers.count("Transfer-Encoding") > 1 ||
        !iequals(req_.get_header_value("Transfer-Encoding"), "chunked"))
      return fail(501, "Transfer-Encoding '" + req_.get_header_value("Transfer-Encoding") +
                           "' is not supported (only chunked)");
    stage_ = Stage::chunk_size;
  }
  std::string length;
  for (auto it = lengths.first; it != lengths.second; ++it) {
    const std::string& v = it->second;
    if (v.empty() || v.size() > 18 || v.find_first_not_of("0123456789") != std::string::npos)
      return fail(400, "Content-Length '" + v + "' is not a number of bytes");
    if (!length.empty() && v != length) return fail(400, "two different Content-Length headers");
    length = v;
  }
  if (!length.empty()) {
    content_length_ = std::stoull(length);
    if (content_length_ > limits_.max_body)
      return fail(413, "the request body has " + length + " bytes, more than the " +
                           std::to_string(limits_.max_body) + " this service accepts");
    stage_ = content_length_ ? Stage::body : Stage::done;
  } else if (!has_te) {
    stage_ = Stage::done;
  }
  if (req_.has_header("Expect")) {
    if (!iequals(req_.get_header_value("Expect"), "100-continue"))
      return fail(417, "Expect: '" + req_.get_header_value("Expect") +
                           "' is not supported (only 100-continue)");
    expect_continue_ = true;
  }
  return State::complete;
}

RequestParser::State RequestParser::parse_body() {
  const auto too_large = [&] {
    return fail(413, "the request body is larger than the " + std::to_string(limits_.max_body) +
                         " bytes this service accepts");
  };
  while (stage_ != Stage::done) {
    const std::size_t avail = buf_.size() - pos_;
    switch (stage_) {
      case Stage::body: {
        const std::size_t n = std::min(avail, content_length_ - req_.body.size());
        req_.body.append(buf_, pos_, n);
        pos_ += n;
        if (req_.body.size() < content_length_) return State::need_more;
        stage_ = Stage::done;
        break;
      }
      case Stage::chunk_size: {
        // The line (size and extensions, without its CRLF) holds at most
        // kMaxChunkLine bytes, whether it arrives whole or in pieces.
        const auto nl = buf_.find('\n', pos_);
        std::string_view line(buf_.data() + pos_,
                              (nl == std::string::npos ? buf_.size() : nl) - pos_);
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        if (line.size() > kMaxChunkLine)
          return fail(400,
                      "a chunk size line longer than " + std::to_string(kMaxChunkLine) + " bytes");
        if (nl == std::string::npos) return State::need_more;
        pos_ = nl + 1;
        const std::string_view size = trim_ows(line.substr(0, line.find(';')));
        if (size.empty() || size.size() > 8 ||
            size.find_first_not_of("0123456789abcdefABCDEF") != std::string_view::npos)
          return fail(400, "the chunk size '" + printable(size) + "' is not a hex number");
        chunk_left_ = std::stoul(std::string(size), nullptr, 16);
        if (req_.body.size() + chunk_left_ > limits_.max_body) return too_large();
        stage_ = chunk_left_ ? Stage::chunk_data : Stage::trailers;
        break;
      }
      case Stage::chunk_data: {
        const std::size_t n = std::min(avail, chunk_left_);
        req_.body.append(buf_, pos_, n);
        pos_ += n;
        chunk_left_ -= n;
        if (chunk_left_) return State::need_more;
        stage_ = Stage::chunk_crlf;
        break;
      }
      case Stage::chunk_crlf: {
        if (avail < 1 || (buf_[pos_] == '\r' && avail < 2)) return State::need_more;
        if (buf_[pos_] == '\r') ++pos_;
        if (buf_[pos_] != '\n') return fail(400, "a chunk's data is not followed by CRLF");
        ++pos_;
        stage_ = Stage::chunk_size;
        break;
      }
      case Stage::trailers: {
        // Trailer fields are read and dropped (RFC 9112 §7.1.2), within the head limit.
        const auto nl = buf_.find('\n', pos_);
        if (nl == std::string::npos) {
          if (trailer_bytes_ + avail > limits_.max_head)
            return fail(431, "the chunked body's trailer is larger than " +
                                 std::to_string(limits_.max_head) + " bytes");
          return State::need_more;
        }
        const std::size_t len = nl - pos_ + 1;
        trailer_bytes_ += len;
        const bool empty = len == 1 || (len == 2 && buf_[pos_] == '\r');
        pos_ = nl + 1;
        if (trailer_bytes_ > limits_.max_head)
          return fail(431, "the chunked body's trailer is larger than " +
                               std::to_string(limits_.max_head) + " bytes");
        if (empty) stage_ = Stage::done;
        break;
      }
      default:
        stage_ = Stage::done;
    }
  }
  return State::complete;
}

}  // namespace lmcfg::web
