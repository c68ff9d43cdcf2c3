#include "db/database.hpp"

#include <sqlite3.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <utility>

#include "common/layers.hpp"

namespace lmcfg::db {

namespace {

std::string lower(std::string_view s) {
  std::string r(s);
  for (auto& c : r) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return r;
}

// Minimal read-only statement wrapper. next() is true while there are rows;
// once it returns false, failed() tells an error from the end of the rows.
class Stmt {
 public:
  Stmt() = default;
  Stmt(sqlite3* db, const char* sql) {
    if (sqlite3_prepare_v2(db, sql, -1, &s_, nullptr) != SQLITE_OK) {
      sqlite3_finalize(s_);
      s_ = nullptr;
    }
  }
  ~Stmt() { sqlite3_finalize(s_); }
  Stmt(const Stmt&) = delete;
  Stmt& operator=(const Stmt&) = delete;
  Stmt(Stmt&& o) noexcept : s_(std::exchange(o.s_, nullptr)), rc_(o.rc_) {}
  Stmt& operator=(Stmt&& o) noexcept {
    std::swap(s_, o.s_);
    std::swap(rc_, o.rc_);
    return *this;
  }
  bool ok() const { return s_ != nullptr; }
  bool next() {
    rc_ = sqlite3_step(s_);
    return rc_ == SQLITE_ROW;
  }
  bool failed() const { return rc_ != SQLITE_ROW && rc_ != SQLITE_DONE; }
  // Ends the statement (and its read transaction) so it can run again.
  void reset() {
    sqlite3_reset(s_);
    rc_ = SQLITE_DONE;
  }
  void bind(int i, std::int64_t v) { sqlite3_bind_int64(s_, i, v); }

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
  int rc_ = SQLITE_DONE;
};

// "file:///abs/path?immutable=1", the path made absolute and %-escaped where
// a URI needs it.
std::string immutable_uri(const std::string& path) {
  std::error_code ec;
  std::string abs = std::filesystem::absolute(path, ec).string();
  if (ec) abs = path;
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

std::optional<TypeCode> opt_type(const Stmt& q, int i) {
  auto v = q.opt_i64(i);
  if (!v) return std::nullopt;
  return type_from_code(static_cast<unsigned>(*v));
}

// Columns read_parameter() expects, in this order.
#define LMCFG_PARAM_COLUMNS                                                                    \
  "id, upid, profiles, layer, name, path, type_code, address_usage, min, max, default_value, " \
  "unit, scale, comm, description, source, src_file, src_line"

Parameter read_parameter(const Stmt& q) {
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
  return p;
}

// The rows of one UPID, ordered by row id; empty = the UPID is absent.
struct UpidRows {
  std::vector<Parameter> rows;
};
const UpidRows kAbsent{};

struct ParamTable {
  std::vector<Parameter> rows;             // sorted by UPID, row id
  std::vector<std::string> search_keys;    // lower-case "name\npath\ndescription" per row
  std::array<std::size_t, kLayerCount> per_layer{};  // rows per layer
};
struct ErrorTable {
  std::vector<ErrorEntry> rows;  // sorted by domain, code (error() searches it)
};
bool error_before(const ErrorEntry& e, std::string_view domain, std::uint32_t code) {
  const int c = std::string_view(e.domain).compare(domain);
  return c < 0 || (c == 0 && e.code < code);
}
struct CommandTable {
  std::vector<MotionCommand> rows;  // sorted by header
  std::unordered_map<std::uint16_t, std::uint32_t> by_header;
};

// A value loaded at most once, on first use, and then published to readers
// without a lock. get() returns nullptr when the load failed; the next get()
// tries again.
template <class T>
class Lazy {
 public:
  template <class Load, class Fail>
  const T* get(std::mutex& mu, Load& load, Fail fail) {
    if (const T* p = ptr_.load(std::memory_order_acquire)) return p;
    return load_slow(mu, load, fail);
  }

 private:
  template <class Load, class Fail>
  [[gnu::noinline]] const T* load_slow(std::mutex& mu, Load& load, Fail& fail) {
    std::lock_guard<std::mutex> lock(mu);
    if (const T* p = ptr_.load(std::memory_order_relaxed)) return p;
    Result<T> r = load();
    if (!r) {
      fail(std::move(r).error());
      return nullptr;
    }
    owned_ = std::make_unique<T>(std::move(r).value());
    ptr_.store(owned_.get(), std::memory_order_release);
    return owned_.get();
  }

  std::atomic<const T*> ptr_{nullptr};
  std::unique_ptr<T> owned_;  // written once, under the mutex, before ptr_
};

template <class T>
const T& or_empty(const T* p) {
  if (p) return *p;
  static const T empty{};  // after a failed load
  return empty;
}

}  // namespace

struct Database::Impl {
  sqlite3* db = nullptr;
  DbInfo info;  // without counts; constant after open()

