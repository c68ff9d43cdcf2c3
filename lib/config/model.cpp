#include "config/model.hpp"

#include <algorithm>
#include <set>

#include "common/bytes.hpp"
#include "common/layers.hpp"
#include "config/fields.hpp"

namespace lmcfg::config {

std::string_view to_string(ParamSet s) noexcept {
  return s == ParamSet::full ? "full" : "modified";
}

std::optional<ParamSet> param_set_from_string(std::string_view s) noexcept {
  if (s == "modified") return ParamSet::modified;
  if (s == "full") return ParamSet::full;
  return std::nullopt;
}

// ---------------------------------------------------------------------------
std::string CurveView::length_ms_text() const {
  // length is in 10 us units: ms = length / 100, printed exactly.
  std::string s = std::to_string(length / 100);
  unsigned frac = length % 100;
  if (frac != 0) {
    s += '.';
    s += static_cast<char>('0' + frac / 10);
    if (frac % 10 != 0) s += static_cast<char>('0' + frac % 10);
  }
  return s;
}

std::string_view CurveView::x_name(int code) noexcept {
  switch (code) {
    case 0:
      return "time";
    case 1:
      return "encoder position";
    case 2:
      return "position";
    default:
      return "unknown";
  }
}

std::string_view CurveView::y_name(int code) noexcept {
  switch (code) {
    case 0:
      return "position";
    case 1:
      return "velocity";
    case 2:
      return "current";
    case 3:
      return "encoder position";
    case 4:
      return "encoder speed";
    default:
      return "unknown";
  }
}

Result<void> check_curve_blocks(const Curve& c) {
  if (c.info.size() < kCurveHeaderMin)
    return Error(Errc::validation_failed,
                 "info block has " + std::to_string(c.info.size()) +
                     " bytes; expected at least 8 (sizes at offsets 0, 4 and 6)");
  const std::uint16_t info_size = get_u16le(c.info, 0);
  if (info_size != c.info.size())
    return Error(Errc::validation_failed, "info block has " + std::to_string(c.info.size()) +
                                              " bytes but its header (offset 0) says " +
                                              std::to_string(info_size));
  const std::uint32_t count = get_u16le(c.info, 4);
  const std::uint32_t bps = get_u16le(c.info, 6);
  if (count * bps != c.data.size())
    return Error(Errc::validation_failed,
                 "data block has " + std::to_string(c.data.size()) +
                     " bytes but the info block says " + std::to_string(count) + " setpoints x " +
                     std::to_string(bps) + " bytes = " + std::to_string(count * bps));
  return {};
}

namespace {
// A name stored in a drive's bytes (curve info, command table entry): printable
// ASCII as is, anything else (and the escape character itself) as \xNN. The
// manuals give no character set for these fields, and a drive may hold any
// bytes there; the files are UTF-8 text, so a byte that is not ASCII cannot be
// copied through.
std::string printable_name(ByteView raw, std::size_t begin, std::size_t end) {
  std::string s;
  for (std::size_t i = begin; i < end && i < raw.size() && raw[i] != 0; ++i) {
    const auto c = raw[i];
    if (c >= 0x20 && c < 0x7F && c != '\\') {
      s.push_back(static_cast<char>(c));
    } else {
      static const char* kHex = "0123456789ABCDEF";
      s += "\\x";
      s.push_back(kHex[c >> 4]);
      s.push_back(kHex[c & 15]);
    }
  }
  return s;
}
}  // namespace

Result<CurveView> decode_curve(const Curve& c) {
  LMCFG_TRY(check_curve_blocks(c));
  if (c.info.size() < kCurveInfoFull)
    return Error(Errc::validation_failed,
                 "info block has " + std::to_string(c.info.size()) + " bytes; decoding needs 70");
  const ByteView b = c.info;
  CurveView v;
  v.info_size = get_u16le(b, 0);
  v.object_type = get_u16le(b, 2);
  const unsigned hi = v.object_type >> 8;
  v.x_code = static_cast<int>(hi & 0x0F);
  v.y_code = static_cast<int>(hi >> 4);
  v.setpoint_count = get_u16le(b, 4);
  v.bytes_per_setpoint = get_u16le(b, 6);
  v.name = printable_name(b, 8, 30);
  v.curve_id = get_u16le(b, 30);
  v.length = get_u32le(b, 32);
  v.x_dimension = get_u16le(b, 36);
  v.y_dimension = get_u16le(b, 38);
  v.wizard = get_u16le(b, 40);
  for (std::size_t i = 0; i < v.wizard_params.size(); ++i)
    v.wizard_params[i] = get_u32le(b, 42 + 4 * i);
  if (v.bytes_per_setpoint != 0 && v.bytes_per_setpoint % 4 == 0) {
    v.setpoints.reserve(c.data.size() / 4);
    for (std::size_t off = 0; off + 4 <= c.data.size(); off += 4)
      v.setpoints.push_back(static_cast<std::int32_t>(get_u32le(c.data, off)));
  }
  return v;
}

std::string ct_entry_name(ByteView raw) { return printable_name(raw, 38, 54); }

// ---------------------------------------------------------------------------
const Parameter* DriveConfig::find_param(std::uint16_t upid) const {
  const int l = lmcfg::layers::of_upid(upid);
  if (l == 0) return nullptr;
  for (const auto& p : layer(l))
    if (p.upid == upid) return &p;
  return nullptr;
}
const Curve* DriveConfig::find_curve(std::uint32_t id) const {
  for (const auto& c : curves)
    if (c.id == id) return &c;
  return nullptr;
}
const CtEntry* DriveConfig::find_ct_entry(std::uint32_t id) const {
  for (const auto& e : ct_entries)
    if (e.id == id) return &e;
  return nullptr;
}

void canonicalize(DriveConfig& cfg) {
  for (auto& l : cfg.layers)
    std::stable_sort(l.begin(), l.end(),
                     [](const auto& a, const auto& b) { return a.upid < b.upid; });
  std::stable_sort(cfg.curves.begin(), cfg.curves.end(),
                   [](const auto& a, const auto& b) { return a.id < b.id; });
  std::stable_sort(cfg.ct_entries.begin(), cfg.ct_entries.end(),
                   [](const auto& a, const auto& b) { return a.id < b.id; });
  if (cfg.devicenet) {
    const auto by_target = [](const DevicenetValue& a, const DevicenetValue& b) {
      return std::pair(a.motor, a.command) < std::pair(b.motor, b.command);
    };
    std::stable_sort(cfg.devicenet->values.begin(), cfg.devicenet->values.end(), by_target);
    std::stable_sort(cfg.devicenet->live.begin(), cfg.devicenet->live.end(), by_target);
    std::sort(cfg.devicenet->motors.begin(), cfg.devicenet->motors.end());
  }
}

bool is_clean_text(std::string_view s) noexcept {
  std::size_t i = 0;
  while (i < s.size()) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c < 0x20 || c == 0x7F) return false;
    if (c < 0x80) {
      ++i;
      continue;
    }
    std::size_t n = 0;
    std::uint32_t cp = 0;
    if ((c & 0xE0) == 0xC0) {
      n = 1;
      cp = c & 0x1Fu;
    } else if ((c & 0xF0) == 0xE0) {
      n = 2;
      cp = c & 0x0Fu;
    } else if ((c & 0xF8) == 0xF0) {
      n = 3;
      cp = c & 0x07u;
    } else
      return false;
    if (i + n >= s.size()) return false;
    for (std::size_t k = 1; k <= n; ++k) {
      const auto cc = static_cast<unsigned char>(s[i + k]);
      if ((cc & 0xC0) != 0x80) return false;
      cp = (cp << 6) | (cc & 0x3Fu);
    }
    if ((n == 1 && cp < 0x80) || (n == 2 && cp < 0x800) || (n == 3 && cp < 0x10000) ||
        cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF) || (cp >= 0x80 && cp < 0xA0))
      return false;
    i += n + 1;
  }
  return true;
}

