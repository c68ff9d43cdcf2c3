#include "ops/expected_link.hpp"

#include <algorithm>
#include <cctype>

#include "common/bytes.hpp"
#include "common/layers.hpp"
#include "db/database.hpp"
#include "ops/compare.hpp"

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
  // Not in the file: no recorded default either, so the database's.
  return {default_of(db, upid, std::nullopt).value, true};
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

}  // namespace

link::ExpectedLink expected_link(const Plan& plan, const db::Database& db) {
  link::ExpectedLink out;
  if (db.is_empty())
    out.reasons.push_back(
        "no UPID database: the factory defaults of the LinRS parameters are unknown");
  const Known id_src = value_after(plan, db, kMacidSource);
  if (!id_src.value) {
    out.macid_reason =
        "MACID: " + hex(kMacidSource, 4, "h") +
        " MACID Source Select is at its factory default, the hex switches (seed 003 §15); their "
        "setting is not known to the tool";
  } else if (*id_src.value == kMacidByParameter) {
    const Known id = value_after(plan, db, kMacidValue);
    if (id.value && *id.value <= 0xFF) {
      out.macid = static_cast<std::uint8_t>(*id.value);
      out.macid_reason = "MACID " + hex(*out.macid, 2, "h") + ": " + hex(kMacidSource, 4, "h") +
                         " = By Parameter, " + hex(kMacidValue, 4, "h") +
                         " MACID Parameter Value = " + std::to_string(*id.value) +
                         (id.from_default ? " (its default)" : "");
    } else {
      out.macid_reason = "MACID: " + hex(kMacidSource, 4, "h") +
                         " = By Parameter, but the value of " + hex(kMacidValue, 4, "h") +
                         " is not known";
    }
  } else {
    out.macid_reason = "MACID: " + hex(kMacidSource, 4, "h") + " = " +
                       std::to_string(*id_src.value) +
                       " selects the hex switches, whose setting is not known to the tool";
  }
  out.reasons.push_back(out.macid_reason);

  const Known baud_src = value_after(plan, db, kBaudSource);
  if (!baud_src.value) {
    out.baud_reason =
        "baud rate: " + hex(kBaudSource, 4, "h") +
        " Baud Rate Source Select is at its factory default, hex switch S1 (seed 003 §15); its "
        "setting is not known to the tool";
  } else if (*baud_src.value == kBaudRateByParameter) {
    const Known code = value_after(plan, db, kBaudCode);
    if (code.value) out.baud = baud_of_label(db, kBaudCode, *code.value);
    if (out.baud) {
      out.baud_reason = "baud rate " + std::to_string(*out.baud) + ": " + hex(kBaudSource, 4, "h") +
                        " = By Parameter, " + hex(kBaudCode, 4, "h") +
                        " Baud Rate Parameter Def = " + std::to_string(*code.value);
    } else if (code.value) {
      out.baud_reason = "baud rate: " + hex(kBaudSource, 4, "h") +
                        " = By Parameter, but the database has no rate for " +
                        hex(kBaudCode, 4, "h") + " = " + std::to_string(*code.value) +
                        " (seed 003 states only 8 = 38400 Baud)";
    } else {
      out.baud_reason = "baud rate: " + hex(kBaudSource, 4, "h") +
                        " = By Parameter, but the raw value of " + hex(kBaudCode, 4, "h") +
                        " (its default, 57600 Bit/s by seed 003 §15) is not known";
    }
  } else {
    out.baud_reason = "baud rate: " + hex(kBaudSource, 4, "h") + " = " +
                      std::to_string(*baud_src.value) +
                      " selects hex switch S1, whose setting is not known to the tool";
  }
  out.reasons.push_back(out.baud_reason);
  return out;
}

}  // namespace lmcfg::ops