  std::mutex mu;  // guards db, the statements, last_error and every load
  std::optional<Error> last_error;
  Stmt upid_rows, upid_labels;  // prepared on the first UPID lookup

  // UPID cache: two levels of 256 slots, published with release stores and
  // read with acquire loads. A slot is nullptr (not looked up yet), &kAbsent,
  // or rows owned by the page.
  struct Page {
    std::array<std::atomic<const UpidRows*>, 256> slot{};
    std::array<std::unique_ptr<UpidRows>, 256> owned;  // under mu
  };
  std::array<std::atomic<Page*>, 256> pages{};
  std::array<std::unique_ptr<Page>, 256> page_owned;  // under mu

  Lazy<std::vector<Profile>> profiles;
  Lazy<ParamTable> params;
  Lazy<ErrorTable> errors;
  Lazy<CommandTable> commands;
  Lazy<std::vector<DevicenetParameter>> dn_params;
  Lazy<std::vector<DevicenetCommand>> dn_commands;
  Lazy<DbInfo> full_info;  // info plus counts

  Impl() = default;
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;
  ~Impl() {
    upid_rows = Stmt();
    upid_labels = Stmt();
    sqlite3_close_v2(db);
  }

  // Records a failed load (mu held). SQLite's page cache is emptied so that a
  // retry reads the file again instead of pages read while it was bad.
  void fail(Error e) {
    last_error = std::move(e);
    sqlite3_db_release_memory(db);
  }

  Error sql_error(const std::string& what) const {
    return Error(Errc::parse_error,
                 "UPID database " + info.path + ": " + what + ": " + sqlite3_errmsg(db));
  }

  const UpidRows* upid(std::uint16_t u) {
    if (const Page* p = pages[u >> 8].load(std::memory_order_acquire))
      if (const UpidRows* r = p->slot[u & 0xFF].load(std::memory_order_acquire)) return r;
    return load_upid(u);
  }
  const UpidRows* load_upid(std::uint16_t u);

  template <class T, class Load>
  const T* load_once(Lazy<T>& slot, Load load) {
    return slot.get(mu, load, [this](Error e) { fail(std::move(e)); });
  }
  const ParamTable& param_table() {
    return or_empty(load_once(params, [this] { return load_params(); }));
  }
  const ErrorTable& error_table() {
    return or_empty(load_once(errors, [this] { return load_errors(); }));
  }
  const CommandTable& command_table() {
    return or_empty(load_once(commands, [this] { return load_commands(); }));
  }
  const std::vector<Profile>& profile_table() {
    return or_empty(load_once(profiles, [this] { return load_profiles(); }));
  }
  const std::vector<DevicenetParameter>& dn_param_table() {
    return or_empty(load_once(dn_params, [this] { return load_dn_params(); }));
  }
  const std::vector<DevicenetCommand>& dn_command_table() {
    return or_empty(load_once(dn_commands, [this] { return load_dn_commands(); }));
  }
  // info with counts, or (until counting succeeds) info without.
  const DbInfo& full() {
    const DbInfo* p = load_once(full_info, [this] { return load_counts(); });
    return p ? *p : info;
  }