namespace {

std::string motor_text(int motor) {
  return motor == kDevicenetController ? std::string("the controller")
                                       : std::string("motor ") + static_cast<char>('A' + motor);
}

std::optional<Issue> find_devicenet_issue(const DriveConfig& cfg) {
  const auto& dn = *cfg.devicenet;
  const auto section = [](std::string field, std::string message) {
    return Issue{Issue::Where::devicenet, 0, 0, std::move(field), std::move(message)};
  };
  if (std::any_of(cfg.scope.layers.begin(), cfg.scope.layers.end(), [](bool b) { return b; }) ||
      cfg.scope.curves || cfg.scope.command_table)
    return Issue{Issue::Where::scope, 0, 0, "layers",
                 "a DeviceNet capture has no parameter layers, curves or command table: its "
                 "scope must name none"};
  for (int l = 1; l <= lmcfg::layers::kCount; ++l)
    if (!cfg.layer(l).empty())
      return Issue{Issue::Where::layer, l, 0, "", "a DeviceNet capture has no UPID parameters"};
  if (dn.can_bitrate != 125000 && dn.can_bitrate != 250000 && dn.can_bitrate != 500000)
    return section("can_bitrate", "CAN bit rate " + std::to_string(dn.can_bitrate) +
                                      " is not a DeviceNet rate (125000, 250000, 500000)");
  for (const auto& m : dn.io_modules)
    if (m.empty() || !is_clean_text(m))
      return section("io_modules", "expected module names of UTF-8 text, not empty");
  std::set<int> motors;
  for (int m : dn.motors)
    if (m < 0 || m > 3 || !motors.insert(m).second)
      return section("motors", "expected motors A..D, each once");
  for (const bool live : {false, true}) {
    const auto& list = live ? dn.live : dn.values;
    std::set<std::pair<int, int>> seen;
    for (std::size_t i = 0; i < list.size(); ++i) {
      const auto& v = list[i];
      const auto at = [&](std::string field, std::string message) {
        Issue is{Issue::Where::devicenet_value, 0, i, std::move(field), std::move(message)};
        is.live = live;
        return is;
      };
      if (v.motor != kDevicenetController && (v.motor < 0 || v.motor > 3))
        return at("motor", "expected the controller or a motor A..D");
      if (v.motor != kDevicenetController && !motors.count(v.motor))
        return at("motor", motor_text(v.motor) + " is not among the section's motors");
      if (v.command > 0x7F)
        return at("command", "command ID " + hex(v.command, 2) + "h is outside 00h..7Fh");
      if (!live && (v.command & 1))
        return at("command", "command ID " + hex(v.command, 2) +
                                 "h is a Set command; values are recorded under their Get "
                                 "command (an even ID)");
      if (!seen.insert({v.motor, v.command}).second)
        return at("command",
                  "duplicate command " + hex(v.command, 2) + "h for " + motor_text(v.motor));
      if (auto field = fields::unclean_text(fields::devicenet_value_fields(), v))
        return at(*field, "expected UTF-8 text without control characters");
    }
  }
  return std::nullopt;
}

}  // namespace

