#include "ops/relink.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>

#include "common/bytes.hpp"
#include "common/layers.hpp"
#include "db/database.hpp"

namespace lmcfg::ops {

namespace {

constexpr std::uint16_t kBaudSource = kBaudRateSource, kBaudCode = kBaudRateCode;

struct Known {
  std::optional<std::uint32_t> value;
  bool from_default = false;
};

// The value a restored layer holds after the restore: the file's, else the
// factory default (as far as the database knows it). Unknown outside the
// restored layers: those keep whatever the target had.
Known value_after(const Plan& plan, const db::Database& db, std::uint16_t upid) {
  const int layer = layers::of_upid(upid);
  if (layer == 0 || !plan.expected.scope.layers[static_cast<std::size_t>(layer - 1)]) return {};
  for (const auto& p : plan.expected.layer(layer))
    if (p.upid == upid) return {p.value, false};
  const db::Parameter* d = db.find(upid);
  if (d && d->default_value) return {static_cast<std::uint32_t>(*d->default_value), true};
  return {std::nullopt, true};
}

// "38400 Baud" -> 38400, when the label starts with one of the §3.2.1 rates.
std::optional<unsigned> baud_of_label(const db::Database& db, std::uint16_t upid,
                                      std::uint32_t raw) {
  const db::Parameter* d = db.find(upid);
  if (!d) return std::nullopt;
  for (const auto& l : d->spec.labels) {
    if (l.raw != static_cast<std::int64_t>(raw)) continue;
    unsigned rate = 0;
    for (char ch : l.label) {
      if (!std::isdigit(static_cast<unsigned char>(ch))) break;
      rate = rate * 10 + static_cast<unsigned>(ch - '0');
    }
    if (std::find(transport::kSerialBaudRates.begin(), transport::kSerialBaudRates.end(), rate) !=
        transport::kSerialBaudRates.end())
      return rate;
  }
  return std::nullopt;
}

std::string describe(const RelinkCandidate& c) {
  std::string s = std::to_string(c.line.baud) + " Bd, MACID " + hex(c.macid, 2, "h") +
                  ", checksum " + checksum_name(c.checksum);
  if (c.line.parity != transport::Parity::none)
    s += ", parity " + std::string(transport::parity_name(c.line.parity));
  if (c.line.stop_bits != 1) s += ", " + std::to_string(c.line.stop_bits) + " stop bits";
  return s;
}

}  // namespace

ExpectedLink expected_link(const Plan& plan, const db::Database& db) {
  ExpectedLink out;
  if (db.is_empty())
    out.reasons.push_back(
        "no UPID database: the factory defaults of the LinRS parameters are unknown");
  const Known id_src = value_after(plan, db, kMacidSource);
  if (!id_src.value) {
    out.reasons.push_back(
        "MACID: " + hex(kMacidSource, 4, "h") +
        " MACID Source Select is at its factory default, the hex switches (seed 003 §15); their "
        "setting is not known to the tool");
  } else if (*id_src.value == kMacidByParameter) {
    const Known id = value_after(plan, db, kMacidValue);
    if (id.value && *id.value <= 0xFF) {
      out.macid = static_cast<std::uint8_t>(*id.value);
      out.reasons.push_back("MACID " + hex(*out.macid, 2, "h") + ": " + hex(kMacidSource, 4, "h") +
                            " = By Parameter, " + hex(kMacidValue, 4, "h") +
                            " MACID Parameter Value = " + std::to_string(*id.value) +
                            (id.from_default ? " (its default)" : ""));
    } else {
      out.reasons.push_back("MACID: " + hex(kMacidSource, 4, "h") +
                            " = By Parameter, but the value of " + hex(kMacidValue, 4, "h") +
                            " is not known");
    }
  } else {
    out.reasons.push_back("MACID: " + hex(kMacidSource, 4, "h") + " = " +
                          std::to_string(*id_src.value) +
                          " selects the hex switches, whose setting is not known to the tool");
  }

  const Known baud_src = value_after(plan, db, kBaudSource);
  if (!baud_src.value) {
    out.reasons.push_back(
        "baud rate: " + hex(kBaudSource, 4, "h") +
        " Baud Rate Source Select is at its factory default, hex switch S1 (seed 003 §15); its "
        "setting is not known to the tool");
  } else if (*baud_src.value == kBaudRateByParameter) {
    const Known code = value_after(plan, db, kBaudCode);
    if (code.value) out.baud = baud_of_label(db, kBaudCode, *code.value);
    if (out.baud) {
      out.reasons.push_back("baud rate " + std::to_string(*out.baud) + ": " +
                            hex(kBaudSource, 4, "h") + " = By Parameter, " +
                            hex(kBaudCode, 4, "h") +
                            " Baud Rate Parameter Def = " + std::to_string(*code.value));
    } else if (code.value) {
      out.reasons.push_back("baud rate: " + hex(kBaudSource, 4, "h") +
                            " = By Parameter, but the database has no rate for " +
                            hex(kBaudCode, 4, "h") + " = " + std::to_string(*code.value) +
                            " (seed 003 states only 8 = 38400 Baud)");
    } else {
      out.reasons.push_back("baud rate: " + hex(kBaudSource, 4, "h") +
                            " = By Parameter, but the raw value of " + hex(kBaudCode, 4, "h") +
                            " (its default, 57600 Bit/s by seed 003 §15) is not known");
    }
  } else {
    out.reasons.push_back("baud rate: " + hex(kBaudSource, 4, "h") + " = " +
                          std::to_string(*baud_src.value) +
                          " selects hex switch S1, whose setting is not known to the tool");
  }
  return out;
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

}  // namespace lmcfg::ops