  // Loaders: called with mu held.
  Result<std::vector<Profile>> load_profiles();
  Result<ParamTable> load_params();
  Result<ErrorTable> load_errors();
  Result<CommandTable> load_commands();
  Result<std::vector<DevicenetParameter>> load_dn_params();
  Result<std::vector<DevicenetCommand>> load_dn_commands();
  Result<DbInfo> load_counts();
};

const UpidRows* Database::Impl::load_upid(std::uint16_t u) {
  std::lock_guard<std::mutex> lock(mu);
  Page* page = pages[u >> 8].load(std::memory_order_relaxed);
  if (page)
    if (const UpidRows* r = page->slot[u & 0xFF].load(std::memory_order_relaxed)) return r;
  if (!upid_rows.ok()) {
    upid_rows =
        Stmt(db, "SELECT " LMCFG_PARAM_COLUMNS " FROM parameters WHERE upid = ?1 ORDER BY id");
    if (!upid_rows.ok()) {
      fail(sql_error("parameters"));
      return nullptr;
    }
  }
  if (!upid_labels.ok()) {
    upid_labels =
        Stmt(db, "SELECT raw, label FROM enum_labels WHERE parameter_id = ?1 ORDER BY raw");
    if (!upid_labels.ok()) {
      fail(sql_error("enum_labels"));
      return nullptr;
    }
  }
  auto rows = std::make_unique<UpidRows>();
  std::vector<std::int64_t> ids;
  upid_rows.bind(1, u);
  while (upid_rows.next()) {
    ids.push_back(upid_rows.i64(0));
    rows->rows.push_back(read_parameter(upid_rows));
  }
  char what[32];
  std::snprintf(what, sizeof what, " of UPID %04Xh", static_cast<unsigned>(u));
  if (upid_rows.failed()) {
    Error e = sql_error(std::string("parameters") + what);
    upid_rows.reset();  // before fail(): a running statement keeps its pages
    fail(std::move(e));
    return nullptr;
  }
  upid_rows.reset();
  for (std::size_t i = 0; i < ids.size(); ++i) {
    upid_labels.bind(1, ids[i]);
    while (upid_labels.next())
      rows->rows[i].spec.labels.push_back({upid_labels.i64(0), upid_labels.text(1)});
    if (upid_labels.failed()) {
      Error e = sql_error(std::string("enum_labels") + what);
      upid_labels.reset();
      fail(std::move(e));
      return nullptr;
    }
    upid_labels.reset();
  }
  if (!page) {
    page_owned[u >> 8] = std::make_unique<Page>();
    page = page_owned[u >> 8].get();
    pages[u >> 8].store(page, std::memory_order_release);
  }
  const UpidRows* r = &kAbsent;
  if (!rows->rows.empty()) {
    r = rows.get();
    page->owned[u & 0xFF] = std::move(rows);
  }
  page->slot[u & 0xFF].store(r, std::memory_order_release);
  return r;
}

Result<std::vector<Profile>> Database::Impl::load_profiles() {
  std::vector<Profile> out;
  Stmt q(db,
         "SELECT profile, family, software, version, description, source, src_file, src_line "
         "FROM profiles ORDER BY profile");
  if (!q.ok()) return sql_error("profiles");
  while (q.next())
    out.push_back(Profile{q.text(0), q.text(1), q.text(2), q.text(3), q.text(4), q.prov(5)});
  if (q.failed()) return sql_error("profiles");
  return out;
}

Result<ParamTable> Database::Impl::load_params() {
  ParamTable t;
  std::unordered_map<std::int64_t, std::uint32_t> by_id;
  {
    Stmt q(db, "SELECT " LMCFG_PARAM_COLUMNS " FROM parameters ORDER BY upid, id");
    if (!q.ok()) return sql_error("parameters");
    while (q.next()) {
      by_id[q.i64(0)] = static_cast<std::uint32_t>(t.rows.size());
      t.rows.push_back(read_parameter(q));
    }
    if (q.failed()) return sql_error("parameters");
  }
  {
    Stmt q(db, "SELECT parameter_id, raw, label FROM enum_labels ORDER BY parameter_id, raw");
    if (!q.ok()) return sql_error("enum_labels");
    while (q.next()) {
      auto it = by_id.find(q.i64(0));
      if (it != by_id.end()) t.rows[it->second].spec.labels.push_back({q.i64(1), q.text(2)});
    }
    if (q.failed()) return sql_error("enum_labels");
  }
  t.search_keys.reserve(t.rows.size());
  for (const auto& p : t.rows) {
    t.search_keys.push_back(lower(p.name) + "\n" + lower(p.path) + "\n" + lower(p.description));
    ++t.per_layer[static_cast<std::size_t>(p.layer)];
  }
  return t;
}

Result<ErrorTable> Database::Impl::load_errors() {
  ErrorTable t;
  Stmt q(db,
         "SELECT domain, code, code_text, text, description, action, source, src_file, src_line, "
         "class FROM errors ORDER BY domain, code");
  if (!q.ok()) return sql_error("errors");
  while (q.next())
    t.rows.push_back(ErrorEntry{q.text(0), static_cast<std::uint32_t>(q.i64(1)), q.text(2),
                                q.text(3), q.text(4), q.text(5), q.prov(6), q.text(9)});
  if (q.failed()) return sql_error("errors");
  // SQLite's ORDER BY already is this order (BINARY collation); made certain
  // for the binary search.
  std::stable_sort(t.rows.begin(), t.rows.end(), [](const ErrorEntry& x, const ErrorEntry& y) {
    return error_before(x, y.domain, y.code);
  });
  return t;
}

Result<CommandTable> Database::Impl::load_commands() {
  CommandTable t;
  {
    Stmt q(db,
           "SELECT master, sub, name, products, description, source, src_file, src_line FROM "
           "motion_commands ORDER BY header");
    if (!q.ok()) return sql_error("motion_commands");
    while (q.next()) {
      MotionCommand c;
      c.master = static_cast<std::uint8_t>(q.i64(0));
      c.sub = static_cast<std::uint8_t>(q.i64(1));
      c.name = q.text(2);
      c.products = q.text(3);
      c.description = q.text(4);
      c.prov = q.prov(5);
      t.rows.push_back(std::move(c));
    }
    if (q.failed()) return sql_error("motion_commands");
  }
  for (std::uint32_t i = 0; i < t.rows.size(); ++i) t.by_header[t.rows[i].header()] = i;
  {
    Stmt q(db,
           "SELECT master, sub, idx, offset, name, type_code, unit, scale, source, src_file, "
           "src_line, range_text, min, max, scaled FROM motion_command_params "
           "ORDER BY master, sub, idx");
    if (!q.ok()) return sql_error("motion_command_params");
    while (q.next()) {
      auto h =
          motion_header(static_cast<std::uint8_t>(q.i64(0)), static_cast<std::uint8_t>(q.i64(1)));
      auto it = t.by_header.find(h);
      if (it == t.by_header.end()) continue;
      MotionParam p;
      p.index = static_cast<int>(q.i64(2));
      p.offset = static_cast<int>(q.i64(3));
      p.name = q.text(4);
      p.spec.type = opt_type(q, 5);
      p.spec.unit = q.text(6);
      p.spec.scale = q.opt_real(7);
      p.prov = q.prov(8);
      p.range_text = q.text(11);
      p.spec.min = q.opt_i64(12);
      p.spec.max = q.opt_i64(13);
      p.scaled = q.i64(14) != 0;
      t.rows[it->second].params.push_back(std::move(p));
    }
    if (q.failed()) return sql_error("motion_command_params");
  }
  return t;
}

Result<std::vector<DevicenetParameter>> Database::Impl::load_dn_params() {
  std::vector<DevicenetParameter> out;
  {
    Stmt q(db,
           "SELECT id, name, path, type_code, min, max, default_value, unit, scale, comm, "
           "description, source, src_file, src_line FROM devicenet_parameters ORDER BY seq");
    if (!q.ok()) return sql_error("devicenet_parameters");
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
      out.push_back(std::move(p));
    }
    if (q.failed()) return sql_error("devicenet_parameters");
  }
  {
    Stmt q(db,
           "SELECT parameter_id, raw, label FROM devicenet_parameter_labels ORDER BY "
           "parameter_id, raw");
    if (!q.ok()) return sql_error("devicenet_parameter_labels");
    while (q.next()) {
      const std::string id = q.text(0);
      for (auto& p : out)
        if (p.id == id) p.spec.labels.push_back({q.i64(1), q.text(2)});
    }
    if (q.failed()) return sql_error("devicenet_parameter_labels");
  }
  return out;
}

Result<std::vector<DevicenetCommand>> Database::Impl::load_dn_commands() {
  std::vector<DevicenetCommand> out;
  {
    Stmt q(db,
           "SELECT id, id_text, direction, name, table_name, range_text, min, max, unit, scale, "
           "unit_text, addressed, direct, description, source, src_file, src_line FROM "
           "devicenet_commands ORDER BY id");
    if (!q.ok()) return sql_error("devicenet_commands");
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
      out.push_back(std::move(c));
    }
    if (q.failed()) return sql_error("devicenet_commands");
  }
  {
    Stmt q(db,
           "SELECT command_id, raw, label FROM devicenet_command_labels ORDER BY command_id, raw");
    if (!q.ok()) return sql_error("devicenet_command_labels");
    while (q.next()) {
      for (auto& c : out)
        if (c.id == q.i64(0)) c.spec.labels.push_back({q.i64(1), q.text(2)});
    }
    if (q.failed()) return sql_error("devicenet_command_labels");
  }
  return out;
}

