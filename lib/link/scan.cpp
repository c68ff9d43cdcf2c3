#include "link/scan.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>

#include "codec/messages.hpp"

namespace lmcfg::link {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

std::string line_name(const transport::SerialSettings& s) { return transport::format_settings(s); }

struct PassResult {
  std::map<std::uint8_t, std::size_t> answered;  // MACID -> data bytes of its answer
  Bytes heard;                                   // every byte received in the pass
  std::size_t unexplained = 0;
};

// One request per MACID in [first, last], answers attributed by their MACID.
Result<PassResult> sweep(transport::Transport& link, const transport::SerialSettings& line,
                         const codec::ChecksumConfig& chk, unsigned first, unsigned last,
                         double deadline_ms, const ScanOptions& o, std::uint64_t& telegrams) {
  PassResult r;
  codec::StreamDecoder dec(chk);
  std::size_t explained = 0;
  auto take = [&](const Bytes& chunk) {
    if (r.heard.size() < 65536) r.heard.insert(r.heard.end(), chunk.begin(), chunk.end());
    dec.feed(chunk);
    std::optional<std::uint8_t> from;
    while (auto item = dec.next()) {
      if (!item->ok()) continue;
      const auto& t = item->value();
      explained += 3 + 3 + t.data.size() + chk.size() + 1;
      if (t.main != 0x00 || t.sub != 0x00) continue;  // an echo of a request, or no answer
      r.answered.emplace(t.id, t.data.size());
      from = t.id;
    }
    return from;
  };
  const auto deadline = std::chrono::microseconds(static_cast<long long>(deadline_ms * 1000.0));
  // A frame that has started is read to its end: the longest telegram's wire time.
  const auto frame_time = std::chrono::microseconds(
      static_cast<long long>(72.0 * 1e6 * transport::bits_per_byte(line) / line.baud));
  const std::string phase = "scanning " + line_name(line) + " " + checksum_name(chk);
  for (unsigned id = first; id <= last; ++id) {
    if (o.progress) o.progress(phase, id - first + 1, last - first + 1);
    LMCFG_ASSIGN_OR_RETURN(Bytes wire, codec::encode(codec::make_response_request(
                                                         static_cast<std::uint8_t>(id),
                                                         codec::ResponseRequest::default_response),
                                                     chk));
    LMCFG_TRY(link.write(wire));
    ++telegrams;
    auto until = Clock::now() + deadline;
    bool extended = false;
    for (;;) {
      const auto now = Clock::now();
      if (now >= until) {
        // Bytes of a frame still arriving: give it the time to finish, once.
        if (!extended && dec.buffered() > 0) {
          until = now + frame_time;
          extended = true;
          continue;
        }
        break;
      }
      auto left = std::chrono::ceil<transport::Millis>(until - now);
      LMCFG_ASSIGN_OR_RETURN(Bytes chunk, link.read_some(left));
      if (chunk.empty()) continue;
      if (auto from = take(chunk); from && *from == id) break;
    }
  }
  // The last IDs' answers may still be on their way.
  for (;;) {
    LMCFG_ASSIGN_OR_RETURN(
        Bytes chunk, link.read_some(transport::Millis(static_cast<long long>(deadline_ms) + 1)));
    if (chunk.empty()) break;
    take(chunk);
  }
  r.unexplained = r.heard.size() > explained ? r.heard.size() - explained : 0;
  return r;
}

// Telegrams in `heard` that decode as answers with checksum `c`.
std::map<std::uint8_t, std::size_t> answers_with(const Bytes& heard,
                                                 const codec::ChecksumConfig& c) {
  std::map<std::uint8_t, std::size_t> out;
  codec::StreamDecoder dec(c);
  dec.feed(heard);
  while (auto item = dec.next()) {
    if (item->ok() && item->value().main == 0x00 && item->value().sub == 0x00)
      out.emplace(item->value().id, item->value().data.size());
  }
  return out;
}

bool same_drive(const FoundDrive& a, const FoundDrive& b) {
  return a.id == b.id && a.line == b.line && a.checksum == b.checksum;
}

}  // namespace

std::vector<unsigned> scan_rates() { return {57600, 115200, 38400, 19200, 9600, 4800}; }

double id_deadline_ms(const transport::SerialSettings& line, const codec::ChecksumConfig& c,
                      double latency_ms, const ScanOptions& o) {
  const double byte_ms = 1e3 * transport::bits_per_byte(line) / static_cast<double>(line.baud);
  const double request_bytes = 7.0 + static_cast<double>(c.size());
  return (request_bytes + 1.0) * byte_ms + o.turnaround_ms + latency_ms + o.margin_ms;
}

std::vector<codec::ChecksumConfig> checksum_variants() {
  std::vector<codec::ChecksumConfig> v{codec::ChecksumConfig{}};
  for (auto cov :
       {codec::ChecksumCoverage::id_through_data, codec::ChecksumCoverage::start_through_data,
        codec::ChecksumCoverage::data_only}) {
    for (const char* name : {"add", "crc-ffff", "crc-0000", "crc-kermit"}) {
      auto c = parse_checksum(name).value();
      c.coverage = cov;
      v.push_back(c);
    }
  }
  return v;
}

