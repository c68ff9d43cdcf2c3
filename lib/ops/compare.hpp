#pragma once
// One comparison of two sets of configuration values, for diff (ops/diff.hpp),
// the restore plan and verify (ops/restore.hpp); docs/architecture.md "One
// comparison". Parameters are compared by UPID per layer with the default rule
// in one place (default_of), curves and command table entries by ID and raw
// content. Each comparison gives typed rows (key, each side's value, a Reason);
// what a caller shows or does with them (diff's items, the plan's writes and
// deletes, verify's mismatches) stays with the caller, which never decides on
// display text.
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "common/result.hpp"
#include "config/model.hpp"

namespace lmcfg::db {
class Database;
}

namespace lmcfg::ops {

// Where a factory default came from.
enum class DefaultSource {
  none,      // unknown
  database,  // the UPID database
  recorded,  // a capture's record (the drive's own, asked at backup: §10 05h 07h)
  asked,     // asked now (the caller's AskValue: a drive's default or ROM value)
};

struct DefaultValue {
  std::optional<std::uint32_t> value;
  DefaultSource source = DefaultSource::none;
};

// The default rule: the database's default, else the recorded one (`recorded`:
// a capture's record of the UPID, either side's).
DefaultValue default_of(const db::Database& db, std::uint16_t upid,
                        std::optional<std::uint32_t> recorded);

// Why a row differs (or not).
enum class Reason {
  same,       // both values known and equal
  differs,    // both values known, they differ
  only_in_a,  // A holds it; B's value is not known (not listed and its default unknown, not
              // ROM-writable there, no such curve or entry)
  only_in_b,  // the other way round
};
// "same", "differs", "only in A", "only in B".
const char* reason_text(Reason r);

// ---------------------------------------------------------------------------
// Parameters.

// A side's value of a UPID it does not list: the default once resolved (nullopt:
// unknown). Link errors propagate; a refusal is nullopt.
using AskValue = std::function<Result<std::optional<std::uint32_t>>(std::uint16_t upid)>;

// How a side's UPID it does not list is resolved.
enum class Resolve {
  none,             // not at all: the row is only_in_X of the other side
  rule_then_ask,    // the default rule, else `ask` (diff)
  ask,              // always `ask` (verify: the drive's ROM value, §10 05h 01h)
  rule_if_differs,  // the rule where it shows a difference, else `ask`: a value equal to a
                    // recorded default may still differ from what a drive's ROM holds (plan)
};

struct ParamSide {
  const std::vector<config::Parameter>* values = nullptr;  // what the side lists
  // What an unlisted UPID stands for: a modified-only capture (§10.2) holds it
  // at its default; in a full capture (§10.3) it is not ROM-writable.
  config::ParamSet listed = config::ParamSet::modified;
  Resolve resolve = Resolve::rule_then_ask;
  AskValue ask;  // empty: never asked
};

struct ParamValue {
  enum class State { value, at_default, not_writable };
  State state = State::value;
  std::optional<std::uint32_t> value;          // listed, or the resolved default
  DefaultSource source = DefaultSource::none;  // at_default: where `value` came from
  const config::Parameter* record = nullptr;   // the side's record, when listed
};

struct ParamRow {
  int layer = 0;
  std::uint16_t upid = 0;
  ParamValue a, b;
  // When one side does not list the UPID: the default rule's answer (also
  // where it resolved nothing, e.g. against a full capture's not_writable).
  DefaultValue def;
  Reason reason = Reason::same;
  bool type_differs = false;  // both records give a type, and they differ
  bool differs() const { return reason != Reason::same || type_differs; }
};

struct ParamCompare {
  std::vector<ParamRow> rows;                             // every UPID either side lists, by UPID
  std::size_t defaults_recorded = 0, defaults_asked = 0;  // DefaultSource counts of `def`
};

// One layer's parameters of A and B. `visit` (optional) is called with each
// UPID before it is resolved (progress).
Result<ParamCompare> compare_parameters(int layer, const ParamSide& a, const ParamSide& b,
                                        const db::Database& db,
                                        const std::function<void(std::uint16_t)>& visit = {});

// ---------------------------------------------------------------------------
// Curves and command table entries: by ID, raw content.

template <class T>
struct EntryRow {
  std::uint32_t id = 0;
  const T* a = nullptr;  // nullptr: not on that side
  const T* b = nullptr;
  Reason reason = Reason::same;
};
using CurveRow = EntryRow<config::Curve>;
using CtRow = EntryRow<config::CtEntry>;

// The rows that differ, by ID.
std::vector<CurveRow> compare_curves(const std::vector<config::Curve>& a,
                                     const std::vector<config::Curve>& b);
std::vector<CtRow> compare_ct_entries(const std::vector<config::CtEntry>& a,
                                      const std::vector<config::CtEntry>& b);

}  // namespace lmcfg::ops
