#include "fleet/inventory.hpp"

#include <toml++/toml.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <span>
#include <sstream>

#include "common/bytes.hpp"
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
  void known_keys(const toml::table& t, std::span<const std::string_view> allowed,
                  std::string_view where) {
    for (auto&& [key, value] : t) {
      bool ok = false;
      for (auto a : allowed) ok = ok || key.str() == a;
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

 private:
  std::string file_;
  std::vector<std::string> problems_;
};

constexpr std::string_view kRootKeys[] = {"line"};
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
                                          "drive"};
constexpr std::string_view kDriveKeys[] = {"name", "id", "labels"};

void read_drive(Checker& c, const toml::table& t, LineEntry& line) {
  const std::string where = "drive of line '" + line.name + "'";
  c.known_keys(t, kDriveKeys, where);
  DriveEntry d;
  d.at = c.at(t.source());
  if (auto name = c.string(t, "name", where, true)) {
    if (auto ok = check_position_name(*name); !ok.ok()) {
      c.problem(t.get("name")->source(), ok.error().message);
    }
    d.name = *name;
  }
  if (!t.get("id")) {
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
        d.labels[std::string(k.str())] = *v.value<std::string>();
      }
    }
  }
  line.drives.push_back(std::move(d));
}

void read_line(Checker& c, const toml::table& t, std::size_t index, Inventory& inv) {
  LineEntry line;
  line.at = c.at(t.source());
  const std::string fallback = "line " + std::to_string(index + 1);
  line.name = c.string(t, "name", fallback, true).value_or(fallback);
  c.known_keys(t, kLineKeys, "line '" + line.name + "'");
  line.port = c.string(t, "port", "line '" + line.name + "'", true).value_or("");
  line.baud = c.integer(t, "baud");
  line.stop_bits = c.integer(t, "stop_bits");
  line.timeout_ms = c.integer(t, "timeout_ms");
  line.retries = c.integer(t, "retries");
  line.settle_ms = c.integer(t, "settle_ms");
  line.agreeing_reads = c.integer(t, "agreeing_reads");
  line.parity = c.string(t, "parity", "", false);
  line.checksum = c.string(t, "checksum", "", false);
  line.checksum_coverage = c.string(t, "checksum_coverage", "", false);
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
  }
  inv.lines.push_back(std::move(line));
}

void check_unique(Checker& c, const Inventory& inv) {
  std::map<std::string, Position> line_names, drive_names;
  for (const auto& line : inv.lines) {
    if (auto [it, fresh] = line_names.emplace(line.name, line.at); !fresh) {
      c.problem(line.at,
                "duplicate line name '" + line.name + "' (first at " + it->second.str() + ")");
    }
    std::map<std::uint8_t, const DriveEntry*> ids;
    for (const auto& d : line.drives) {
      if (d.name.empty()) continue;
      if (auto [it, fresh] = drive_names.emplace(d.name, d.at); !fresh) {
        c.problem(d.at, "duplicate drive name '" + d.name + "' at " + d.at.str() + " (first at " +
                            it->second.str() + ")");
      }
      if (auto [it, fresh] = ids.emplace(d.id, &d); !fresh) {
        c.problem(d.at, "line '" + line.name + "': drives '" + it->second->name + "' (" +
                            it->second->at.str() + ") and '" + d.name + "' (" + d.at.str() +
                            ") both have MACID " + hex(d.id, 2, "h"));
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

Result<void> check_position_name(std::string_view name) {
  const std::string quoted = "drive name '" + std::string(name) + "'";
  if (name.empty()) return Error(Errc::invalid_argument, "drive name is empty");
  std::size_t start = 0;
  while (start <= name.size()) {
    const auto slash = name.find('/', start);
    const auto seg =
        name.substr(start, slash == std::string_view::npos ? name.npos : slash - start);
    if (seg.empty() || seg == "." || seg == "..") {
      return Error(Errc::invalid_argument,
                   quoted + " must be path segments separated by '/', none empty, '.' or '..'");
    }
    for (char ch : seg) {
      const bool ok = (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') ||
                      (ch >= '0' && ch <= '9') || ch == '.' || ch == '_' || ch == '-';
      if (!ok) {
        return Error(Errc::invalid_argument, quoted + " contains '" + std::string(1, ch) +
                                                 "' (allowed: letters, digits, . _ - and /)");
      }
    }
    if (slash == std::string_view::npos) break;
    start = slash + 1;
  }
  return {};
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
    } else if (spec->kind() != link::Kind::byte_link) {
      problem(l, "port '" + l.port +
                     "' is a CAN link (DeviceNet controllers); a fleet line is a LinRS line");
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

}  // namespace lmcfg::fleet
