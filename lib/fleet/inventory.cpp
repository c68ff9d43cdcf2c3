#include "fleet/inventory.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <span>
#include <sstream>

#include "common/bytes.hpp"
#include "common/text.hpp"
#include "config/io_common.hpp"
#include "devicenet/catalogue.hpp"
#include "link/port.hpp"

namespace lmcfg::fleet {
namespace {

Position position_of(const toml::source_region& s, const std::string& file) {
  return Position{file, static_cast<int>(s.begin.line), static_cast<int>(s.begin.column)};
}

// Collects every problem of the file, so one `fleet check` shows them all.
class Checker {
 public:
  explicit Checker(std::string file) : file_(std::move(file)) {}

  void problem(const toml::source_region& at, const std::string& what) {
    problems_.push_back(position_of(at, file_).str() + ": " + what);
  }
  void problem(const Position& at, const std::string& what) {
    problems_.push_back(at.str() + ": " + what);
  }
  Position at(const toml::source_region& s) const { return position_of(s, file_); }
  const std::vector<std::string>& problems() const { return problems_; }

  // Every key of `t` is one of `allowed`; the message lists them.
  // Keys in `elsewhere` are reported by the caller (keys of the other protocol).
  void known_keys(const toml::table& t, std::span<const std::string_view> allowed,
                  std::string_view where, std::span<const std::string_view> elsewhere = {}) {
    for (auto&& [key, value] : t) {
      bool ok = false;
      for (auto a : allowed) ok = ok || key.str() == a;
      for (auto a : elsewhere) ok = ok || key.str() == a;
      if (ok) continue;
      std::string list;
      for (auto a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
      problem(key.source(), "unknown key '" + std::string(key.str()) + "' in " +
                                std::string(where) + " (known: " + list + ")");
    }
  }

  std::optional<std::string> string(const toml::table& t, std::string_view key,
                                    std::string_view where, bool required) {
    const toml::node* n = t.get(key);
    if (!n) {
      if (required) problem(t.source(), std::string(where) + " has no '" + std::string(key) + "'");
      return std::nullopt;
    }
    if (auto s = n->value<std::string>(); s && n->is_string()) return *s;
    problem(n->source(), "'" + std::string(key) + "' must be a string");
    return std::nullopt;
  }

  std::optional<std::int64_t> integer(const toml::table& t, std::string_view key) {
    const toml::node* n = t.get(key);
    if (!n) return std::nullopt;
    if (n->is_integer()) return n->as_integer()->get();
    problem(n->source(), "'" + std::string(key) + "' must be an integer");
    return std::nullopt;
  }

  // `ignore = ["1037h", "13A2"]`: UPIDs as 4 hex digits, an 'h' after them optional.
  std::vector<std::uint16_t> upids(const toml::table& t, std::string_view key) {
    std::vector<std::uint16_t> out;
    const toml::node* n = t.get(key);
    if (!n) return out;
    const toml::array* a = n->as_array();
    if (!a) {
      problem(n->source(),
              "'" + std::string(key) + "' must be an array of UPIDs, e.g. [\"1037h\"]");
      return out;
    }
    for (const auto& e : *a) {
      auto s = e.value<std::string>();
      std::optional<std::uint16_t> upid;
      if (s && e.is_string()) {
        std::string_view v = *s;
        if (!v.empty() && (v.back() == 'h' || v.back() == 'H')) v.remove_suffix(1);
        upid = config::detail::parse_upid_hex(v);
      }
      if (!upid) {
        problem(e.source(), "'" + std::string(key) + "': " +
                                (s && e.is_string() ? "'" + *s + "'" : std::string("a value")) +
                                " is not a UPID (4 hex digits, e.g. \"1037h\")");
        continue;
      }
      out.push_back(*upid);
    }
    return out;
  }

  // `on_replaced = "notify" | "restore"` (lmcfg serve: a factory-fresh drive
  // found at a position the archive holds a file for).
  std::optional<std::string> on_replaced(const toml::table& t) {
    auto s = string(t, "on_replaced", "", false);
    if (s && *s != "notify" && *s != "restore") {
      problem(t.get("on_replaced")->source(),
              "'on_replaced' must be \"notify\" or \"restore\", not '" + *s + "'");
      return std::nullopt;
    }
    return s;
  }

  std::optional<std::chrono::seconds> duration(const toml::table& t, std::string_view key) {
    const toml::node* n = t.get(key);
    if (!n) return std::nullopt;
    auto s = n->value<std::string>();
    if (!s || !n->is_string()) {
      problem(n->source(), "'" + std::string(key) + "' must be a string such as \"6h\"");
      return std::nullopt;
    }
    auto d = parse_duration(*s);
    if (!d.ok()) {
      problem(n->source(), "'" + std::string(key) + "': " + d.error().message);
      return std::nullopt;
    }
    return *d;
  }

 private:
  std::string file_;
  std::vector<std::string> problems_;
};

constexpr std::string_view kRootKeys[] = {"line", "schedule", "notify", "archive",
                                          "require_reason"};
constexpr std::string_view kScheduleKeys[] = {"backup_every", "status_every"};
constexpr std::string_view kNotifyKeys[] = {"webhook", "command"};
constexpr std::string_view kArchiveKeys[] = {"push"};
constexpr std::string_view kLineKeys[] = {"name",
                                          "port",
                                          "baud",
                                          "parity",
                                          "stop_bits",
                                          "checksum",
                                          "checksum_coverage",
                                          "timeout_ms",
                                          "retries",
                                          "settle_ms",
                                          "agreeing_reads",
                                          "ignore",
                                          "on_replaced",
                                          "drive"};
constexpr std::string_view kDriveKeys[] = {"name",   "id",          "labels",
                                           "ignore", "on_replaced", "family"};
// A line whose port is a CAN link: DeviceNet controllers (docs/devicenet.md),
// with the settings of the CLI's DeviceNet options of the same names.
constexpr std::string_view kDevicenetLineKeys[] = {
    "name",    "port",   "can_bitrate", "devicenet_own_macid", "devicenet_listen_ms", "timeout_ms",
    "retries", "ignore", "drive"};
constexpr std::string_view kDevicenetDriveKeys[] = {
    "name",   "devicenet_macid", "devicenet_motors", "io_modules", "no_module_values",
    "labels", "ignore"};
// The keys of one protocol only: on a line of the other, each is named as such.
constexpr std::string_view kLinrsOnlyLineKeys[] = {
    "baud", "parity", "stop_bits", "checksum", "checksum_coverage", "settle_ms", "agreeing_reads"};
constexpr std::string_view kDevicenetOnlyLineKeys[] = {"can_bitrate", "devicenet_own_macid",
                                                       "devicenet_listen_ms"};
constexpr std::string_view kLinrsOnlyDriveKeys[] = {"id", "family"};
constexpr std::string_view kDevicenetOnlyDriveKeys[] = {"devicenet_macid", "devicenet_motors",
                                                        "io_modules", "no_module_values"};

// "'baud' is a LinRS key, not for DeviceNet line 'can1' (port 'slcan:/dev/ttyACM0' is a CAN
// link)" for each key of `t` in `other` (the other protocol's keys).
void misplaced_keys(Checker& c, const toml::table& t, std::span<const std::string_view> other,
                    const LineEntry& line, const std::string& whose) {
  const std::string of_other = line.devicenet ? "a LinRS key" : "a DeviceNet key";
  const std::string here =
      line.devicenet ? "DeviceNet line '" + line.name + "' (port '" + line.port + "' is a CAN link)"
                     : "LinRS line '" + line.name +
                           "' (DeviceNet needs a CAN port: "
                           "slcan:DEVICE, slcan:tcp://HOST:PORT, can0)";
  for (auto&& [key, value] : t) {
    for (auto k : other) {
      if (key.str() != k) continue;
      c.problem(key.source(),
                whose + "'" + std::string(k) + "' is " + of_other + ", not for " + here);
    }
  }
}

// DeviceNet controllers: devicenet_macid (0..63), devicenet_motors ("A,B"),
// io_modules ("control-in,addressed-in,..."), no_module_values, checked by
// the parsers of the options of the same names.
void read_devicenet_drive(Checker& c, const toml::table& t, DriveEntry& d) {
  if (!t.get("devicenet_macid")) {
    c.problem(t.source(), "drive '" + d.name +
                              "' has no 'devicenet_macid' (the controller's MAC ID 0..63, e.g. "
                              "devicenet_macid = 5)");
  } else if (auto mac = c.integer(t, "devicenet_macid")) {
    if (*mac < 0 || *mac > 63) {
      c.problem(t.get("devicenet_macid")->source(), "drive '" + d.name + "': devicenet_macid " +
                                                        std::to_string(*mac) +
                                                        " is not a DeviceNet MAC ID 0..63");
    } else {
      d.id = static_cast<std::uint8_t>(*mac);
    }
  }
  if (auto motors = c.string(t, "devicenet_motors", "", false)) {
    auto selected = devicenet::parse_motor_list("devicenet_motors", *motors);
    if (!selected.ok()) {
      c.problem(t.get("devicenet_motors")->source(), selected.error().message);
    } else {
      std::vector<int> list;
      for (int m = 0; m < 4; ++m)
        if ((*selected)[static_cast<std::size_t>(m)]) list.push_back(m);
      d.devicenet_motors = list;
    }
  }
  if (auto modules = c.string(t, "io_modules", "", false)) {
    auto layout = devicenet::parse_modules(*modules);
    if (!layout.ok())
      c.problem(t.get("io_modules")->source(), layout.error().message);
    else
      d.io_modules = *layout;
  }
  if (const toml::node* n = t.get("no_module_values")) {
    if (!n->is_boolean())
      c.problem(n->source(), "'no_module_values' must be true or false");
    else
      d.module_values = !n->as_boolean()->get();
  }
}

void read_drive(Checker& c, const toml::table& t, LineEntry& line) {
  const std::string where = "drive of line '" + line.name + "'";
  const auto other = line.devicenet ? std::span<const std::string_view>(kLinrsOnlyDriveKeys)
                                    : std::span<const std::string_view>(kDevicenetOnlyDriveKeys);
  misplaced_keys(c, t, other, line, "drive '" + t["name"].value_or(std::string()) + "': ");
  c.known_keys(t,
               line.devicenet ? std::span<const std::string_view>(kDevicenetDriveKeys) : kDriveKeys,
               where, other);
  DriveEntry d;
  d.at = c.at(t.source());
  if (auto name = c.string(t, "name", where, true)) {
    if (auto ok = check_position_name(*name); !ok.ok()) {
      c.problem(t.get("name")->source(), ok.error().message);
    }
    d.name = *name;
  }
  const bool linudp =
      !line.port.empty() && link::scheme_of(line.port).protocol == link::Protocol::linudp;
  if (line.devicenet) {
    read_devicenet_drive(c, t, d);
  } else if (linudp) {
    // A LinUDP drive is addressed by its IP (LinUDP V2 §3.2): no MACID.
    if (t.get("id"))
      c.problem(t.get("id")->source(), "drive '" + d.name + "': a " + line.port +
                                           " line reaches its drive by address; remove 'id'");
  } else if (!t.get("id")) {
    c.problem(t.source(), "drive '" + d.name + "' has no 'id' (its MACID, e.g. id = 0x11)");
  } else if (auto id = c.integer(t, "id")) {
    if (*id < 0 || *id > 0xFF) {
      c.problem(t.get("id")->source(),
                "drive '" + d.name + "': id " + std::to_string(*id) + " is not a MACID 0..255");
    } else {
      d.id = static_cast<std::uint8_t>(*id);
    }
  }
  if (const toml::node* labels = t.get("labels")) {
    if (!labels->is_table()) {
      c.problem(labels->source(),
                "'labels' must be a table of strings, e.g. { machine = \"press3\" }");
    } else {
      for (auto&& [k, v] : *labels->as_table()) {
        if (!v.is_string()) {
          c.problem(v.source(), "label '" + std::string(k.str()) + "' must be a string");
          continue;
        }
        // Labels go into the archived file, pages and events: one line each.
        const std::string key(k.str());
        const std::string value = *v.value<std::string>();
        if (auto ok = check_line("label name '" + key + "'", key, kMaxLabelBytes); !ok.ok()) {
          c.problem(v.source(), ok.error().message);
          continue;
        }
        if (auto ok = check_line("label '" + key + "'", value, kMaxLabelBytes); !ok.ok()) {
          c.problem(v.source(), ok.error().message);
          continue;
        }
        d.labels[key] = value;
      }
    }
  }
  d.ignore = c.upids(t, "ignore");
  d.on_replaced = c.on_replaced(t);
  if (!line.devicenet) {
    if (auto fam = c.string(t, "family", where, false)) {
      auto f = families::parse(*fam, "drive '" + d.name + "'");
      if (f.ok())
        d.family = *f;
      else
        c.problem(t.get("family")->source(), f.error().message);
    }
  }
  line.drives.push_back(std::move(d));
}

void read_line(Checker& c, const toml::table& t, std::size_t index, Inventory& inv) {
  LineEntry line;
  line.at = c.at(t.source());
  const std::string fallback = "line " + std::to_string(index + 1);
  line.name = c.string(t, "name", fallback, true).value_or(fallback);
  if (t.get("name") && t.get("name")->is_string()) {
    if (auto ok = check_line_name(line.name); !ok.ok())
      c.problem(t.get("name")->source(), ok.error().message);
  }
  line.port = c.string(t, "port", "line '" + line.name + "'", true).value_or("");
  // The port's row in the table of port schemes says the protocol.
  line.devicenet = !line.port.empty() && link::is_can_port(line.port);
  const auto other = line.devicenet ? std::span<const std::string_view>(kLinrsOnlyLineKeys)
                                    : std::span<const std::string_view>(kDevicenetOnlyLineKeys);
  misplaced_keys(c, t, other, line, "");
  c.known_keys(t,
               line.devicenet ? std::span<const std::string_view>(kDevicenetLineKeys) : kLineKeys,
               "line '" + line.name + "'", other);
  line.baud = c.integer(t, "baud");
  line.stop_bits = c.integer(t, "stop_bits");
  line.timeout_ms = c.integer(t, "timeout_ms");
  line.retries = c.integer(t, "retries");
  line.settle_ms = c.integer(t, "settle_ms");
  line.agreeing_reads = c.integer(t, "agreeing_reads");
  line.can_bitrate = c.integer(t, "can_bitrate");
  line.devicenet_own_macid = c.integer(t, "devicenet_own_macid");
  line.devicenet_listen_ms = c.integer(t, "devicenet_listen_ms");
  line.parity = c.string(t, "parity", "", false);
  line.checksum = c.string(t, "checksum", "", false);
  line.checksum_coverage = c.string(t, "checksum_coverage", "", false);
  line.ignore = c.upids(t, "ignore");
  line.on_replaced = c.on_replaced(t);
  if (const toml::node* drives = t.get("drive")) {
    const toml::array* a = drives->as_array();
    if (!a || !a->is_array_of_tables()) {
      c.problem(drives->source(), "'drive' must be an array of tables ([[line.drive]])");
    } else {
      for (const auto& d : *a) read_drive(c, *d.as_table(), line);
    }
  }
  if (line.drives.empty()) {
    c.problem(t.source(), "line '" + line.name + "' has no drives ([[line.drive]])");
  } else if (line.drives.size() > 1 && !line.port.empty() &&
             link::scheme_of(line.port).protocol == link::Protocol::linudp) {
    c.problem(t.source(), "line '" + line.name +
                              "': a linudp:// port reaches one drive (its IP "
                              "address, LinUDP V2 §3.2); give each drive a line of its own");
  }
  inv.lines.push_back(std::move(line));
}

// [schedule], [notify] and [archive] (docs/serve.md).
void read_service_tables(Checker& c, const toml::table& root, Inventory& inv) {
  if (const toml::node* n = root.get("archive")) {
    if (!n->is_table()) {
      c.problem(n->source(), "'archive' must be a table ([archive])");
    } else {
      const toml::table& t = *n->as_table();
      c.known_keys(t, kArchiveKeys, "[archive]");
      if (auto push = c.string(t, "push", "[archive]", false)) {
        if (push->empty())
          c.problem(t.get("push")->source(),
                    "'push' must name a git remote (a remote's name, a URL or a path), not \"\"");
        inv.archive.push = *push;
      }
    }
  }
  if (const toml::node* n = root.get("require_reason")) {
    if (!n->is_boolean())
      c.problem(n->source(), "'require_reason' must be true or false");
    else
      inv.require_reason = n->as_boolean()->get();
  }
  if (const toml::node* n = root.get("schedule")) {
    if (!n->is_table()) {
      c.problem(n->source(), "'schedule' must be a table ([schedule])");
    } else {
      c.known_keys(*n->as_table(), kScheduleKeys, "[schedule]");
      inv.schedule.backup_every = c.duration(*n->as_table(), "backup_every");
      inv.schedule.status_every = c.duration(*n->as_table(), "status_every");
    }
  }
  if (const toml::node* n = root.get("notify")) {
    if (!n->is_table()) {
      c.problem(n->source(), "'notify' must be a table ([notify])");
      return;
    }
    const toml::table& t = *n->as_table();
    c.known_keys(t, kNotifyKeys, "[notify]");
    if (auto w = c.string(t, "webhook", "[notify]", false)) {
      if (w->rfind("http://", 0) != 0 && w->rfind("https://", 0) != 0)
        c.problem(t.get("webhook")->source(),
                  "'webhook' must be an http:// or https:// URL, not '" + *w + "'");
      inv.notify.webhook = *w;
    }
    if (auto cmd = c.string(t, "command", "[notify]", false)) {
      // Absolute as the platform has it: /usr/local/bin/x, or C:\lmcfg\x.cmd on Windows.
      if (cmd->empty() || !std::filesystem::path(*cmd).is_absolute())
        c.problem(t.get("command")->source(),
                  "'command' must be an absolute path to a program, not '" + *cmd + "'");
      inv.notify.command = *cmd;
    }
  }
}

// ASCII lower case: drive names are ASCII (check_position_name).
std::string folded(std::string s) {
  for (char& ch : s) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return s;
}

void check_unique(Checker& c, const Inventory& inv) {
  std::map<std::string, Position> line_names, drive_names;
  // By folded name: on a case-insensitive file system (a clone of the archive
  // on macOS or Windows) "Press3/Z.json" and "press3/z.json" are one file.
  std::map<std::string, const DriveEntry*> drive_folded;
  for (const auto& line : inv.lines) {
    if (auto [it, fresh] = line_names.emplace(line.name, line.at); !fresh) {
      c.problem(line.at,
                "duplicate line name '" + line.name + "' (first at " + it->second.str() + ")");
    }
    for (const auto& other : inv.lines) {
      if (&other == &line) break;
      if (other.name != line.name && iequals(other.name, line.name)) {
        c.problem(line.at, "line names '" + other.name + "' (" + other.at.str() + ") and '" +
                               line.name + "' differ only in case: rename one");
      }
    }
    std::map<std::uint8_t, const DriveEntry*> ids;
    for (const auto& d : line.drives) {
      if (d.name.empty()) continue;
      if (auto [it, fresh] = drive_names.emplace(d.name, d.at); !fresh) {
        c.problem(d.at, "duplicate drive name '" + d.name + "' at " + d.at.str() + " (first at " +
                            it->second.str() + ")");
      } else if (auto [f, first] = drive_folded.emplace(folded(d.name), &d); !first) {
        c.problem(d.at, "drive names '" + f->second->name + "' (" + f->second->at.str() +
                            ") and '" + d.name +
                            "' differ only in case: one file on a case-insensitive file "
                            "system; rename one");
      }
      if (auto [it, fresh] = ids.emplace(d.id, &d); !fresh) {
        c.problem(d.at, "line '" + line.name + "': drives '" + it->second->name + "' (" +
                            it->second->at.str() + ") and '" + d.name + "' (" + d.at.str() +
                            ") both have " + (line.devicenet ? "DeviceNet MAC ID " : "MACID ") +
                            hex(d.id, 2, "h"));
      }
    }
  }
}

}  // namespace

std::string Position::str() const {
  return file + ":" + std::to_string(line) + ":" + std::to_string(column);
}

std::size_t Inventory::drive_count() const {
  std::size_t n = 0;
  for (const auto& l : lines) n += l.drives.size();
  return n;
}

const DriveEntry* Inventory::find_drive(std::string_view name, const LineEntry** line) const {
  for (const auto& l : lines) {
    for (const auto& d : l.drives) {
      if (d.name != name) continue;
      if (line) *line = &l;
      return &d;
    }
  }
  return nullptr;
}

Result<std::chrono::seconds> parse_duration(std::string_view text) {
  const std::string expected =
      "'" + std::string(text) +
      "' is not a duration (a whole number > 0 and a unit s, m, h or d, e.g. \"15m\", \"6h\")";
  if (text.size() < 2) return Error(Errc::invalid_argument, expected);
  const auto digits = text.substr(0, text.size() - 1);
  if (digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string_view::npos)
    return Error(Errc::invalid_argument, expected);
  const std::int64_t n = std::stoll(std::string(digits));
  std::int64_t unit = 0;
  switch (text.back()) {
    case 's':
      unit = 1;
      break;
    case 'm':
      unit = 60;
      break;
    case 'h':
      unit = 3600;
      break;
    case 'd':
      unit = 86400;
      break;
    default:
      return Error(Errc::invalid_argument, expected);
  }
  if (n == 0) return Error(Errc::invalid_argument, expected);
  return std::chrono::seconds(n * unit);
}

bool restore_when_replaced(const LineEntry& line, const DriveEntry& d) {
  return d.on_replaced.value_or(line.on_replaced.value_or("notify")) == "restore";
}

std::vector<std::uint16_t> ignored_upids(const LineEntry& line, const DriveEntry& d) {
  std::vector<std::uint16_t> all = line.ignore;
  all.insert(all.end(), d.ignore.begin(), d.ignore.end());
  return all;
}

namespace {
// The tool's options with the line's keys over them.
link::LinkInput line_input(const LineEntry& line, link::LinkInput base) {
  base.port = line.port;
  auto set_int = [](const std::optional<std::int64_t>& v, auto& field) {
    if (v)
      field = static_cast<std::remove_reference_t<decltype(field)>>(
          std::clamp<std::int64_t>(*v, -1, 100'000'000));
  };
  set_int(line.baud, base.baud);
  set_int(line.stop_bits, base.stop_bits);
  set_int(line.timeout_ms, base.timeout_ms);
  set_int(line.retries, base.retries);
  set_int(line.settle_ms, base.settle_ms);
  if (line.agreeing_reads) base.agreeing_reads = std::to_string(*line.agreeing_reads);
  if (line.parity) base.parity = *line.parity;
  if (line.checksum) base.checksum = *line.checksum;
  if (line.checksum_coverage) base.checksum_coverage = *line.checksum_coverage;
  return base;
}
Error at_line(const LineEntry& line, const Error& e) {
  return Error(e.code, line.at.str() + ": line '" + line.name + "': " + e.message);
}
}  // namespace

Result<void> check_line_link(const LineEntry& line, link::LinkInput base) {
  if (auto c = link::check_link_settings(line_input(line, std::move(base))); !c.ok())
    return at_line(line, c.error());
  return {};
}

Result<link::LinkSpec> line_link_spec(const LineEntry& line, link::LinkInput base) {
  auto spec = link::make_link_spec(line_input(line, std::move(base)));
  if (!spec.ok()) return at_line(line, spec.error());
  return spec;
}

Result<void> check_ports(const Inventory& inv) {
  std::string problems;
  auto problem = [&](const LineEntry& l, const std::string& what) {
    problems += (problems.empty() ? "" : "\n") + l.at.str() + ": line '" + l.name + "': " + what;
  };
  for (const auto& l : inv.lines) {
    // The table of port schemes checks the form; its row says whether there
    // is something to find before the run (a device path).
    auto spec = link::parse_port(l.port);
    if (!spec.ok()) {
      problem(l, spec.error().message);
    } else if (spec->scheme->check_present) {
      if (auto present = spec->scheme->check_present(*spec); !present.ok())
        problem(l, present.error().message);
    }
  }
  if (!problems.empty()) return Error(Errc::validation_failed, problems);
  return {};
}

Result<Inventory> parse_inventory(std::string_view text, std::string path) {
  toml::table root;
  try {
    root = toml::parse(text, path);
  } catch (const toml::parse_error& e) {
    return Error(Errc::parse_error,
                 position_of(e.source(), path).str() + ": " + std::string(e.description()));
  }
  Checker c(path);
  Inventory inv;
  inv.path = path;
  c.known_keys(root, kRootKeys, "the inventory");
  read_service_tables(c, root, inv);  // and require_reason
  const toml::node* lines = root.get("line");
  const toml::array* a = lines ? lines->as_array() : nullptr;
  if (!lines) {
    return Error(Errc::validation_failed, path + ":1:1: the inventory has no lines ([[line]])");
  }
  if (!a || !a->is_array_of_tables()) {
    c.problem(lines->source(), "'line' must be an array of tables ([[line]])");
  } else {
    for (std::size_t i = 0; i < a->size(); ++i) read_line(c, *(*a)[i].as_table(), i, inv);
    if (c.problems().empty()) check_unique(c, inv);
  }
  if (!c.problems().empty()) {
    std::string all;
    for (const auto& p : c.problems()) all += (all.empty() ? "" : "\n") + p;
    return Error(Errc::validation_failed, all);
  }
  return inv;
}

Result<Inventory> load_inventory(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Error(Errc::file_error, path + ": cannot open the inventory");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) return Error(Errc::file_error, path + ": cannot read the inventory");
  return parse_inventory(text.str(), path);
}

Result<InventoryEdit> link_inventory_edit(const Inventory& inv, std::string_view drive,
                                          const LinkKeys& after) {
  const LineEntry* line = nullptr;
  const DriveEntry* d = inv.find_drive(drive, &line);
  if (!d)
    return Error(Errc::not_found,
                 inv.path + ": no drive is called '" + std::string(drive) + "' (--drive)");
  InventoryEdit out;
  const LinkKeys unset;  // what a key the line leaves out means: the option's default
  const std::string where = line->at.str() + ": [[line]] \"" + line->name + "\": ";
  std::vector<std::string> line_keys;
  auto num = [&](const char* key, const std::optional<std::int64_t>& now, std::int64_t def,
                 std::int64_t want) {
    if (now.value_or(def) != want)
      line_keys.push_back(std::string(key) + " = " + std::to_string(want));
  };
  auto str = [&](const char* key, const std::optional<std::string>& now, const std::string& def,
                 const std::string& want) {
    if (now.value_or(def) != want) line_keys.push_back(std::string(key) + " = \"" + want + "\"");
  };
  num("baud", line->baud, unset.baud, after.baud);
  str("parity", line->parity, unset.parity, after.parity);
  num("stop_bits", line->stop_bits, unset.stop_bits, after.stop_bits);
  // "crc" and "crc-ffff" are one checksum (--checksum).
  auto same_sum = [](std::string a, std::string b) {
    if (a == "crc") a = "crc-ffff";
    if (b == "crc") b = "crc-ffff";
    return a == b;
  };
  if (!same_sum(line->checksum.value_or(unset.checksum), after.checksum))
    line_keys.push_back("checksum = \"" + after.checksum + "\"");
  str("checksum_coverage", line->checksum_coverage, unset.checksum_coverage,
      after.checksum_coverage);
  for (const auto& k : line_keys) out.keys.push_back(where + k);
  if (d->id != after.id) {
    char id[8];
    std::snprintf(id, sizeof id, "0x%02X", after.id);
    out.keys.push_back(d->at.str() + ": [[line.drive]] \"" + d->name + "\": id = " + id);
  }
  if (!line_keys.empty() && line->drives.size() > 1) {
    std::string others;
    for (const auto& o : line->drives)
      if (&o != d) others += (others.empty() ? "" : ", ") + o.name;
    out.warnings.push_back("line \"" + line->name + "\" (" + line->at.str() + ") carries " +
                           std::to_string(line->drives.size()) +
                           " drives on one port that share its rate, parity, stop bits and "
                           "checksum: move the others (" +
                           others +
                           ") to the same settings with lmcfg link before changing the line's "
                           "keys, or the fleet commands reach only part of the line");
  }
  return out;
}

}  // namespace lmcfg::fleet
