#include "link/relink.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>

#include "common/bytes.hpp"
#include "link/scan.hpp"

namespace lmcfg::link {

namespace {

std::string describe(const RelinkCandidate& c) {
  std::string s = std::to_string(c.line.baud) + " Bd, MACID " + hex(c.macid, 2, "h") +
                  ", checksum " + checksum_name(c.checksum);
  if (c.line.parity != transport::Parity::none)
    s += ", parity " + std::string(transport::parity_name(c.line.parity));
  if (c.line.stop_bits != 1) s += ", " + std::to_string(c.line.stop_bits) + " stop bits";
  return s;
}

}  // namespace

std::string link_options_of(const RelinkCandidate& c) {
  FoundDrive d;
  d.id = c.macid;
  d.line = c.line;
  d.checksum = c.checksum;
  return link_options_of(d);
}

std::vector<RelinkCandidate> relink_candidates(const ExpectedLink& expected,
                                               const RelinkOverrides& o,
                                               const transport::SerialSettings& line,
                                               std::uint8_t macid,
                                               const codec::ChecksumConfig& checksum) {
  std::vector<unsigned> bauds;
  std::vector<std::uint8_t> ids;
  std::vector<codec::ChecksumConfig> sums;
  auto add_baud = [&](std::optional<unsigned> b) {
    if (b && std::find(bauds.begin(), bauds.end(), *b) == bauds.end()) bauds.push_back(*b);
  };
  auto add_id = [&](std::optional<std::uint8_t> i) {
    if (i && std::find(ids.begin(), ids.end(), *i) == ids.end()) ids.push_back(*i);
  };
  add_baud(o.baud);
  add_baud(expected.baud);
  add_baud(line.baud);
  for (unsigned b : transport::kSerialBaudRates) add_baud(b);
  add_id(o.macid);
  add_id(expected.macid);
  add_id(macid);
  if (o.checksum) sums.push_back(*o.checksum);
  if (!o.checksum || !(*o.checksum == checksum)) sums.push_back(checksum);

  std::vector<transport::SerialSettings> lines;
  if (o.parity || o.stop_bits) {
    transport::SerialSettings l = line;
    l.parity = o.parity.value_or(line.parity);
    l.stop_bits = o.stop_bits.value_or(line.stop_bits);
    if (l.parity != line.parity || l.stop_bits != line.stop_bits) lines.push_back(l);
  }
  lines.push_back(line);

  std::vector<RelinkCandidate> out;
  for (const auto& l : lines)
    for (unsigned b : bauds)
      for (auto id : ids)
        for (const auto& cs : sums) {
          RelinkCandidate c{l, id, cs};
          c.line.baud = b;
          out.push_back(c);
        }
  return out;
}

Result<RelinkReport> reconnect(Session& session, const ExpectedLink& expected,
                               const RelinkOverrides& overrides) {
  auto& client = session.client();
  const RelinkCandidate before{session.line(), client.options().id, client.options().checksum};
  const auto candidates =
      relink_candidates(expected, overrides, before.line, before.macid, before.checksum);
  RelinkReport rep;
  rep.reasons = expected.reasons;
  std::vector<std::string> tried, skipped;
  // One attempt per candidate: a retry would only double the time spent on
  // settings the drive does not use.
  const auto saved = client.options();
  for (const auto& cand : candidates) {
    if (auto r = session.relink(cand.line, cand.macid, cand.checksum); !r.ok()) {
      const std::string what = std::to_string(cand.line.baud) + " Bd";
      if (std::find(skipped.begin(), skipped.end(), what) == skipped.end()) skipped.push_back(what);
      continue;
    }
    auto co = client.options();
    co.read_retries = 0;
    client.set_options(co);
    ++rep.attempts;
    auto answer = client.default_response();
    co.read_retries = saved.read_retries;
    client.set_options(co);
    // An error state (C1..C9) is an answer too: the drive hears these settings.
    if (answer.ok() || answer.error().code == ErrorClass::drive_refusal) {
      rep.used = cand;
      rep.changed =
          !(cand.line.baud == before.line.baud && cand.line.parity == before.line.parity &&
            cand.line.stop_bits == before.line.stop_bits && cand.macid == before.macid &&
            cand.checksum == before.checksum);
      rep.summary = "the drive answers at " + describe(cand);
      return rep;
    }
    tried.push_back(describe(cand));
  }
  (void)session.relink(before.line, before.macid, before.checksum);
  std::string msg = "after the reset the drive answered none of the " +
                    std::to_string(tried.size()) + " link settings tried (" +
                    (tried.empty() ? std::string("none") : tried.front()) +
                    (tried.size() > 1 ? " ... " + tried.back() : std::string()) + ")";
  if (!skipped.empty()) {
    msg += "; not tried, this link cannot change its line settings:";
    for (const auto& s : skipped) msg += " " + s;
  }
  for (const auto& r : expected.reasons) msg += "; " + r;
  return Error(Errc::timeout, msg);
}

Result<RelinkReport> reconnect_within(Session& session, const ExpectedLink& expected,
                                      const RelinkOverrides& overrides, transport::Millis budget) {
  const std::int64_t start = session.client().link().now_ns();
  const std::int64_t budget_ns = static_cast<std::int64_t>(budget.count()) * 1'000'000;
  for (std::int64_t round_start = start;;) {
    auto r = reconnect(session, expected, overrides);
    const std::int64_t now = session.client().link().now_ns();
    if (r.ok() || r.error().code != make_error_code(Errc::timeout) || now == round_start) return r;
    if (now - start >= budget_ns) {
      Error e = std::move(r).error();
      e.message += "; looked for it for " + std::to_string(budget.count() / 1000) +
                   " s (--recover-timeout-s)";
      return e;
    }
    round_start = now;
  }
}

}  // namespace lmcfg::link
