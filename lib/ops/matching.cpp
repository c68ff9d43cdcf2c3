// One meaning of "matches" (ops/matching.hpp, docs/fleet.md "What matches means").
#include "ops/matching.hpp"

#include <algorithm>

#include "common/bytes.hpp"
#include "common/layers.hpp"
#include "db/database.hpp"
#include "ops/expected_link.hpp"
#include "ops/restore.hpp"

namespace lmcfg::ops {

const char* kept_by_name(KeptBy k) { return k == KeptBy::communication ? "communication" : "unit"; }

const char* kept_reason(KeptBy k) {
  if (k == KeptBy::communication)
    return "a communication setting: a restore keeps the drive's own value, so that the drive "
           "keeps answering on its line as it does now";
  return "the drive's place on its line, which the inventory sets";
}

const char* kept_remedy(KeptBy k) {
  if (k == KeptBy::communication)
    return "Nothing needs doing while the drive answers on its line. To make the drive's own "
           "settings the approved ones, approve its state after the next backup. To give the "
           "drive the configuration's settings, an engineer restores it with its communication "
           "settings included (lmcfg restore --include-comm) on a line of its own: the drive "
           "then answers only at the new settings.";
  return "Nothing to do: the inventory says where the drive answers.";
}

std::optional<KeptBy> kept_parameter(std::uint16_t upid, const db::Database& db,
                                     bool include_comm) {
  if (!include_comm && is_comm_parameter(db, upid)) return KeptBy::communication;
  return std::nullopt;
}

std::optional<KeptBy> kept_by(const DiffItem& it, const db::Database& db, const MatchPolicy& p) {
  switch (it.kind) {
    case DiffItem::Kind::parameter:
      return kept_parameter(static_cast<std::uint16_t>(it.key), db, p.include_comm);
    case DiffItem::Kind::metadata:
      // diff_metadata's per-unit fields (the ones --ignore-unit leaves out).
      if (it.name == "macid" || it.name == "devicenet can_bitrate") return KeptBy::unit;
      return std::nullopt;
    default:
      return std::nullopt;
  }
}

std::string moves_at_restart(const config::DriveConfig& drive, const db::Database& db,
                             const MatchPolicy& p) {
  if (drive.devicenet) return {};
  Plan as_read;
  as_read.expected = drive;
  const link::ExpectedLink after = expected_link(as_read, db);
  if (after.macid && p.macid && *after.macid != *p.macid)
    return "after its next restart the drive answers at MACID " + hex(*after.macid, 2, "h") +
           ", not at " + hex(*p.macid, 2, "h") + " where the inventory has it (" +
           after.macid_reason + ")";
  if (after.baud && p.baud && *after.baud != *p.baud)
    return "after its next restart the drive answers at " + std::to_string(*after.baud) +
           " baud, not at the line's " + std::to_string(*p.baud) + " (" + after.baud_reason + ")";
  return {};
}

Matching match(DiffResult d, const config::DriveConfig& drive, const db::Database& db,
               const MatchPolicy& p) {
  Matching m;
  // Kept communication values hold only while they keep the drive where it is.
  const std::string moves = moves_at_restart(drive, db, p);
  for (auto& it : d.items) {
    if (it.kind == DiffItem::Kind::parameter &&
        std::find(p.ignored.begin(), p.ignored.end(), it.key) != p.ignored.end())
      continue;
    const auto kept = kept_by(it, db, p);
    if (kept && !(moves.size() && *kept == KeptBy::communication)) {
      m.kept.push_back(KeptValue{std::move(it), *kept});
      continue;
    }
    m.differences.push_back(std::move(it));
  }
  if (!moves.empty() && !drive.devicenet) {
    DiffItem it;
    it.kind = DiffItem::Kind::metadata;
    it.name = "link after restart";
    it.a = p.macid ? "MACID " + hex(*p.macid, 2, "h") : std::string("the line's settings");
    it.b = moves;
    m.differences.push_back(std::move(it));
  }
  return m;
}

std::string kept_text(const KeptValue& k, const char* side) {
  const DiffItem& it = k.item;
  std::string what;
  if (it.kind == DiffItem::Kind::parameter)
    what = std::string(layers::name(it.layer)) + " " + hex(it.key, 4, "h") +
           (it.name.empty() ? "" : " " + it.name);
  else
    what = it.name;
  return what + ": " + side + " " + it.a + ", drive " + it.b;
}

nlohmann::ordered_json kept_json(const KeptValue& k, const char* side) {
  const DiffItem& it = k.item;
  nlohmann::ordered_json j{{"kind", kind_name(it.kind)}};
  if (it.kind == DiffItem::Kind::parameter) {
    j["layer"] = std::string(layers::name(it.layer));
    j["upid"] = hex(it.key, 4);
  }
  j["name"] = it.name;
  j["configuration"] = it.a;
  j["drive"] = it.b;
  j["by"] = kept_by_name(k.by);
  j["reason"] = kept_reason(k.by);
  j["remedy"] = kept_remedy(k.by);
  j["text"] = kept_text(k, side);
  return j;
}

}  // namespace lmcfg::ops
