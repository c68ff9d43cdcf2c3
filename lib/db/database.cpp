#include "db/database.hpp"

#include <sqlite3.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>

#include "common/layers.hpp"

namespace lmcfg::db {

namespace {

std::string lower(std::string_view s) {
  std::string r(s);
  for (auto& c : r) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return r;
}

// Minimal read-only statement wrapper.
class Query {
 public:
  Query(sqlite3* db, const char* sql) {
    ok_ = sqlite3_prepare_v2(db, sql, -1, &s_, nullptr) == SQLITE_OK;
  }
  ~Query() { sqlite3_finalize(s_); }
  Query(const Query&) = delete;
  Query& operator=(const Query&) = delete;
  bool ok() const { return ok_; }
  bool next() { return sqlite3_step(s_) == SQLITE_ROW; }
  std::string text(int i) const {
    auto* p = sqlite3_column_text(s_, i);
    return p ? std::string(reinterpret_cast<const char*>(p),
                           static_cast<std::size_t>(sqlite3_column_bytes(s_, i)))
             : std::string();
  }
  bool null(int i) const { return sqlite3_column_type(s_, i) == SQLITE_NULL; }
  std::int64_t i64(int i) const { return sqlite3_column_int64(s_, i); }
  std::optional<std::int64_t> opt_i64(int i) const {
    if (null(i)) return std::nullopt;
    return i64(i);
  }
  std::optional<double> opt_real(int i) const {
    if (null(i)) return std::nullopt;
    return sqlite3_column_double(s_, i);
  }
  Provenance prov(int first) const {
    return Provenance{text(first), text(first + 1), static_cast<int>(i64(first + 2))};
  }

 private:
  sqlite3_stmt* s_ = nullptr;
  bool ok_ = false;
};

std::optional<TypeCode> opt_type(const Query& q, int i) {
  auto v = q.opt_i64(i);
  if (!v) return std::nullopt;
  return type_from_code(static_cast<unsigned>(*v));
}

}  // namespace

// db::Layer is the 0-based view of the layer numbers 1..4 of common/layers.hpp.
std::string_view layer_name(Layer l) noexcept { return layers::name(static_cast<int>(l) + 1); }

std::optional<Layer> layer_from_name(std::string_view name) noexcept {
  auto n = layers::from_name(name);
  if (!n) return std::nullopt;
  return static_cast<Layer>(*n - 1);
}

std::optional<Layer> layer_of_upid(std::uint16_t upid) noexcept {
  const int n = layers::of_upid(upid);
  if (n == 0) return std::nullopt;
  return static_cast<Layer>(n - 1);
}

std::uint16_t layer_base_upid(Layer l) noexcept {
  return layers::base_upid(static_cast<int>(l) + 1);
}

bool Parameter::applies_to(std::string_view profile) const {
  if (profiles.empty() || profile.empty()) return true;
  return std::find(profiles.begin(), profiles.end(), profile) != profiles.end();
}

Result<std::string> Database::default_path() {
  if (const char* env = std::getenv(std::string(kDbPathEnv).c_str()); env && *env)
    return std::string(env);
  std::error_code ec;
  auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec)
    return Error(Errc::file_error, "cannot locate the running executable via /proc/self/exe (" +
                                       ec.message() + "); set " + std::string(kDbPathEnv) +
                                       " or pass --db");
  return (exe.parent_path() / std::string(kDefaultDbFileName)).string();
}

Result<Database> Database::open_default() {
  LMCFG_ASSIGN_OR_RETURN(auto path, default_path());
  return open(path);
}

