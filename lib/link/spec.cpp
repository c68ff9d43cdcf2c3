#include "link/spec.hpp"

#include "codec/messages.hpp"
#include "common/bytes.hpp"
#include "link/session.hpp"

namespace lmcfg::link {

LinkSpec LinkSpec::for_macid(std::uint8_t id) const {
  LinkSpec s = *this;
  s.client.id = id;
  return s;
}

namespace {
std::string shown(const InputNames& n, const std::string& text) {
  return n.quote_text ? "'" + text + "'" : text;
}
Error outside(const char* name, int value, const char* range) {
  return Error(Errc::invalid_argument,
               std::string(name) + " " + std::to_string(value) + " is outside " + range);
}
}  // namespace

namespace {
// Every setting but the port.
Result<LinkSpec> settings_of(const LinkInput& in, const InputNames& names) {
  LinkSpec l;
  l.trace_path = in.trace;
  l.holder = in.holder;
  l.serial.baud = in.baud;
  l.serial.stop_bits = in.stop_bits;
  LMCFG_ASSIGN_OR_RETURN(l.serial.parity, parse_parity(in.parity));
  LMCFG_TRY(transport::validate(l.serial));
  auto id = parse_number(in.id, false);
  if (!id || *id > 0xFF)
    return Error(Errc::invalid_argument, std::string(names.id) + " " + shown(names, in.id) +
                                             " is not a MACID 0..255 (0x00..0xFF)");
  l.client.id = static_cast<std::uint8_t>(*id);
  LMCFG_ASSIGN_OR_RETURN(l.client.checksum, parse_checksum(in.checksum));
  LMCFG_ASSIGN_OR_RETURN(l.client.checksum.coverage, parse_checksum_coverage(in.checksum_coverage));
  if (in.response_layout != "auto") {
    auto layout = codec::parse_layout_items(in.response_layout);
    if (!layout)
      return Error(Errc::invalid_argument,
                   std::string(names.response_layout) + " " + shown(names, in.response_layout) +
                       " is not auto, factory or a comma list of comm_state, status_word, "
                       "state_var, error_code, warn_word, echo_header, monitoring_1, "
                       "monitoring_2, mc_response");
    l.client.layout = *layout;
    l.client.adapt_layout = false;
  }
  if (in.timeout_ms < 1 || in.timeout_ms > 60000)
    return outside(names.timeout_ms, in.timeout_ms, "1..60000");
  if (in.retries < 0 || in.retries > 10) return outside(names.retries, in.retries, "0..10");
  l.client.timeout = transport::Millis(in.timeout_ms);
  if (in.settle_ms != -1) {
    if (in.settle_ms < 1 || in.settle_ms > 60000)
      return outside(names.settle_ms, in.settle_ms, "1..60000");
    l.client.settle = transport::Millis(in.settle_ms);
    l.fixed_settle = true;
  }
  l.client.read_retries = in.retries;
  if (in.long_timeout_s < 0 || in.long_timeout_s > 3600)
    return outside(names.long_timeout_s, in.long_timeout_s, "1..3600");
  if (in.long_timeout_s > 0) {
    const transport::Millis t(1000LL * in.long_timeout_s);
    l.client.defaulting_timeout = l.client.flash_timeout = l.client.reset_timeout = t;
  }
  if (in.recover_timeout_s < 0 || in.recover_timeout_s > 3600)
    return outside(names.recover_timeout_s, in.recover_timeout_s, "1..3600");
  if (in.recover_timeout_s > 0)
    l.client.recover_timeout = transport::Millis(1000LL * in.recover_timeout_s);
  if (in.agreeing_reads != "auto") {
    auto n = parse_number(in.agreeing_reads, false);
    if (!n || *n < 1 || *n > 5)
      return Error(Errc::invalid_argument, std::string(names.agreeing_reads) + " " +
                                               shown(names, in.agreeing_reads) + " is not " +
                                               names.automatic + " or 1..5");
    l.agreeing_reads = static_cast<int>(*n);
  }
  l.client.on_long_wait = in.on_long_wait;
  l.client.cancel = in.cancel;
  return l;
}
}  // namespace

Result<void> check_link_settings(const LinkInput& in, const InputNames& names) {
  LMCFG_TRY(settings_of(in, names));
  return {};
}

Result<LinkSpec> make_link_spec(const LinkInput& in, const InputNames& names) {
  LMCFG_ASSIGN_OR_RETURN(auto l, settings_of(in, names));
  if (in.port.empty())
    return Error(Errc::invalid_argument,
                 "no --port given (a serial device, tcp://host:port or sim:FILE)");
  LMCFG_ASSIGN_OR_RETURN(l.port, parse_port(in.port));
  if (l.port.scheme_name() == "serial") l.serial.device = l.port.address;
  return l;
}

}  // namespace lmcfg::link
