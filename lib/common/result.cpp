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

class CommStateCategory final : public std::error_category {
 public:
  const char* name() const noexcept override { return "linrs-comm-state"; }
  std::string message(int ev) const override {
    // seed 003 §16.1
    switch (ev) {
      case 0xC1:
        return "C1h checksum error";
      case 0xC2:
        return "C2h message format error: end of telegram (04h) missing";
      case 0xC3:
        return "C3h undefined message main ID";
      case 0xC4:
        return "C4h undefined message sub ID";
      case 0xC5:
        return "C5h wrong baud rate defined with S1";
      case 0xC8:
        return "C8h parameter unknown UPID";
      case 0xC9:
        return "C9h parameter wrong type";
      default: {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%02Xh undocumented communication state", ev & 0xFF);
        return buf;
      }
    }
  }
};

}  // namespace

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