// Rows per table, counted as the former load-everything open() counted them:
// enum labels of existing parameters, parameters of existing commands.
Result<DbInfo> Database::Impl::load_counts() {
  static constexpr const char* kTables[] = {"profiles",
                                            "parameters",
                                            "enum_labels",
                                            "errors",
                                            "motion_commands",
                                            "motion_command_params",
                                            "devicenet_parameters",
                                            "devicenet_commands"};
  Stmt q(db,
         "SELECT (SELECT count(*) FROM profiles), (SELECT count(*) FROM parameters), "
         "(SELECT count(*) FROM enum_labels WHERE parameter_id IN (SELECT id FROM parameters)), "
         "(SELECT count(*) FROM errors), (SELECT count(*) FROM motion_commands), "
         "(SELECT count(*) FROM motion_command_params mp WHERE EXISTS (SELECT 1 FROM "
         "motion_commands c WHERE c.master = mp.master AND c.sub = mp.sub)), "
         "(SELECT count(*) FROM devicenet_parameters), (SELECT count(*) FROM devicenet_commands)");
  if (!q.ok()) return sql_error("counting rows");
  if (!q.next()) return sql_error("counting rows");
  DbInfo full = info;
  for (int i = 0; i < 8; ++i) full.counts[kTables[i]] = static_cast<std::size_t>(q.i64(i));
  return full;
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
  std::error_code ec;
  auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec)
    return Error(Errc::file_error, "cannot locate the running executable via /proc/self/exe (" +
                                       ec.message() + "); set " + std::string(kDbPathEnv) +
                                       " or pass --db");
  return find_default_path(nullptr, exe.parent_path());
}