Result<Database> Database::open(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    return Error(Errc::file_error, "UPID database " + path +
                                       " not found (expected the file built from upid-db/; set " +
                                       std::string(kDbPathEnv) + " or pass --db)");
  sqlite3* raw = nullptr;
  int rc = sqlite3_open_v2(path.c_str(), &raw, SQLITE_OPEN_READONLY, nullptr);
  struct Closer {
    sqlite3* d;
    ~Closer() { sqlite3_close(d); }
  } closer{raw};
  if (rc != SQLITE_OK)
    return Error(Errc::file_error, "cannot open UPID database " + path + ": " +
                                       (raw ? sqlite3_errmsg(raw) : "out of memory"));
  auto bad = [&](const std::string& what) {
    return Error(Errc::parse_error,
                 "UPID database " + path + ": " + what + ": " + sqlite3_errmsg(raw));
  };

  Database d;
  d.info_.path = path;
  {
    Query q(raw, "SELECT key, value FROM meta");
    if (!q.ok()) return bad("not a UPID database (no meta table)");
    while (q.next()) {
      std::string k = q.text(0);
      if (k == "schema_version")
        d.info_.schema_version = std::atoi(q.text(1).c_str());
      else if (k == "content_hash")
        d.info_.content_hash = q.text(1);
      else if (k == "built_from")
        d.info_.built_from = q.text(1);
    }
  }
  if (d.info_.schema_version != kSchemaVersion)
    return Error(Errc::unsupported_version,
                 "UPID database " + path + " has schema version " +
                     std::to_string(d.info_.schema_version) + ", this program reads version " +
                     std::to_string(kSchemaVersion) + " (rebuild the database)");
  {
    Query q(raw,
            "SELECT profile, family, software, version, description, source, src_file, src_line "
            "FROM profiles ORDER BY profile");
    if (!q.ok()) return bad("profiles");
    while (q.next())
      d.profiles_.push_back(
          Profile{q.text(0), q.text(1), q.text(2), q.text(3), q.text(4), q.prov(5)});
  }
  std::unordered_map<std::int64_t, std::uint32_t> by_id;
  {
    Query q(
        raw,
        "SELECT id, upid, profiles, layer, name, path, type_code, address_usage, min, max, "
        "default_value, unit, "
        "scale, comm, description, source, src_file, src_line FROM parameters ORDER BY upid, id");
    if (!q.ok()) return bad("parameters");
    while (q.next()) {
      Parameter p;
      p.upid = static_cast<std::uint16_t>(q.i64(1));
      std::string profiles = q.text(2);
      if (profiles != "*") {
        std::size_t start = 0;
        while (start <= profiles.size()) {
          std::size_t comma = profiles.find(',', start);
          if (comma == std::string::npos) comma = profiles.size();
          p.profiles.push_back(profiles.substr(start, comma - start));
          start = comma + 1;
        }
      }
      p.layer = layer_from_name(q.text(3)).value_or(Layer::OS);
      p.name = q.text(4);
      p.path = q.text(5);
      p.spec.type = opt_type(q, 6);
      if (auto au = q.opt_i64(7)) p.address_usage = AddressUsage{static_cast<std::uint16_t>(*au)};
      p.spec.min = q.opt_i64(8);
      p.spec.max = q.opt_i64(9);
      p.default_value = q.opt_i64(10);
      p.spec.unit = q.text(11);
      p.spec.scale = q.opt_real(12);
      p.comm = q.i64(13) != 0;
      p.description = q.text(14);
      p.prov = q.prov(15);
      by_id[q.i64(0)] = static_cast<std::uint32_t>(d.params_.size());
      d.params_.push_back(std::move(p));
    }
  }
  {
    Query q(raw, "SELECT parameter_id, raw, label FROM enum_labels ORDER BY parameter_id, raw");
    if (!q.ok()) return bad("enum_labels");
    while (q.next()) {
      auto it = by_id.find(q.i64(0));
      if (it != by_id.end()) d.params_[it->second].spec.labels.push_back({q.i64(1), q.text(2)});
    }
  }
  {
    Query q(raw,
            "SELECT domain, code, code_text, text, description, action, source, src_file, src_line "
            "FROM errors ORDER BY domain, code");
    if (!q.ok()) return bad("errors");
    while (q.next()) {
      d.errors_.push_back(ErrorEntry{q.text(0), static_cast<std::uint32_t>(q.i64(1)), q.text(2),
                                     q.text(3), q.text(4), q.text(5), q.prov(6)});
    }
  }
  {
    Query q(raw,
            "SELECT master, sub, name, products, description, source, src_file, src_line FROM "
            "motion_commands ORDER BY header");
    if (!q.ok()) return bad("motion_commands");
    while (q.next()) {
      MotionCommand c;
      c.master = static_cast<std::uint8_t>(q.i64(0));
      c.sub = static_cast<std::uint8_t>(q.i64(1));
      c.name = q.text(2);
      c.products = q.text(3);
      c.description = q.text(4);
      c.prov = q.prov(5);
      d.commands_.push_back(std::move(c));
    }
  }
  for (std::uint32_t i = 0; i < d.commands_.size(); ++i) d.by_header_[d.commands_[i].header()] = i;
  {
    Query q(
        raw,
        "SELECT master, sub, idx, offset, name, type_code, unit, scale, source, src_file, src_line "
        "FROM motion_command_params ORDER BY master, sub, idx");
    if (!q.ok()) return bad("motion_command_params");
    while (q.next()) {
      auto h =
          motion_header(static_cast<std::uint8_t>(q.i64(0)), static_cast<std::uint8_t>(q.i64(1)));
      auto it = d.by_header_.find(h);
      if (it == d.by_header_.end()) continue;
      MotionParam p;
      p.index = static_cast<int>(q.i64(2));
      p.offset = static_cast<int>(q.i64(3));
      p.name = q.text(4);
      p.spec.type = opt_type(q, 5);
      p.spec.unit = q.text(6);
      p.spec.scale = q.opt_real(7);
      p.prov = q.prov(8);
      d.commands_[it->second].params.push_back(std::move(p));
    }
  }

  {
    Query q(raw,
            "SELECT id, name, path, type_code, min, max, default_value, unit, scale, comm, "
            "description, source, src_file, "
            "src_line FROM devicenet_parameters ORDER BY seq");
    if (!q.ok()) return bad("devicenet_parameters");
    while (q.next()) {
      DevicenetParameter p;
      p.id = q.text(0);
      p.name = q.text(1);
      p.path = q.text(2);
      p.spec.type = opt_type(q, 3);
      p.spec.min = q.opt_i64(4);
      p.spec.max = q.opt_i64(5);
      p.default_value = q.opt_i64(6);
      p.spec.unit = q.text(7);
      p.spec.scale = q.opt_real(8);
      p.comm = q.i64(9) != 0;
      p.description = q.text(10);
      p.prov = q.prov(11);
      d.dn_params_.push_back(std::move(p));
    }
  }
  {
    Query q(raw,
            "SELECT parameter_id, raw, label FROM devicenet_parameter_labels ORDER BY "
            "parameter_id, raw");
    if (!q.ok()) return bad("devicenet_parameter_labels");
    while (q.next()) {
      for (auto& p : d.dn_params_)
        if (p.id == q.text(0)) p.spec.labels.push_back({q.i64(1), q.text(2)});
    }
  }
  {
    Query q(raw,
            "SELECT id, id_text, direction, name, table_name, range_text, min, max, unit, scale, "
            "unit_text, addressed, "
            "direct, description, source, src_file, src_line FROM devicenet_commands ORDER BY id");
    if (!q.ok()) return bad("devicenet_commands");
    while (q.next()) {
      DevicenetCommand c;
      c.id = static_cast<std::uint8_t>(q.i64(0));
      c.id_text = q.text(1);
      c.direction = q.text(2);
      c.name = q.text(3);
      c.table_name = q.text(4);
      c.range_text = q.text(5);
      c.spec.min = q.opt_i64(6);
      c.spec.max = q.opt_i64(7);
      c.spec.unit = q.text(8);
      c.spec.scale = q.opt_real(9);
      c.unit_text = q.text(10);
      c.addressed = q.i64(11) != 0;
      c.direct = q.i64(12) != 0;
      c.description = q.text(13);
      c.prov = q.prov(14);
      d.dn_commands_.push_back(std::move(c));
    }
  }
  {
    Query q(raw,
            "SELECT command_id, raw, label FROM devicenet_command_labels ORDER BY command_id, raw");
    if (!q.ok()) return bad("devicenet_command_labels");
    while (q.next()) {
      for (auto& c : d.dn_commands_)
        if (c.id == q.i64(0)) c.spec.labels.push_back({q.i64(1), q.text(2)});
    }
  }
  for (std::uint32_t i = 0; i < d.params_.size(); ++i) {
    d.by_upid_[d.params_[i].upid].push_back(i);
    d.search_keys_.push_back(lower(d.params_[i].name) + "\n" + lower(d.params_[i].path));
  }
  for (std::uint32_t i = 0; i < d.errors_.size(); ++i)
    d.by_error_[{d.errors_[i].domain, d.errors_[i].code}] = i;

  std::size_t nlabels = 0, ncparams = 0;
  for (const auto& p : d.params_) nlabels += p.spec.labels.size();
  for (const auto& c : d.commands_) ncparams += c.params.size();
  d.info_.counts = {{"profiles", d.profiles_.size()},
                    {"parameters", d.params_.size()},
                    {"enum_labels", nlabels},
                    {"errors", d.errors_.size()},
                    {"motion_commands", d.commands_.size()},
                    {"motion_command_params", ncparams},
                    {"devicenet_parameters", d.dn_params_.size()},
                    {"devicenet_commands", d.dn_commands_.size()}};
  return d;
}

