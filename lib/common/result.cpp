#include "common/result.hpp"

#include <cstdio>

namespace lmcfg {
namespace {

class LmcfgCategory final : public std::error_category {
 public:
  const char* name() const noexcept override { return "lmcfg"; }
  std::string message(int ev) const override {
    switch (static_cast<Errc>(ev)) {
      case Errc::ok:
        return "success";
      case Errc::timeout:
        return "no answer before the deadline";
      case Errc::link_closed:
        return "link closed";
      case Errc::io_error:
        return "input/output error on the link";
      case Errc::frame_short:
        return "telegram shorter than its length byte says";
      case Errc::frame_overlong:
        return "telegram longer than its length byte says";
      case Errc::frame_malformed:
        return "malformed telegram";
      case Errc::checksum_mismatch:
        return "telegram checksum mismatch";
      case Errc::unexpected_response:
        return "unexpected response";
      case Errc::drive_refused:
        return "drive refused the request";
      case Errc::invalid_argument:
        return "invalid argument";
      case Errc::parse_error:
        return "parse error";
      case Errc::unsupported_version:
        return "unsupported format version";
      case Errc::validation_failed:
        return "validation failed";
      case Errc::not_found:
        return "not found";
      case Errc::file_error:
        return "file error";
      case Errc::plan_refused:
        return "plan refused";
      case Errc::verify_mismatch:
        return "verification mismatch";
      case Errc::cancelled:
        return "cancelled";
      case Errc::not_supported:
        return "not supported by this link";
      case Errc::interrupted:
        return "interrupted";
    }
    return "unknown lmcfg error " + std::to_string(ev);
  }
};

// The error communication states and their texts: one table. LinRS §16.1 (seed
// 003) lists C1..C5, C8, C9. Newer firmware answers states the seed does not
// list (LinRS 3V27 p32 names D7h; each such state is a refusal with its own
// text); those a later manual names are
// here with the page that names them.
struct CommStateText {
  unsigned state;
  const char* text;
};
constexpr CommStateText kCommStates[] = {
    {0xC1, "C1h checksum error"},
    {0xC2, "C2h message format error: end of telegram (04h) missing"},
    {0xC3, "C3h undefined message main ID"},
    {0xC4, "C4h undefined message sub ID"},
    {0xC5, "C5h wrong baud rate defined with S1"},
    {0xC8, "C8h parameter unknown UPID"},
    {0xC9, "C9h parameter wrong type"},
    // LinRS 3V27 p32, the answer to "save curves to flash": "MC SW not stopped".
    {0xD7, "D7h MC SW not stopped (LinRS 3V27 p32): stop the motion control software first"},
};

class CommStateCategory final : public std::error_category {
 public:
  const char* name() const noexcept override { return "linrs-comm-state"; }
  std::string message(int ev) const override {
    if (const char* t = comm_state_text(static_cast<unsigned>(ev))) return t;
    char buf[64];
    std::snprintf(buf, sizeof buf, "%02Xh undocumented communication state", ev & 0xFF);
    return buf;
  }
};

class ErrorClassCategory final : public std::error_category {
 public:
  const char* name() const noexcept override { return "lmcfg-class"; }
  std::string message(int ev) const override {
    switch (static_cast<ErrorClass>(ev)) {
      case ErrorClass::link_failure:
        return "communication failure";
      case ErrorClass::bad_answer:
        return "answer lost, garbled or unexpected";
      case ErrorClass::link_down:
        return "link failed";
      case ErrorClass::drive_refusal:
        return "drive refused the request";
      case ErrorClass::bad_input:
        return "invalid input";
      case ErrorClass::plan_refused:
        return "plan refused";
      case ErrorClass::verify_mismatch:
        return "verification mismatch";
      case ErrorClass::interrupted:
        return "interrupted";
    }
    return "unknown error class " + std::to_string(ev);
  }
  bool equivalent(const std::error_code& code, int condition) const noexcept override {
    const auto c = class_of(code);
    if (!c) return false;
    const auto want = static_cast<ErrorClass>(condition);
    if (want == ErrorClass::link_failure)
      return *c == ErrorClass::bad_answer || *c == ErrorClass::link_down;
    return *c == want;
  }
};

}  // namespace

const char* comm_state_text(unsigned state) noexcept {
  for (const auto& s : kCommStates)
    if (s.state == state) return s.text;
  return nullptr;
}

std::optional<ErrorClass> class_of(const std::error_code& code) noexcept {
  if (code.category() == comm_state_category()) return ErrorClass::drive_refusal;
  if (code.category() != lmcfg_category()) return ErrorClass::link_down;  // OS errors on the link
  switch (static_cast<Errc>(code.value())) {
    case Errc::ok:
      return std::nullopt;
    case Errc::timeout:
    case Errc::frame_short:
    case Errc::frame_overlong:
    case Errc::frame_malformed:
    case Errc::checksum_mismatch:
    case Errc::unexpected_response:
      return ErrorClass::bad_answer;
    case Errc::link_closed:
    case Errc::io_error:
      return ErrorClass::link_down;
    case Errc::drive_refused:
      return ErrorClass::drive_refusal;
    case Errc::invalid_argument:
    case Errc::parse_error:
    case Errc::unsupported_version:
    case Errc::validation_failed:
    case Errc::not_found:
    case Errc::file_error:
    case Errc::cancelled:
    case Errc::not_supported:
      return ErrorClass::bad_input;
    case Errc::plan_refused:
      return ErrorClass::plan_refused;
    case Errc::verify_mismatch:
      return ErrorClass::verify_mismatch;
    case Errc::interrupted:
      return ErrorClass::interrupted;
  }
  return std::nullopt;
}

const std::error_category& error_class_category() noexcept {
  static const ErrorClassCategory c;
  return c;
}
std::error_condition make_error_condition(ErrorClass c) noexcept {
  return {static_cast<int>(c), error_class_category()};
}

const std::error_category& lmcfg_category() noexcept {
  static const LmcfgCategory c;
  return c;
}
std::error_code make_error_code(Errc e) noexcept { return {static_cast<int>(e), lmcfg_category()}; }

const std::error_category& comm_state_category() noexcept {
  static const CommStateCategory c;
  return c;
}
std::error_code make_comm_state_error(unsigned state_byte) noexcept {
  return {static_cast<int>(state_byte & 0xFFu), comm_state_category()};
}

}  // namespace lmcfg
