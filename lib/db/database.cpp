#include "db/database.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <unordered_map>
#include <utility>

#include "common/executable.hpp"
#include "common/layers.hpp"
#include "db/sqlite.hpp"

namespace lmcfg::db {

namespace {

using sqlite::Statement;

std::string lower(std::string_view s) {
  std::string r(s);
  for (auto& c : r) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return r;
}

// "file:///abs/path?immutable=1", the path made absolute and %-escaped where
// a URI needs it.
std::string immutable_uri(const std::string& path) {
  std::error_code ec;
  std::string abs = std::filesystem::absolute(path, ec).generic_string();
  if (ec) abs = path;
  // A Windows path "C:/x" is the URI path "/C:/x" (SQLite, "URI Filenames").
  if (abs.size() > 1 && abs[1] == ':') abs.insert(0, "/");
  std::string uri = "file://";
  for (char c : abs) {
    if (c == '%' || c == '?' || c == '#') {
      static constexpr char kHex[] = "0123456789abcdef";
      const auto u = static_cast<unsigned char>(c);
      uri += '%';
      uri += kHex[u >> 4];
      uri += kHex[u & 0x0F];
    } else {
      uri += c;
    }
  }
  return uri + "?immutable=1";
}

std::optional<TypeCode> opt_type(const Statement& q, int i) {
  auto v = q.column_opt_int(i);
  if (!v) return std::nullopt;
  return type_from_code(static_cast<unsigned>(*v));
}

// Rows are read in storage order (a plain scan: ordering by an index would
// cost one table lookup per row) and sorted here.
void sort_labels(std::vector<EnumLabel>& labels) {
  std::stable_sort(labels.begin(), labels.end(),
                   [](const EnumLabel& a, const EnumLabel& b) { return a.raw < b.raw; });
}

bool error_before(const ErrorEntry& e, std::string_view domain, std::uint32_t code) {
  const int c = std::string_view(e.domain).compare(domain);
  return c < 0 || (c == 0 && e.code < code);
}

}  // namespace

// Every table, read once by open(); nothing changes afterwards, so any number
// of threads may read it.
struct Database::Impl {
  DbInfo info;
  std::vector<Profile> profiles;         // by id
  bool has_reference = false;            // a profile kReferenceProfile exists
  std::vector<Parameter> params;         // sorted by UPID, row id
  std::vector<std::uint16_t> upids;      // params[i].upid, for the binary search
  std::vector<std::string> search_keys;  // lower-case "name\npath\ndescription" per row
  std::array<std::size_t, kLayerCount> per_layer{};
  std::vector<ErrorEntry> errors;       // sorted by domain, code
  std::vector<MotionCommand> commands;  // sorted by header
  std::unordered_map<std::uint16_t, std::size_t> command_of_header;
  std::vector<DevicenetParameter> dn_params;  // seed order
  std::vector<DevicenetCommand> dn_commands;  // by id

