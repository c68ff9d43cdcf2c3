#include "link/session.hpp"

#include <optional>

namespace lmcfg::link {

Result<codec::ChecksumConfig> parse_checksum(std::string_view t) {
  codec::ChecksumConfig c;
  if (t == "none") return c;
  if (t == "add") {
    c.mode = codec::ChecksumMode::add;
    return c;
  }
  if (t == "crc" || t == "crc-ffff") {
    c.mode = codec::ChecksumMode::crc_ccitt;
    c.crc_init = 0xFFFF;
    return c;
  }
  if (t == "crc-0000") {
    c.mode = codec::ChecksumMode::crc_ccitt;
    c.crc_init = 0x0000;
    return c;
  }
  if (t == "crc-kermit") {
    c.mode = codec::ChecksumMode::crc_kermit;
    c.crc_init = 0x0000;
    return c;
  }
  return Error(Errc::invalid_argument,
               "checksum '" + std::string(t) +
                   "' is not one of none, add, crc, crc-ffff, crc-0000, crc-kermit");
}

Result<codec::ChecksumCoverage> parse_checksum_coverage(std::string_view t) {
  if (t == "id") return codec::ChecksumCoverage::id_through_data;
  if (t == "start") return codec::ChecksumCoverage::start_through_data;
  if (t == "data") return codec::ChecksumCoverage::data_only;
  return Error(Errc::invalid_argument,
               "checksum coverage '" + std::string(t) + "' is not one of id, start, data");
}

std::string_view coverage_name(codec::ChecksumCoverage c) {
  switch (c) {
    case codec::ChecksumCoverage::id_through_data:
      return "id";
    case codec::ChecksumCoverage::start_through_data:
      return "start";
    case codec::ChecksumCoverage::data_only:
      return "data";
  }
  return "id";
}

namespace {
std::string mode_option(const codec::ChecksumConfig& c) {
  switch (c.mode) {
    case codec::ChecksumMode::none:
      return "none";
    case codec::ChecksumMode::add:
      return "add";
    case codec::ChecksumMode::crc_ccitt:
      return c.crc_init == 0 ? "crc-0000" : "crc-ffff";
    case codec::ChecksumMode::crc_kermit:
      return "crc-kermit";
  }
  return "none";
}
bool default_coverage(const codec::ChecksumConfig& c) {
  return c.mode == codec::ChecksumMode::none ||
         c.coverage == codec::ChecksumCoverage::id_through_data;
}
}  // namespace

std::string checksum_name(const codec::ChecksumConfig& c) {
  std::string s = mode_option(c);
  if (!default_coverage(c)) s += " coverage=" + std::string(coverage_name(c.coverage));
  return s;
}

std::string checksum_options(const codec::ChecksumConfig& c) {
  std::string s = "--checksum " + mode_option(c);
  if (!default_coverage(c)) s += " --checksum-coverage " + std::string(coverage_name(c.coverage));
  return s;
}

Result<transport::Parity> parse_parity(std::string_view t) {
  if (auto p = transport::parity_from_name(t)) return *p;
  return Error(Errc::invalid_argument,
               "parity '" + std::string(t) + "' is not one of none, even, odd");
}

Session::Session(LinkOptions opt, transport::OpenedLink link,
                 std::optional<transport::LowLatencyReport> latency)
    : latency_(std::move(latency)),
      opt_(std::move(opt)),
      link_(std::move(link.link)),
      on_close_(std::move(link.on_close)),
      client_(*link_, opt_.client) {}

Result<void> Session::close() {
  if (on_close_) {
    auto once = std::move(on_close_);
    on_close_ = nullptr;
    LMCFG_TRY(once());
  }
  return {};
}

Result<void> Session::relink(const transport::SerialSettings& line, std::uint8_t id,
                             const codec::ChecksumConfig& checksum) {
  const auto& cur = opt_.serial;
  if (line.baud != cur.baud || line.parity != cur.parity || line.stop_bits != cur.stop_bits) {
    LMCFG_TRY(link_->reconfigure(line));
    const std::string device = opt_.serial.device;
    opt_.serial = line;
    opt_.serial.device = device;
  }
  auto co = client_.options();
  co.id = id;
  co.checksum = checksum;
  co.link_has_parity = opt_.serial.parity != transport::Parity::none;
  client_.set_options(co);
  opt_.client.id = id;
  opt_.client.checksum = checksum;
  return {};
}

config::LinkSettings Session::link_settings() const {
  config::LinkSettings s;
  s.port = opt_.port;
  s.baud = std::to_string(opt_.serial.baud);
  s.parity = std::string(transport::parity_name(opt_.serial.parity));
  s.stop_bits = std::to_string(opt_.serial.stop_bits);
  s.checksum = checksum_name(opt_.client.checksum);
  return s;
}

Result<std::unique_ptr<Session>> open_session(const LinkOptions& opt_in) {
  LinkOptions opt = opt_in;
  if (opt.port.empty())
    return Error(Errc::invalid_argument,
                 "no --port given (a serial device, tcp://host:port or sim:FILE)");
  LMCFG_ASSIGN_OR_RETURN(const auto spec, link::parse_port(opt.port));
  link::OpenRequest req;
  req.line = opt.serial;
  req.holder = opt.holder;
  req.real_time_peer = opt.real_time_sim;
  LMCFG_ASSIGN_OR_RETURN(auto opened, link::open_byte_link(spec, req));
  if (spec.scheme_name() == "serial") opt.serial.device = spec.address;
  // A simulated drive is wired at its own settings: the session talks with those.
  if (opened.line) {
    opt.serial.baud = opened.line->baud;
    opt.serial.parity = opened.line->parity;
    opt.serial.stop_bits = opened.line->stop_bits;
  }
  auto& link = opened.link;
  auto latency = std::move(opened.latency);
  if (!opt.trace_path.empty()) {
    std::shared_ptr<transport::TraceSink> sink = transport::make_file_trace(opt.trace_path);
    if (!sink) return Error(Errc::file_error, "cannot open trace file '" + opt.trace_path + "'");
    link = transport::make_traced(std::move(link), std::move(sink));
  }
  // With parity the UART detects a flipped bit; without it and without a
  // checksum each value is read twice (Client::agreeing_reads).
  opt.client.link_has_parity = opt.serial.parity != transport::Parity::none;
  // Automatic unless fixed: two agreeing reads when nothing detects a flipped
  // bit, three once the line has corrupted an answer.
  opt.client.agreeing_reads = opt.agreeing_reads;
  // Deadlines from the wire time and the measured round trips, capped by
  // --timeout-ms; the settle after a lost answer as long as its deadline.
  opt.client.adaptive_deadline = true;
  opt.client.adaptive_settle = !opt.fixed_settle;
  return std::make_unique<Session>(std::move(opt), std::move(opened), std::move(latency));
}

}  // namespace lmcfg::link