std::optional<Issue> find_issue(const DriveConfig& cfg) {
  {
    const auto& id = cfg.identity;
    if (auto field = fields::unclean_text(fields::identity_fields(), id))
      return Issue{Issue::Where::identity, 0, 0, *field,
                   "expected UTF-8 text without control characters"};
    for (const auto& [k, v] : id.labels) {
      if (k.empty() || !is_clean_text(k))
        return Issue{Issue::Where::identity, 0, 0, "labels",
                     "expected label names of UTF-8 text without control characters, not empty"};
      if (!is_clean_text(v))
        return Issue{Issue::Where::identity, 0, 0, "labels." + k,
                     "expected UTF-8 text without control characters"};
    }
  }
  for (int l = 1; l <= lmcfg::layers::kCount; ++l) {
    const auto& params = cfg.layer(l);
    const std::string_view info_name = lmcfg::layers::name(l);
    const unsigned first_upid = lmcfg::layers::base_upid(l), last_upid = first_upid + 0x0EFFu;
    if (!params.empty() && !cfg.scope.layers[static_cast<std::size_t>(l - 1)]) {
      Issue is{Issue::Where::layer, l, 0, "", ""};
      is.message = "layer " + std::to_string(l) + " (" + std::string(info_name) +
                   ") has parameters but is not in the scope's layers";
      return is;
    }
    std::set<std::uint16_t> seen;
    for (std::size_t i = 0; i < params.size(); ++i) {
      const auto& p = params[i];
      if (p.upid < first_upid || p.upid > last_upid)
        return Issue{Issue::Where::param, l, i, "upid",
                     "UPID " + hex(p.upid, 4) + "h is outside layer " + std::to_string(l) + " (" +
                         std::string(info_name) + ") range " + hex(first_upid, 4) + "-" +
                         hex(last_upid, 4)};
      if (!seen.insert(p.upid).second)
        return Issue{Issue::Where::param, l, i, "upid",
                     "duplicate UPID " + hex(p.upid, 4) + "h in layer " + std::to_string(l) + " (" +
                         std::string(info_name) + ")"};
      if (auto field = fields::unclean_text(fields::parameter_fields(), p))
        return Issue{Issue::Where::param, l, i, *field,
                     "expected UTF-8 text without control characters"};
      if (p.type && *p.type > 0x0F)
        return Issue{Issue::Where::param, l, i, "type",
                     "type code " + std::to_string(*p.type) + " is not a type code (0..15)"};
    }
  }
  for (std::size_t i = 0; i < cfg.scope.drive_lacks.size(); ++i) {
    const std::string& g = cfg.scope.drive_lacks[i];
    if (g != "curves" && g != "command_table")
      return Issue{Issue::Where::scope, 0, 0, "drive_lacks",
                   "'" + (is_clean_text(g) ? g : std::string("?")) +
                       "' is not a group (expected curves or command_table)"};
    if (std::find(cfg.scope.drive_lacks.begin(), cfg.scope.drive_lacks.begin() + i, g) !=
        cfg.scope.drive_lacks.begin() + i)
      return Issue{Issue::Where::scope, 0, 0, "drive_lacks", "'" + g + "' is listed twice"};
    if (g == "curves" ? cfg.scope.curves : cfg.scope.command_table)
      return Issue{Issue::Where::scope, 0, 0, "drive_lacks",
                   "the drive lacks '" + g + "', but the scope says it was captured"};
  }
  if (!cfg.curves.empty() && !cfg.scope.curves)
    return Issue{Issue::Where::scope, 0, 0, "curves",
                 "the file holds curves but its scope says curves were not captured"};
  std::set<std::uint32_t> curve_ids;
  for (std::size_t i = 0; i < cfg.curves.size(); ++i) {
    const auto& c = cfg.curves[i];
    if (c.id > 0xFFFF)
      return Issue{Issue::Where::curve, 0, i, "id",
                   "curve ID " + std::to_string(c.id) + " is outside 0..65535"};
    if (!curve_ids.insert(c.id).second)
      return Issue{Issue::Where::curve, 0, i, "id", "duplicate curve ID " + std::to_string(c.id)};
    if (auto r = check_curve_blocks(c); !r.ok()) {
      const bool info_problem =
          c.info.size() < kCurveHeaderMin || get_u16le(c.info, 0) != c.info.size();
      return Issue{Issue::Where::curve, 0, i, info_problem ? "info" : "data",
                   "curve " + std::to_string(c.id) + ": " + r.error().message};
    }
  }
  if (!cfg.ct_entries.empty() && !cfg.scope.command_table)
    return Issue{Issue::Where::scope, 0, 0, "command_table",
                 "the file holds command table entries but its scope says the command table was "
                 "not captured"};
  std::set<std::uint32_t> ct_ids;
  for (std::size_t i = 0; i < cfg.ct_entries.size(); ++i) {
    const auto& e = cfg.ct_entries[i];
    if (e.id > kMaxCtEntryId)
      return Issue{Issue::Where::ct_entry, 0, i, "id",
                   "command table entry ID " + std::to_string(e.id) + " is outside 0..255"};
    if (!ct_ids.insert(e.id).second)
      return Issue{Issue::Where::ct_entry, 0, i, "id",
                   "duplicate command table entry ID " + std::to_string(e.id)};
    if (e.raw.empty())
      return Issue{Issue::Where::ct_entry, 0, i, "raw",
                   "command table entry " + std::to_string(e.id) + " has no bytes"};
  }
  if (cfg.devicenet) return find_devicenet_issue(cfg);
  return std::nullopt;
}

Result<void> validate(const DriveConfig& cfg) {
  auto is = find_issue(cfg);
  if (!is) return {};
  std::string where;
  switch (is->where) {
    case Issue::Where::identity:
      where = "identity " + is->field;
      break;
    case Issue::Where::scope:
      where = "scope";
      break;
    case Issue::Where::layer:
      where = "layer " + std::to_string(is->layer);
      break;
    case Issue::Where::param:
      where = "layer " + std::to_string(is->layer) + " parameter #" + std::to_string(is->index + 1);
      break;
    case Issue::Where::curve:
      where = "curve #" + std::to_string(is->index + 1);
      break;
    case Issue::Where::ct_entry:
      where = "command table entry #" + std::to_string(is->index + 1);
      break;
    case Issue::Where::devicenet:
      where = "devicenet " + is->field;
      break;
    case Issue::Where::devicenet_value:
      where = std::string("devicenet ") + (is->live ? "live" : "values") + " #" +
              std::to_string(is->index + 1);
      break;
  }
  return Error(Errc::validation_failed, "invalid configuration: " + where + ": " + is->message);
}

}  // namespace lmcfg::config