std::string link_options_of(const FoundDrive& d) {
  char id[16];
  std::snprintf(id, sizeof id, "0x%02X", d.id);
  std::string s = "--baud " + std::to_string(d.line.baud);
  if (d.line.parity != transport::Parity::none)
    s += " --parity " + std::string(transport::parity_name(d.line.parity));
  if (d.line.stop_bits != 1) s += " --stop-bits " + std::to_string(d.line.stop_bits);
  s += " --id " + std::string(id) + " " + checksum_options(d.checksum);
  return s;
}

Result<ScanReport> scan(Session& session, const ScanOptions& o) {
  // A scan sends LinRS telegrams at MACIDs and rates: nothing a LinUDP drive
  // on Ethernet should receive (LinUDP V2 §3.2: addressed by IP).
  if (session.spec().port.scheme && session.spec().port.protocol() == Protocol::linudp) {
    return Error(Errc::not_supported, "port " + session.spec().port.text +
                                          ": a LinUDP drive is not scanned for LinRS settings");
  }
  ScanReport report;
  const auto t0 = Clock::now();
  auto& link = session.client().link();
  const std::uint8_t keep_id = session.client().options().id;
  const bool gateway = link.byte_time_us() <= 0.0;  // TCP: the rate is the gateway's
  std::vector<unsigned> rates = o.bauds.empty() ? scan_rates() : o.bauds;
  if (gateway) {
    report.notes.push_back(link.describe() +
                           ": the line rate is set in the gateway; scanned through it as it is");
    rates = {session.line().baud};
  }

  auto add_found = [&](FoundDrive d) {
    for (const auto& f : report.found)
      if (same_drive(f, d)) return;
    report.found.push_back(std::move(d));
  };

  // One pass; returns its bytes for the checksum analysis.
  auto pass = [&](const transport::SerialSettings& line,
                  const codec::ChecksumConfig& chk) -> Result<PassResult> {
    if (!gateway) LMCFG_TRY(session.relink(line, keep_id, chk));
    const double dl = o.deadline ? static_cast<double>(o.deadline->count())
                      : gateway  ? 50.0
                                 : id_deadline_ms(line, chk, link.receive_latency_ms(), o);
    const auto p0 = Clock::now();
    LMCFG_ASSIGN_OR_RETURN(auto r,
                           sweep(link, line, chk, o.first_id, o.last_id, dl, o, report.telegrams));
    ScanPass sp{line, chk, o.last_id - o.first_id + 1, dl, seconds_since(p0), r.unexplained};
    report.passes.push_back(sp);
    for (const auto& [id, n] : r.answered) {
      if (id < o.first_id || id > o.last_id) continue;
      add_found(FoundDrive{id, line, chk, n, "answered"});
    }
    return r;
  };

  // Confirms a candidate with one request at its settings.
  auto confirm = [&](const transport::SerialSettings& line, const codec::ChecksumConfig& chk,
                     std::uint8_t id) -> Result<std::optional<std::size_t>> {
    if (!gateway) LMCFG_TRY(session.relink(line, keep_id, chk));
    const double dl = o.deadline ? static_cast<double>(o.deadline->count())
                      : gateway  ? 50.0
                                 : id_deadline_ms(line, chk, link.receive_latency_ms(), o);
    LMCFG_ASSIGN_OR_RETURN(auto r,
                           sweep(link, line, chk, id, id, dl, ScanOptions{}, report.telegrams));
    if (auto it = r.answered.find(id); it != r.answered.end())
      return std::optional<std::size_t>(it->second);
    return std::optional<std::size_t>();
  };

  for (unsigned baud : rates) {
    transport::SerialSettings line = session.line();
    line.device.clear();
    line.baud = baud;
    LMCFG_ASSIGN_OR_RETURN(auto r, pass(line, o.checksum));
    if (r.unexplained == 0) continue;
    bool explained = false;
    if (o.try_checksums) {
      for (const auto& variant : checksum_variants()) {
        if (variant == o.checksum) continue;
        for (const auto& [id, n] : answers_with(r.heard, variant)) {
          if (id < o.first_id || id > o.last_id) continue;
          explained = true;
          LMCFG_ASSIGN_OR_RETURN(auto ok, confirm(line, variant, id));
          if (!ok) continue;
          add_found(FoundDrive{id, line, variant, *ok,
                               "answered a request without its checksum framed with " +
                                   checksum_name(variant) + "; confirmed"});
        }
      }
    }
    if (!explained && o.try_parities && !gateway) {
      for (auto parity : {transport::Parity::even, transport::Parity::odd}) {
        if (parity == line.parity) continue;
        auto p = line;
        p.parity = parity;
        LMCFG_TRY(pass(p, o.checksum));
      }
    }
  }
  report.seconds = seconds_since(t0);
  return report;
}

}  // namespace lmcfg::link
