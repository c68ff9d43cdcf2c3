#include "link/session.hpp"

#include <optional>

#include "client/linudp_client.hpp"

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

namespace {
// The client's settings for a session: the spec's, with what the link itself
// decides. With parity the UART detects a flipped bit; without it and without
// a checksum each value is read twice (Client::agreeing_reads), three times
// once the line has corrupted an answer, unless the spec fixes the number.
// Deadlines from the wire time and the measured round trips, capped by
// --timeout-ms; the settle after a lost answer as long as its deadline.
client::ClientOptions client_options(const LinkSpec& spec, const transport::SerialSettings& line) {
  client::ClientOptions c = spec.client;
  c.link_has_parity = line.parity != transport::Parity::none;
  // UDP/IP over Ethernet: the frame check sequence and the UDP checksum
  // detect a flipped bit (LinUDP V2 §4.3: plain UDP/IPv4), as parity does.
  if (spec.port.scheme && spec.port.protocol() == Protocol::linudp) c.link_has_parity = true;
  c.agreeing_reads = spec.agreeing_reads;
  c.adaptive_deadline = true;
  c.adaptive_settle = !spec.fixed_settle;
  return c;
}
}  // namespace

Session::Session(LinkSpec spec, transport::SerialSettings line, transport::OpenedLink link,
                 std::optional<transport::LowLatencyReport> latency)
    : latency_(std::move(latency)),
      spec_(std::move(spec)),
      line_(line),
      link_(std::move(link.link)),
      on_close_(std::move(link.on_close)) {
  if (spec_.port.scheme && spec_.port.protocol() == Protocol::linudp)
    client_ = std::make_unique<client::LinudpClient>(*link_, client_options(spec_, line_));
  else
    client_ = std::make_unique<client::LinrsClient>(*link_, client_options(spec_, line_));
}

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
  if (line.baud != line_.baud || line.parity != line_.parity || line.stop_bits != line_.stop_bits) {
    LMCFG_TRY(link_->reconfigure(line));
    const std::string device = line_.device;
    line_ = line;
    line_.device = device;
  }
  auto co = client_->options();
  co.id = id;
  co.checksum = checksum;
  co.link_has_parity = line_.parity != transport::Parity::none;
  client_->set_options(co);
  return {};
}

LinkSpec Session::current_spec() const {
  LinkSpec s = spec_;
  s.serial = line_;
  s.client.id = client_->options().id;
  s.client.checksum = client_->options().checksum;
  return s;
}

config::LinkSettings Session::link_settings() const {
  config::LinkSettings s;
  s.port = spec_.port.text;
  if (spec_.port.scheme && spec_.port.protocol() == Protocol::linudp) {
    s.checksum = "none";  // UDP/IP carries no serial line (LinUDP V2 §4.3)
    return s;
  }
  s.baud = std::to_string(line_.baud);
  s.parity = std::string(transport::parity_name(line_.parity));
  s.stop_bits = std::to_string(line_.stop_bits);
  s.checksum = checksum_name(client_->options().checksum);
  return s;
}

Result<std::unique_ptr<Session>> open_session(const LinkSpec& spec) {
  OpenRequest req;
  req.line = spec.serial;
  req.holder = spec.holder;
  req.real_time_peer = spec.real_time_sim;
  LMCFG_ASSIGN_OR_RETURN(auto opened, open_byte_link(spec.port, req));
  // A simulated drive is wired at its own settings: the session talks with those.
  transport::SerialSettings line = spec.serial;
  if (opened.line) {
    line.baud = opened.line->baud;
    line.parity = opened.line->parity;
    line.stop_bits = opened.line->stop_bits;
  }
  auto latency = std::move(opened.latency);
  if (!spec.trace_path.empty()) {
    std::shared_ptr<transport::TraceSink> sink = transport::make_file_trace(spec.trace_path);
    if (!sink) return Error(Errc::file_error, "cannot open trace file '" + spec.trace_path + "'");
    opened.link = transport::make_traced(std::move(opened.link), std::move(sink));
  }
  return std::make_unique<Session>(spec, line, std::move(opened), std::move(latency));
}

}  // namespace lmcfg::link
