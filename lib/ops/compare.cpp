// The one comparison behind diff, the restore plan and verify. See compare.hpp.
#include "ops/compare.hpp"

#include <map>
#include <set>

#include "db/database.hpp"

namespace lmcfg::ops {

DefaultValue default_of(const db::Database& db, std::uint16_t upid,
                        std::optional<std::uint32_t> recorded) {
  // The database describes the firmware; a capture's record is the source
  // drive's own answer (§10 05h 07h), used where the database is silent.
  if (const db::Parameter* d = db.find(upid); d && d->default_value)
    return {static_cast<std::uint32_t>(*d->default_value), DefaultSource::database};
  if (recorded) return {recorded, DefaultSource::recorded};
  return {};
}

const char* reason_text(Reason r) {
  switch (r) {
    case Reason::same:
      return "same";
    case Reason::differs:
      return "differs";
    case Reason::only_in_a:
      return "only in A";
    case Reason::only_in_b:
      return "only in B";
  }
  return "?";
}

namespace {

using ByUpid = std::map<std::uint16_t, const config::Parameter*>;

ByUpid by_upid(const ParamSide& s) {
  ByUpid m;
  if (s.values)
    for (const auto& p : *s.values) m.emplace(p.upid, &p);
  return m;
}

const config::Parameter* find_in(const ByUpid& m, std::uint16_t upid) {
  auto it = m.find(upid);
  return it == m.end() ? nullptr : it->second;
}

Result<std::optional<std::uint32_t>> ask(const ParamSide& s, std::uint16_t upid) {
  if (!s.ask) return std::optional<std::uint32_t>();
  return s.ask(upid);
}

// The unlisted side's value of `upid` (the listed side holds `other`), as its
// Resolve says; `row.def` gets the rule's answer where the rule is consulted.
Result<void> resolve_unlisted(const ParamSide& side, std::uint16_t upid, std::uint32_t other,
                              std::optional<std::uint32_t> recorded, const db::Database& db,
                              ParamRow& row, ParamValue& v) {
  auto asked = [&]() -> Result<void> {
    LMCFG_ASSIGN_OR_RETURN(auto value, ask(side, upid));
    if (value) {
      if (v.state == ParamValue::State::at_default) {
        v.value = value;
        v.source = DefaultSource::asked;
      }
      if (side.resolve == Resolve::rule_then_ask) row.def = {value, DefaultSource::asked};
    }
    return {};
  };
  switch (side.resolve) {
    case Resolve::none:
      return {};
    case Resolve::ask:
      return asked();
    case Resolve::rule_then_ask:
      row.def = default_of(db, upid, recorded);
      if (!row.def.value) return asked();
      break;
    case Resolve::rule_if_differs:
      row.def = default_of(db, upid, recorded);
      if (!row.def.value || *row.def.value == other) return asked();
      break;
  }
  if (v.state == ParamValue::State::at_default) {
    v.value = row.def.value;
    v.source = row.def.source;
  }
  return {};
}

Reason reason_of(const ParamValue& a, const ParamValue& b) {
  if (a.value && b.value) return *a.value == *b.value ? Reason::same : Reason::differs;
  return a.value ? Reason::only_in_a : Reason::only_in_b;
}

}  // namespace

Result<ParamCompare> compare_parameters(int layer, const ParamSide& a, const ParamSide& b,
                                        const db::Database& db,
                                        const std::function<void(std::uint16_t)>& visit) {
  ParamCompare out;
  const ByUpid pa = by_upid(a), pb = by_upid(b);
  std::set<std::uint16_t> upids;
  for (const auto& [upid, p] : pa) upids.insert(upid);
  for (const auto& [upid, p] : pb) upids.insert(upid);
  auto unlisted_state = [](const ParamSide& s) {
    return s.listed == config::ParamSet::modified ? ParamValue::State::at_default
                                                  : ParamValue::State::not_writable;
  };
  for (auto upid : upids) {
    if (visit) visit(upid);
    ParamRow row;
    row.layer = layer;
    row.upid = upid;
    const auto* ra = find_in(pa, upid);
    const auto* rb = find_in(pb, upid);
    if (ra) row.a = {ParamValue::State::value, ra->value, DefaultSource::none, ra};
    if (rb) row.b = {ParamValue::State::value, rb->value, DefaultSource::none, rb};
    // The recorded default: either side's record (A's first).
    std::optional<std::uint32_t> recorded;
    for (const auto* p : {ra, rb})
      if (p && !recorded) recorded = p->default_value;
    if (!ra) {
      row.a.state = unlisted_state(a);
      LMCFG_TRY(resolve_unlisted(a, upid, rb->value, recorded, db, row, row.a));
    } else if (!rb) {
      row.b.state = unlisted_state(b);
      LMCFG_TRY(resolve_unlisted(b, upid, ra->value, recorded, db, row, row.b));
    }
    out.defaults_recorded += row.def.source == DefaultSource::recorded ? 1 : 0;
    out.defaults_asked += row.def.source == DefaultSource::asked ? 1 : 0;
    row.reason = reason_of(row.a, row.b);
    row.type_differs = ra && rb && ra->type && rb->type && *ra->type != *rb->type;
    out.rows.push_back(row);
  }
  return out;
}

namespace {

template <class T>
std::vector<EntryRow<T>> compare_entries(const std::vector<T>& a, const std::vector<T>& b) {
  std::map<std::uint32_t, EntryRow<T>> m;
  // The first record of an ID, as DriveConfig::find_curve / find_ct_entry.
  for (const auto& x : a)
    if (!m[x.id].a) m[x.id].a = &x;
  for (const auto& x : b)
    if (!m[x.id].b) m[x.id].b = &x;
  std::vector<EntryRow<T>> out;
  for (auto& [id, row] : m) {
    row.id = id;
    if (row.a && row.b)
      row.reason = *row.a == *row.b ? Reason::same : Reason::differs;
    else
      row.reason = row.a ? Reason::only_in_a : Reason::only_in_b;
    if (row.reason != Reason::same) out.push_back(row);
  }
  return out;
}

}  // namespace

std::vector<CurveRow> compare_curves(const std::vector<config::Curve>& a,
                                     const std::vector<config::Curve>& b) {
  return compare_entries(a, b);
}

std::vector<CtRow> compare_ct_entries(const std::vector<config::CtEntry>& a,
                                      const std::vector<config::CtEntry>& b) {
  return compare_entries(a, b);
}

}  // namespace lmcfg::ops