  // Loaders, run by open() on the open connection.
  Result<void> load(sqlite3* db);
  Result<void> load_profiles(sqlite3* db);
  Result<void> load_params(sqlite3* db);
  Result<void> load_errors(sqlite3* db);
  Result<void> load_commands(sqlite3* db);
  Result<void> load_dn_params(sqlite3* db);
  Result<void> load_dn_commands(sqlite3* db);
  Error sql_error(sqlite3* db, const std::string& what) const {
    return Error(Errc::parse_error,
                 "UPID database " + info.path + ": " + what + ": " + sqlite3_errmsg(db));
  }
};

Result<void> Database::Impl::load(sqlite3* db) {
  LMCFG_TRY(load_profiles(db));
  LMCFG_TRY(load_params(db));
  LMCFG_TRY(load_errors(db));
  LMCFG_TRY(load_commands(db));
  LMCFG_TRY(load_dn_params(db));
  LMCFG_TRY(load_dn_commands(db));
  // Rows per table as loaded: enum labels of existing parameters, parameters
  // of existing commands.
  std::size_t labels = 0, command_params = 0;
  for (const auto& p : params) labels += p.spec.labels.size();
  for (const auto& c : commands) command_params += c.params.size();
  info.counts = {{"profiles", profiles.size()},
                 {"parameters", params.size()},
                 {"enum_labels", labels},
                 {"errors", errors.size()},
                 {"motion_commands", commands.size()},
                 {"motion_command_params", command_params},
                 {"devicenet_parameters", dn_params.size()},
                 {"devicenet_commands", dn_commands.size()}};
  return {};
}

Result<void> Database::Impl::load_profiles(sqlite3* db) {
  Statement q(db,
              "SELECT profile, family, software, version, description, source, src_file, "
              "src_line FROM profiles");
  if (!q.ok()) return sql_error(db, "profiles");
  while (q.next())
    profiles.push_back(Profile{q.column_text(0), q.column_text(1), q.column_text(2),
                               q.column_text(3), q.column_text(4), q.column_prov(5)});
  if (q.failed()) return sql_error(db, "profiles");
  std::sort(profiles.begin(), profiles.end(),
            [](const Profile& a, const Profile& b) { return a.id < b.id; });
  has_reference = std::any_of(profiles.begin(), profiles.end(),
                              [](const Profile& p) { return p.id == kReferenceProfile; });
  return {};
}

Result<void> Database::Impl::load_params(sqlite3* db) {
  std::unordered_map<std::int64_t, std::size_t> index_of_id;
  {
    Statement q(db,
                "SELECT id, upid, profiles, layer, name, path, type_code, address_usage, min, "
                "max, default_value, unit, scale, comm, description, source, src_file, src_line "
                "FROM parameters");
    if (!q.ok()) return sql_error(db, "parameters");
    while (q.next()) {
      Parameter p;
      p.upid = static_cast<std::uint16_t>(q.column_int(1));
      const std::string list = q.column_text(2);
      if (list != "*") {
        std::size_t start = 0;
        while (start <= list.size()) {
          std::size_t comma = list.find(',', start);
          if (comma == std::string::npos) comma = list.size();
          p.profiles.push_back(list.substr(start, comma - start));
          start = comma + 1;
        }
      }
      p.layer = layer_from_name(q.column_text(3)).value_or(Layer::OS);
      p.name = q.column_text(4);
      p.path = q.column_text(5);
      p.spec.type = opt_type(q, 6);
      if (auto au = q.column_opt_int(7))
        p.address_usage = AddressUsage{static_cast<std::uint16_t>(*au)};
      p.spec.min = q.column_opt_int(8);
      p.spec.max = q.column_opt_int(9);
      p.default_value = q.column_opt_int(10);
      p.spec.unit = q.column_text(11);
      p.spec.scale = q.column_opt_real(12);
      p.comm = q.column_int(13) != 0;
      p.description = q.column_text(14);
      p.prov = q.column_prov(15);
      index_of_id[q.column_int(0)] = params.size();
      params.push_back(std::move(p));
    }
    if (q.failed()) return sql_error(db, "parameters");
  }
  {
    Statement q(db, "SELECT parameter_id, raw, label FROM enum_labels");
    if (!q.ok()) return sql_error(db, "enum_labels");
    while (q.next()) {
      auto it = index_of_id.find(q.column_int(0));
      if (it != index_of_id.end())
        params[it->second].spec.labels.push_back({q.column_int(1), q.column_text(2)});
    }
    if (q.failed()) return sql_error(db, "enum_labels");
  }
  // Row id order (the scan's) within a UPID.
  std::stable_sort(params.begin(), params.end(),
                   [](const Parameter& a, const Parameter& b) { return a.upid < b.upid; });
  upids.reserve(params.size());
  search_keys.reserve(params.size());
  for (auto& p : params) {
    sort_labels(p.spec.labels);
    upids.push_back(p.upid);
    search_keys.push_back(lower(p.name) + "\n" + lower(p.path) + "\n" + lower(p.description));
    ++per_layer[static_cast<std::size_t>(p.layer)];
  }
  return {};
}

Result<void> Database::Impl::load_errors(sqlite3* db) {
  Statement q(db,
              "SELECT domain, code, code_text, text, description, action, source, src_file, "
              "src_line, class FROM errors");
  if (!q.ok()) return sql_error(db, "errors");
  while (q.next())
    errors.push_back(ErrorEntry{q.column_text(0), static_cast<std::uint32_t>(q.column_int(1)),
                                q.column_text(2), q.column_text(3), q.column_text(4),
                                q.column_text(5), q.column_prov(6), q.column_text(9)});
  if (q.failed()) return sql_error(db, "errors");
  // By domain (byte order, as SQLite's BINARY collation), code.
  std::stable_sort(errors.begin(), errors.end(), [](const ErrorEntry& x, const ErrorEntry& y) {
    return error_before(x, y.domain, y.code);
  });
  return {};
}

Result<void> Database::Impl::load_commands(sqlite3* db) {
  {
    Statement q(db,
                "SELECT master, sub, name, products, description, source, src_file, src_line "
                "FROM motion_commands");
    if (!q.ok()) return sql_error(db, "motion_commands");
    while (q.next()) {
      MotionCommand c;
      c.master = static_cast<std::uint8_t>(q.column_int(0));
      c.sub = static_cast<std::uint8_t>(q.column_int(1));
      c.name = q.column_text(2);
      c.products = q.column_text(3);
      c.description = q.column_text(4);
      c.prov = q.column_prov(5);
      commands.push_back(std::move(c));
    }
    if (q.failed()) return sql_error(db, "motion_commands");
  }
  std::sort(commands.begin(), commands.end(),
            [](const MotionCommand& a, const MotionCommand& b) { return a.header() < b.header(); });
  for (std::size_t i = 0; i < commands.size(); ++i) command_of_header[commands[i].header()] = i;
  Statement q(db,
              "SELECT master, sub, idx, offset, name, type_code, unit, scale, source, src_file, "
              "src_line, range_text, min, max, scaled FROM motion_command_params");
  if (!q.ok()) return sql_error(db, "motion_command_params");
  while (q.next()) {
    auto it = command_of_header.find(motion_header(static_cast<std::uint8_t>(q.column_int(0)),
                                                   static_cast<std::uint8_t>(q.column_int(1))));
    if (it == command_of_header.end()) continue;
    MotionParam p;
    p.index = static_cast<int>(q.column_int(2));
    p.offset = static_cast<int>(q.column_int(3));
    p.name = q.column_text(4);
    p.spec.type = opt_type(q, 5);
    p.spec.unit = q.column_text(6);
    p.spec.scale = q.column_opt_real(7);
    p.prov = q.column_prov(8);
    p.range_text = q.column_text(11);
    p.spec.min = q.column_opt_int(12);
    p.spec.max = q.column_opt_int(13);
    p.scaled = q.column_int(14) != 0;
    commands[it->second].params.push_back(std::move(p));
  }
  if (q.failed()) return sql_error(db, "motion_command_params");
  for (auto& c : commands)
    std::sort(c.params.begin(), c.params.end(),
              [](const MotionParam& a, const MotionParam& b) { return a.index < b.index; });
  return {};
}

Result<void> Database::Impl::load_dn_params(sqlite3* db) {
  {
    Statement q(db,
                "SELECT id, name, path, type_code, min, max, default_value, unit, scale, comm, "
                "description, source, src_file, src_line FROM devicenet_parameters ORDER BY seq");
    if (!q.ok()) return sql_error(db, "devicenet_parameters");
    while (q.next()) {
      DevicenetParameter p;
      p.id = q.column_text(0);
      p.name = q.column_text(1);
      p.path = q.column_text(2);
      p.spec.type = opt_type(q, 3);
      p.spec.min = q.column_opt_int(4);
      p.spec.max = q.column_opt_int(5);
      p.default_value = q.column_opt_int(6);
      p.spec.unit = q.column_text(7);
      p.spec.scale = q.column_opt_real(8);
      p.comm = q.column_int(9) != 0;
      p.description = q.column_text(10);
      p.prov = q.column_prov(11);
      dn_params.push_back(std::move(p));
    }
    if (q.failed()) return sql_error(db, "devicenet_parameters");
  }
  Statement q(db, "SELECT parameter_id, raw, label FROM devicenet_parameter_labels");
  if (!q.ok()) return sql_error(db, "devicenet_parameter_labels");
  while (q.next()) {
    const std::string id = q.column_text(0);
    for (auto& p : dn_params)
      if (p.id == id) p.spec.labels.push_back({q.column_int(1), q.column_text(2)});
  }
  if (q.failed()) return sql_error(db, "devicenet_parameter_labels");
  for (auto& p : dn_params) sort_labels(p.spec.labels);
  return {};
}

Result<void> Database::Impl::load_dn_commands(sqlite3* db) {
  {
    Statement q(db,
                "SELECT id, id_text, direction, name, table_name, range_text, min, max, unit, "
                "scale, unit_text, addressed, direct, description, source, src_file, src_line "
                "FROM devicenet_commands ORDER BY id");
    if (!q.ok()) return sql_error(db, "devicenet_commands");
    while (q.next()) {
      DevicenetCommand c;
      c.id = static_cast<std::uint8_t>(q.column_int(0));
      c.id_text = q.column_text(1);
      c.direction = q.column_text(2);
      c.name = q.column_text(3);
      c.table_name = q.column_text(4);
      c.range_text = q.column_text(5);
      c.spec.min = q.column_opt_int(6);
      c.spec.max = q.column_opt_int(7);
      c.spec.unit = q.column_text(8);
      c.spec.scale = q.column_opt_real(9);
      c.unit_text = q.column_text(10);
      c.addressed = q.column_int(11) != 0;
      c.direct = q.column_int(12) != 0;
      c.description = q.column_text(13);
      c.prov = q.column_prov(14);
      dn_commands.push_back(std::move(c));
    }
    if (q.failed()) return sql_error(db, "devicenet_commands");
  }
  Statement q(db, "SELECT command_id, raw, label FROM devicenet_command_labels");
  if (!q.ok()) return sql_error(db, "devicenet_command_labels");
  while (q.next()) {
    const std::int64_t id = q.column_int(0);
    for (auto& c : dn_commands)
      if (c.id == id) c.spec.labels.push_back({q.column_int(1), q.column_text(2)});
  }
  if (q.failed()) return sql_error(db, "devicenet_command_labels");
  for (auto& c : dn_commands) sort_labels(c.spec.labels);
  return {};
}

// db::Layer is the 0-based view of the layer numbers 1..4 of common/layers.hpp,
// plus Other for the UPIDs between the ranges.
std::string_view layer_name(Layer l) noexcept {
  if (l == Layer::Other) return "Other";
  return layers::name(static_cast<int>(l) + 1);
}

std::optional<Layer> layer_from_name(std::string_view name) noexcept {
  auto n = layers::from_name(name);
  if (!n) {
    if (lower(name) == "other") return Layer::Other;
    return std::nullopt;
  }
  return static_cast<Layer>(*n - 1);
}

std::optional<Layer> layer_of_upid(std::uint16_t upid) noexcept {
  const int n = layers::of_upid(upid);
  if (n == 0) return std::nullopt;
  return static_cast<Layer>(n - 1);
}

std::uint16_t layer_base_upid(Layer l) noexcept {
  if (l == Layer::Other) return 0xFFFF;
  return layers::base_upid(static_cast<int>(l) + 1);
}

bool Parameter::applies_to(std::string_view profile) const {
  if (profiles.empty() || profile.empty()) return true;
  return std::find(profiles.begin(), profiles.end(), profile) != profiles.end();
}

Result<std::string> Database::find_default_path(const char* env_value,
                                                const std::filesystem::path& exe_dir) {
  const std::string env_name(kDbPathEnv);
  if (env_value && *env_value) return std::string(env_value);
  const std::string file(kDefaultDbFileName);
  const std::pair<std::filesystem::path, const char*> places[] = {
      {exe_dir / file, "next to the program"},
      {(exe_dir / ".." / "share" / "lmcfg" / file).lexically_normal(),
       "../share/lmcfg/ relative to the program"},
  };
  std::string looked = "$" + env_name + " (not set)";
  for (const auto& [path, what] : places) {
    std::error_code ec;
    if (std::filesystem::is_regular_file(path, ec)) return path.string();
    looked += ", " + path.string() + " (" + what + ")";
  }
  return Error(Errc::file_error, "UPID database not found; looked in: " + looked + "; expected " +
                                     file + " in one of them (pass --db PATH or set " + env_name +
                                     ")");
}

Result<std::string> Database::default_path() {
  const char* env = std::getenv(std::string(kDbPathEnv).c_str());
  if (env && *env) return find_default_path(env, {});
  auto exe = running_executable();
  if (!exe.ok())
    return Error(Errc::file_error,
                 exe.error().message + "; set " + std::string(kDbPathEnv) + " or pass --db");
  return find_default_path(nullptr, exe->parent_path());
}

Result<Database> Database::open_default() {
  LMCFG_ASSIGN_OR_RETURN(auto path, default_path());
  return open(path);
}

Database::Database() noexcept = default;

const Database& Database::empty() noexcept {
  static const Database none;
  return none;
}

Database::Database(std::unique_ptr<Impl> impl) noexcept : impl_(std::move(impl)) {}
Database::Database(Database&&) noexcept = default;
Database& Database::operator=(Database&&) noexcept = default;
Database::~Database() = default;

Result<Database> Database::open(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    return Error(Errc::file_error, "UPID database " + path +
                                       " not found (expected the file built from upid-db/; set " +
                                       std::string(kDbPathEnv) + " or pass --db)");
  // immutable=1: nothing writes the file while it is read (the compiler
  // replaces it by rename), so SQLite takes no file locks and does not look
  // for a journal. The connection lives only as long as open() runs.
  sqlite::Connection conn;
  if (!conn.open(immutable_uri(path), SQLITE_OPEN_READONLY | SQLITE_OPEN_NOMUTEX | SQLITE_OPEN_URI))
    return Error(Errc::file_error, "cannot open UPID database " + path + ": " + conn.error());
  sqlite3* raw = conn.get();
  auto impl = std::make_unique<Impl>();
  DbInfo& info = impl->info;
  info.path = path;
  {
    Statement q(raw, "SELECT key, value FROM meta");
    if (!q.ok())
      return Error(Errc::parse_error,
                   "UPID database " + path +
                       ": not a UPID database (no meta table): " + sqlite3_errmsg(raw));
    while (q.next()) {
      std::string k = q.column_text(0);
      if (k == "schema_version")
        info.schema_version = std::atoi(q.column_text(1).c_str());
      else if (k == "content_hash")
        info.content_hash = q.column_text(1);
      else if (k == "built_from")
        info.built_from = q.column_text(1);
    }
  }
  if (info.schema_version != kSchemaVersion)
    return Error(Errc::unsupported_version,
                 "UPID database " + path + " has schema version " +
                     std::to_string(info.schema_version) + ", this program reads version " +
                     std::to_string(kSchemaVersion) + " (rebuild the database)");
  LMCFG_TRY(impl->load(raw));
  return Database(std::move(impl));
}

const Parameter* Database::find(std::uint16_t upid, std::string_view profile) const {
  if (!impl_) return nullptr;
  // A database without the reference profile (one built from a drive's scan,
  // a test's) has no other family's rows to keep apart: its first row serves.
  if (profile.empty() && impl_->has_reference) profile = kReferenceProfile;
  const auto& u = impl_->upids;
  for (auto i = std::lower_bound(u.begin(), u.end(), upid); i != u.end() && *i == upid; ++i) {
    const Parameter& p = impl_->params[static_cast<std::size_t>(i - u.begin())];
    if (p.applies_to(profile)) return &p;
  }
  return nullptr;
}

std::vector<const Parameter*> Database::find_all(std::uint16_t upid) const {
  std::vector<const Parameter*> out;
  if (!impl_) return out;
  const auto& u = impl_->upids;
  for (auto i = std::lower_bound(u.begin(), u.end(), upid); i != u.end() && *i == upid; ++i)
    out.push_back(&impl_->params[static_cast<std::size_t>(i - u.begin())]);
  return out;
}

const std::vector<Parameter>& Database::parameters() const {
  static const std::vector<Parameter> none;
  return impl_ ? impl_->params : none;
}

std::vector<const Parameter*> Database::search(std::string_view needle) const {
  std::vector<const Parameter*> out;
  if (!impl_) return out;
  std::string n = lower(needle);
  if (n.find('\n') != std::string::npos) return out;
  for (std::size_t i = 0; i < impl_->params.size(); ++i)
    if (impl_->search_keys[i].find(n) != std::string::npos) out.push_back(&impl_->params[i]);
  return out;
}

std::vector<const Parameter*> Database::in_layer(Layer layer) const {
  std::vector<const Parameter*> out;
  if (!impl_) return out;
  out.reserve(impl_->per_layer[static_cast<std::size_t>(layer)]);
  for (const auto& p : impl_->params)
    if (p.layer == layer) out.push_back(&p);
  return out;
}

const std::vector<ErrorEntry>& Database::all_errors() const {
  static const std::vector<ErrorEntry> none;
  return impl_ ? impl_->errors : none;
}

const ErrorEntry* Database::error(std::string_view domain, std::uint32_t code) const {
  const auto& v = all_errors();
  const std::string d = lower(domain);
  auto it = std::lower_bound(v.begin(), v.end(), code, [&](const ErrorEntry& e, std::uint32_t c) {
    return error_before(e, d, c);
  });
  return it != v.end() && it->domain == d && it->code == code ? &*it : nullptr;
}

std::vector<const ErrorEntry*> Database::errors(std::string_view domain) const {
  std::string d = lower(domain);
  std::vector<const ErrorEntry*> out;
  for (const auto& e : all_errors())
    if (d.empty() || e.domain == d) out.push_back(&e);
  return out;
}

const std::vector<MotionCommand>& Database::motion_commands() const {
  static const std::vector<MotionCommand> none;
  return impl_ ? impl_->commands : none;
}

const MotionCommand* Database::motion_command(std::uint16_t header) const {
  if (!impl_) return nullptr;
  auto it = impl_->command_of_header.find(static_cast<std::uint16_t>(header & 0xFFF0u));
  return it == impl_->command_of_header.end() ? nullptr : &impl_->commands[it->second];
}

const std::vector<Profile>& Database::profiles() const {
  static const std::vector<Profile> none;
  return impl_ ? impl_->profiles : none;
}

const Profile* Database::profile(std::string_view id) const {
  for (const auto& p : profiles())
    if (p.id == id) return &p;
  return nullptr;
}

const std::vector<DevicenetParameter>& Database::devicenet_parameters() const {
  static const std::vector<DevicenetParameter> none;
  return impl_ ? impl_->dn_params : none;
}

const std::vector<DevicenetCommand>& Database::devicenet_commands() const {
  static const std::vector<DevicenetCommand> none;
  return impl_ ? impl_->dn_commands : none;
}

const DevicenetCommand* Database::devicenet_command(std::uint8_t id) const {
  const auto& v = devicenet_commands();
  auto it = std::lower_bound(v.begin(), v.end(), id,
                             [](const DevicenetCommand& c, std::uint8_t x) { return c.id < x; });
  return it != v.end() && it->id == id ? &*it : nullptr;
}

const DbInfo& Database::info() const {
  static const DbInfo none;
  return impl_ ? impl_->info : none;
}

std::optional<Error> Database::last_error() const { return std::nullopt; }

}  // namespace lmcfg::db