const Parameter* Database::find(std::uint16_t upid, std::string_view profile) const {
  auto it = by_upid_.find(upid);
  if (it == by_upid_.end()) return nullptr;
  for (auto i : it->second)
    if (params_[i].applies_to(profile)) return &params_[i];
  return nullptr;
}

std::vector<const Parameter*> Database::find_all(std::uint16_t upid) const {
  std::vector<const Parameter*> out;
  if (auto it = by_upid_.find(upid); it != by_upid_.end())
    for (auto i : it->second) out.push_back(&params_[i]);
  return out;
}

std::vector<const Parameter*> Database::search(std::string_view needle) const {
  std::string n = lower(needle);
  std::vector<const Parameter*> out;
  for (std::size_t i = 0; i < params_.size(); ++i)
    if (search_keys_[i].find(n) != std::string::npos && (n.find('\n') == std::string::npos))
      out.push_back(&params_[i]);
  return out;
}

std::vector<const Parameter*> Database::in_layer(Layer layer) const {
  std::vector<const Parameter*> out;
  for (const auto& p : params_)
    if (p.layer == layer) out.push_back(&p);
  return out;
}

const ErrorEntry* Database::error(std::string_view domain, std::uint32_t code) const {
  auto it = by_error_.find(std::make_pair(lower(domain), code));
  return it == by_error_.end() ? nullptr : &errors_[it->second];
}

std::vector<const ErrorEntry*> Database::errors(std::string_view domain) const {
  std::string d = lower(domain);
  std::vector<const ErrorEntry*> out;
  for (const auto& e : errors_)
    if (d.empty() || e.domain == d) out.push_back(&e);
  return out;
}

const MotionCommand* Database::motion_command(std::uint16_t header) const {
  auto it = by_header_.find(static_cast<std::uint16_t>(header & 0xFFF0u));
  return it == by_header_.end() ? nullptr : &commands_[it->second];
}

const Profile* Database::profile(std::string_view id) const {
  for (const auto& p : profiles_)
    if (p.id == id) return &p;
  return nullptr;
}

const DevicenetCommand* Database::devicenet_command(std::uint8_t id) const {
  auto it = std::lower_bound(dn_commands_.begin(), dn_commands_.end(), id,
                             [](const DevicenetCommand& c, std::uint8_t v) { return c.id < v; });
  return it != dn_commands_.end() && it->id == id ? &*it : nullptr;
}

}  // namespace lmcfg::db
