// The SQLite writer of the UPID database compiler (schema: lib/db/schema.hpp,
// docs/upid-db.md).
#include <optional>

#include "common/bytes.hpp"
#include "db/compiler_model.hpp"
#include "db/schema.hpp"
#include "db/sqlite.hpp"

namespace lmcfg::db::compiler {

namespace {

std::optional<std::int64_t> opt_bit(const std::optional<AddressUsage>& au, unsigned bit) {
  if (!au) return std::nullopt;
  return (au->raw >> bit) & 1u;
}

using sqlite::Statement;

// One prepared INSERT per table.
struct Statements {
  explicit Statements(sqlite3* db)
      : meta(db, "INSERT INTO meta(key, value) VALUES(?, ?)"),
        prof(db, "INSERT INTO profiles VALUES(?,?,?,?,?,?,?,?)"),
        par(db,
            "INSERT INTO parameters(id, upid, upid_hex, profiles, layer, name, path, "
            "type_code, type, address_usage, ram_read, ram_write, rom_read, rom_write, "
            "no_hash, min, max, default_value, unit, scale, comm, description, source, "
            "src_file, src_line) "
            "VALUES(?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?)"),
        lab(db, "INSERT INTO enum_labels VALUES(?,?,?,?,?,?)"),
        err(db, "INSERT INTO errors VALUES(?,?,?,?,?,?,?,?,?,?)"),
        cmd(db, "INSERT INTO motion_commands VALUES(?,?,?,?,?,?,?,?,?)"),
        cpar(db, "INSERT INTO motion_command_params VALUES(?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?)"),
        dnp(db, "INSERT INTO devicenet_parameters VALUES(?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?)"),
        dnpl(db, "INSERT INTO devicenet_parameter_labels VALUES(?,?,?,?,?,?)"),
        dnc(db, "INSERT INTO devicenet_commands VALUES(?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?)"),
        dncl(db, "INSERT INTO devicenet_command_labels VALUES(?,?,?,?,?,?)") {}
  bool ok() const {
    for (const Statement* s :
         {&meta, &prof, &par, &lab, &err, &cmd, &cpar, &dnp, &dnpl, &dnc, &dncl})
      if (!s->ok()) return false;
    return true;
  }
  Statement meta, prof, par, lab, err, cmd, cpar, dnp, dnpl, dnc, dncl;
};

// parameters and their enum labels; returns the failing table's name, or empty.
std::string insert_parameters(Statements& st, const Model& m) {
  std::int64_t id = 0;
  for (const auto& p : m.params) {
    ++id;
    std::string profiles;
    for (const auto& s : p.profiles) profiles += (profiles.empty() ? "" : ",") + s;
    if (profiles.empty()) profiles = "*";
    std::optional<std::int64_t> tc;
    std::string tn;
    if (p.spec.type) {
      tc = static_cast<std::int64_t>(*p.spec.type);
      tn = std::string(type_name(*p.spec.type));
    }
    std::optional<std::int64_t> au;
    if (p.address_usage) au = p.address_usage->raw;
    Statement& b = st.par;
    b.integer(id)
        .integer(p.upid)
        .text(hex(p.upid, 4))
        .text(profiles)
        .text(std::string(layer_name(p.layer)))
        .text(p.name)
        .text(p.path)
        .integer(tc)
        .text(tn)
        .integer(au);
    b.integer(opt_bit(p.address_usage, 0))
        .integer(opt_bit(p.address_usage, 1))
        .integer(opt_bit(p.address_usage, 2))
        .integer(opt_bit(p.address_usage, 3))
        .integer(opt_bit(p.address_usage, 12));
    b.integer(p.spec.min)
        .integer(p.spec.max)
        .integer(p.default_value)
        .text(p.spec.unit)
        .real(p.spec.scale)
        .integer(p.comm ? 1 : 0)
        .text(p.description)
        .prov(p.prov);
    if (!b.insert()) return "parameters";
    for (const auto& l : p.spec.labels)
      if (!st.lab.integer(id).integer(l.raw).text(l.label).prov(p.prov).insert())
        return "enum_labels";
  }
  return {};
}

// errors
std::string insert_errors(Statements& st, const Model& m) {
  for (const auto& e : m.errors)
    if (!st.err.text(e.domain)
             .integer(e.code)
             .text(e.code_text)
             .text(e.text)
             .text(e.description)
             .text(e.action)
             .text(e.error_class)
             .prov(e.prov)
             .insert())
      return "errors";
  return {};
}

// motion commands and their parameters
std::string insert_commands(Statements& st, const Model& m) {
  for (const auto& c : m.commands) {
    if (!st.cmd.integer(c.master)
             .integer(c.sub)
             .integer(c.header())
             .text(c.name)
             .text(c.products)
             .text(c.description)
             .prov(c.prov)
             .insert())
      return "motion_commands";
    for (const auto& p : c.params) {
      std::optional<std::int64_t> tc;
      if (p.spec.type) tc = static_cast<std::int64_t>(*p.spec.type);
      if (!st.cpar.integer(c.master)
               .integer(c.sub)
               .integer(p.index)
               .integer(p.offset)
               .text(p.name)
               .integer(tc)
               .text(p.spec.type ? std::string(type_name(*p.spec.type)) : std::string())
               .text(p.spec.unit)
               .real(p.spec.scale)
               .text(p.range_text)
               .integer(p.spec.min)
               .integer(p.spec.max)
               .integer(p.scaled ? 1 : 0)
               .prov(p.prov)
               .insert())
        return "motion_command_params";
    }
  }
  return {};
}

// DeviceNet parameters and commands, with their labels
std::string insert_devicenet(Statements& st, const Model& m) {
  const std::string dn_profile(kDevicenetProfile);
  auto type_code_of = [](const ValueSpec& s) -> std::optional<std::int64_t> {
    if (!s.type) return std::nullopt;
    return static_cast<std::int64_t>(*s.type);
  };
  auto type_text_of = [](const ValueSpec& s) {
    return s.type ? std::string(type_name(*s.type)) : std::string();
  };
  std::int64_t seq = 0;
  for (const auto& p : m.dn_params) {
    if (!st.dnp.integer(++seq)
             .text(p.id)
             .text(dn_profile)
             .text(p.name)
             .text(p.path)
             .integer(type_code_of(p.spec))
             .text(type_text_of(p.spec))
             .integer(p.spec.min)
             .integer(p.spec.max)
             .integer(p.default_value)
             .text(p.spec.unit)
             .real(p.spec.scale)
             .integer(p.comm ? 1 : 0)
             .text(p.description)
             .prov(p.prov)
             .insert())
      return "devicenet_parameters";
    for (const auto& l : p.spec.labels)
      if (!st.dnpl.text(p.id).integer(l.raw).text(l.label).prov(p.prov).insert())
        return "devicenet_parameter_labels";
  }
  for (const auto& c : m.dn_commands) {
    if (!st.dnc.integer(c.id)
             .text(c.id_text)
             .text(dn_profile)
             .text(c.direction)
             .text(c.name)
             .text(c.table_name)
             .text(c.range_text)
             .integer(c.spec.min)
             .integer(c.spec.max)
             .text(c.spec.unit)
             .real(c.spec.scale)
             .text(c.unit_text)
             .integer(c.addressed ? 1 : 0)
             .integer(c.direct ? 1 : 0)
             .text(c.description)
             .prov(c.prov)
             .insert())
      return "devicenet_commands";
    for (const auto& l : c.spec.labels)
      if (!st.dncl.integer(c.id).integer(l.raw).text(l.label).prov(c.prov).insert())
        return "devicenet_command_labels";
  }
  return {};
}

// The rows of every table; returns the failing table's name, or empty.
std::string insert_rows(sqlite3* db, const Model& m, const std::string& hash,
                        const std::string& built_from, std::string& error) {
  Statements st(db);
  if (!st.ok()) {
    error = sqlite3_errmsg(db);
    return "prepare";
  }
  auto add_meta = [&](const std::string& k, const std::string& v) {
    return st.meta.text(k).text(v).insert();
  };
  if (!add_meta("schema_version", std::to_string(kSchemaVersion)) ||
      !add_meta("content_hash", hash) || !add_meta("built_from", built_from) ||
      !add_meta("generator", "upiddb-compile"))
    return "meta";
  for (const auto& p : m.profiles)
    if (!st.prof.text(p.id)
             .text(p.family)
             .text(p.software)
             .text(p.version)
             .text(p.description)
             .prov(p.prov)
             .insert())
      return "profiles";
  for (auto* part : {insert_parameters, insert_errors, insert_commands, insert_devicenet})
    if (std::string table = part(st, m); !table.empty()) return table;
  return {};
}

}  // namespace

std::string write_db(const Model& m, const std::string& path, const std::string& hash,
                     const std::string& built_from) {
  sqlite::Connection db;
  if (!db.open(path, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE))
    return "cannot create " + path + ": " + db.error();
  std::string error;  // SQLite's message, where it gave one
  auto fail = [&](const std::string& what) {
    return "writing " + path + ": " + what + ": " + error;
  };
  if (!db.exec("PRAGMA journal_mode=OFF; PRAGMA synchronous=OFF;", &error) ||
      !db.exec(kSchemaSql, &error) || !db.exec("BEGIN", &error))
    return fail("schema");
  if (std::string table = insert_rows(db.get(), m, hash, built_from, error); !table.empty())
    return fail(table);
  if (!db.exec("COMMIT", &error)) return fail("commit");
  if (!db.close()) return "closing " + path + " failed";
  return {};
}

}  // namespace lmcfg::db::compiler