Result<Database> Database::open_default() {
  LMCFG_ASSIGN_OR_RETURN(auto path, default_path());
  return open(path);
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
  auto impl = std::make_unique<Impl>();
  // One connection per Database, used only under Impl::mu: no SQLite mutexes.
  // immutable=1: nothing writes the file while it is open (the compiler replaces
  // it by rename), so SQLite takes no file locks and does not look for a
  // journal or for changes before every read.
  int rc = sqlite3_open_v2(immutable_uri(path).c_str(), &impl->db,
                           SQLITE_OPEN_READONLY | SQLITE_OPEN_NOMUTEX | SQLITE_OPEN_URI, nullptr);
  sqlite3* raw = impl->db;
  if (rc != SQLITE_OK)
    return Error(Errc::file_error, "cannot open UPID database " + path + ": " +
                                       (raw ? sqlite3_errmsg(raw) : "out of memory"));
  DbInfo& info = impl->info;
  info.path = path;
  {
    Stmt q(raw, "SELECT key, value FROM meta");
    if (!q.ok())
      return Error(Errc::parse_error,
                   "UPID database " + path +
                       ": not a UPID database (no meta table): " + sqlite3_errmsg(raw));
    while (q.next()) {
      std::string k = q.text(0);
      if (k == "schema_version")
        info.schema_version = std::atoi(q.text(1).c_str());
      else if (k == "content_hash")
        info.content_hash = q.text(1);
      else if (k == "built_from")
        info.built_from = q.text(1);
    }
  }
  if (info.schema_version != kSchemaVersion)
    return Error(Errc::unsupported_version,
                 "UPID database " + path + " has schema version " +
                     std::to_string(info.schema_version) + ", this program reads version " +
                     std::to_string(kSchemaVersion) + " (rebuild the database)");
  return Database(std::move(impl));
}

