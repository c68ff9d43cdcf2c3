#pragma once
// Diff of two drive configurations (README). Parameters are
// compared by effective value: a UPID absent from a modified-only capture
// (§10.2) is at its default; absent from a full capture (§10.3) it is not
// ROM-writable. A recorded type that differs between the sides is a
// difference even when the values are equal; a value that does not fit its
// type (never truncated) or lies outside the database's range is flagged
// INVALID on the side that holds it. A layer, the curves or the command table
// captured on one side only is a difference of kind `scope` (the other side
// cannot say what it holds), and the header states each side's scope and what
// was compared. Curves and command table entries are compared by raw
// content, with a decoded summary of what changed.
//
// DeviceNet captures (the `devicenet` section, seed 000) are compared value by
// value (motor, Get command ID); their informational `live` values only when
// asked. A DeviceNet capture and a LinRS capture are not comparable: the
// result says so (one scope item and a note) and compares nothing else.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "config/model.hpp"

namespace lmcfg::db {
class Database;
}

namespace lmcfg::ops {

struct DiffOptions {
  bool ignore_metadata = false;  // identity (MACID, firmware, fingerprint, labels)
  bool ignore_unit = false;      // per-unit data: communication parameters, the MACID and the
                                 // DeviceNet CAN bit rate
  bool include_live = false;     // DeviceNet: compare the `live` values too
  // The side is factory_defaults_config(): a DeviceNet capture on the other
  // side has no factory defaults to compare with (a scope item and a note).
  bool a_is_defaults = false;
  bool b_is_defaults = false;
};

// Default value of a UPID when the configuration does not list it; nullopt if
// unknown. diff() asks it only when neither the database nor a capture's
// recorded default knows the value; the tools ask a connected drive (05h 07h).
using DefaultLookup = std::function<std::optional<std::uint32_t>(std::uint16_t upid)>;

struct DiffItem {
  enum class Kind { metadata, parameter, curve, ct_entry, scope, devicenet };
  Kind kind = Kind::parameter;
  int layer = 0;          // parameters: 1..4
  std::uint32_t key = 0;  // UPID, curve ID, CT entry ID or DeviceNet Get command ID
  std::string name;       // parameter name, curve name, entry name, or metadata field
  std::string a;          // value on side A as text ("16", "default 15", "absent")
  std::string b;
  std::string detail;  // decoded summary ("target 100 mm -> 50 mm"), "type UINT16 -> SINT16"
  // Parameters: why the side's value is invalid ("" = valid), and the type
  // each side was shown by ("" = unknown).
  std::string a_invalid, b_invalid;
  std::string a_type, b_type;
  // devicenet: whose value (config::kDevicenetController or motor 0..3 = A..D)
  // and whether it is one of the `live` values.
  int motor = config::kDevicenetController;
  bool live = false;
};
// "metadata", "parameter", "curve", "ct_entry", "scope", "devicenet": the
// `kind` of diff --json.
const char* kind_name(DiffItem::Kind k);

struct DiffResult {
  config::Scope scope_a, scope_b;
  config::Scope compared;  // what both sides captured (parameters: "full" only if both are)
  std::vector<DiffItem> items;
  std::vector<std::string> notes;                 // what could not be compared, and why
  bool devicenet_a = false, devicenet_b = false;  // the side is a DeviceNet capture
  bool live_compared = false;                     // DeviceNet `live` values were compared
  bool identical() const { return items.empty(); }
};

DiffResult diff(const config::DriveConfig& a, const config::DriveConfig& b, const db::Database& db,
                const DefaultLookup& defaults, const DiffOptions& opt);

// Factory state as a configuration: every layer captured, nothing modified, no
// curves, no command table entries.
config::DriveConfig factory_defaults_config();
// The same within `scope` (the other side's), so `diff defaults FILE` compares
// what FILE captured and reports no scope difference.
config::DriveConfig factory_defaults_config(const config::Scope& scope);

// "modified parameters of OS, MC, Intf, Appl; curves; command table"
std::string describe_scope(const config::Scope& s);

std::string render_text(const DiffResult& r, const std::string& a_name, const std::string& b_name);
std::string render_json(const DiffResult& r, const std::string& a_name, const std::string& b_name);

}  // namespace lmcfg::ops