const Parameter* Database::find(std::uint16_t upid, std::string_view profile) const {
  if (!impl_) return nullptr;
  const UpidRows* r = impl_->upid(upid);
  if (!r) return nullptr;
  for (const auto& p : r->rows)
    if (p.applies_to(profile)) return &p;
  return nullptr;
}

std::vector<const Parameter*> Database::find_all(std::uint16_t upid) const {
  std::vector<const Parameter*> out;
  if (!impl_) return out;
  if (const UpidRows* r = impl_->upid(upid))
    for (const auto& p : r->rows) out.push_back(&p);
  return out;
}

const std::vector<Parameter>& Database::parameters() const {
  static const std::vector<Parameter> none;
  return impl_ ? impl_->param_table().rows : none;
}

std::vector<const Parameter*> Database::search(std::string_view needle) const {
  std::vector<const Parameter*> out;
  if (!impl_) return out;
  const ParamTable& t = impl_->param_table();
  std::string n = lower(needle);
  if (n.find('\n') != std::string::npos) return out;
  for (std::size_t i = 0; i < t.rows.size(); ++i)
    if (t.search_keys[i].find(n) != std::string::npos) out.push_back(&t.rows[i]);
  return out;
}

std::vector<const Parameter*> Database::in_layer(Layer layer) const {
  std::vector<const Parameter*> out;
  if (!impl_) return out;
  const ParamTable& t = impl_->param_table();
  out.reserve(t.per_layer[static_cast<std::size_t>(layer)]);
  for (const auto& p : t.rows)
    if (p.layer == layer) out.push_back(&p);
  return out;
}

const std::vector<ErrorEntry>& Database::all_errors() const {
  static const std::vector<ErrorEntry> none;
  return impl_ ? impl_->error_table().rows : none;
}

const ErrorEntry* Database::error(std::string_view domain, std::uint32_t code) const {
  if (!impl_) return nullptr;
  const ErrorTable& t = impl_->error_table();
  const std::string d = lower(domain);
  auto it =
      std::lower_bound(t.rows.begin(), t.rows.end(), code,
                       [&](const ErrorEntry& e, std::uint32_t c) { return error_before(e, d, c); });
  return it != t.rows.end() && it->domain == d && it->code == code ? &*it : nullptr;
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
  return impl_ ? impl_->command_table().rows : none;
}

const MotionCommand* Database::motion_command(std::uint16_t header) const {
  if (!impl_) return nullptr;
  const CommandTable& t = impl_->command_table();
  auto it = t.by_header.find(static_cast<std::uint16_t>(header & 0xFFF0u));
  return it == t.by_header.end() ? nullptr : &t.rows[it->second];
}

const std::vector<Profile>& Database::profiles() const {
  static const std::vector<Profile> none;
  return impl_ ? impl_->profile_table() : none;
}

const Profile* Database::profile(std::string_view id) const {
  for (const auto& p : profiles())
    if (p.id == id) return &p;
  return nullptr;
}

const std::vector<DevicenetParameter>& Database::devicenet_parameters() const {
  static const std::vector<DevicenetParameter> none;
  return impl_ ? impl_->dn_param_table() : none;
}

const std::vector<DevicenetCommand>& Database::devicenet_commands() const {
  static const std::vector<DevicenetCommand> none;
  return impl_ ? impl_->dn_command_table() : none;
}

const DevicenetCommand* Database::devicenet_command(std::uint8_t id) const {
  const auto& v = devicenet_commands();
  auto it = std::lower_bound(v.begin(), v.end(), id,
                             [](const DevicenetCommand& c, std::uint8_t x) { return c.id < x; });
  return it != v.end() && it->id == id ? &*it : nullptr;
}

const DbInfo& Database::info() const {
  static const DbInfo none;
  return impl_ ? impl_->full() : none;
}

std::optional<Error> Database::last_error() const {
  if (!impl_) return std::nullopt;
  std::lock_guard<std::mutex> lock(impl_->mu);
  return impl_->last_error;
}

}  // namespace lmcfg::db
