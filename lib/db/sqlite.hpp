#pragma once
// A small RAII layer over the SQLite C API, shared by the compiler's writer
// (lib/db/compiler_write.cpp) and the reader (lib/db/database.cpp). Internal to
// lib/db: nothing outside the folder sees SQLite.
#include <sqlite3.h>

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

#include "db/database.hpp"

namespace lmcfg::db::sqlite {

// One connection, closed when the object goes.
class Connection {
 public:
  Connection() = default;
  ~Connection() { close(); }
  Connection(const Connection&) = delete;
  Connection& operator=(const Connection&) = delete;

  // sqlite3_open_v2. On failure ok() is false and error() says why (a handle
  // SQLite returns with the error is kept until close, for its message).
  bool open(const std::string& name, int flags) {
    close();
    return sqlite3_open_v2(name.c_str(), &db_, flags, nullptr) == SQLITE_OK;
  }
  // Closes now; false when SQLite refused (a statement still open).
  bool close() {
    const int rc = sqlite3_close_v2(db_);
    db_ = nullptr;
    return rc == SQLITE_OK;
  }
  sqlite3* get() const { return db_; }
  std::string error() const { return db_ ? sqlite3_errmsg(db_) : "out of memory"; }

  // Runs one or more statements without results; on failure `*err` gets
  // SQLite's message.
  bool exec(const char* sql, std::string* err) {
    char* msg = nullptr;
    if (sqlite3_exec(db_, sql, nullptr, nullptr, &msg) == SQLITE_OK) return true;
    if (err) *err = msg ? msg : "sqlite error";
    sqlite3_free(msg);
    return false;
  }

 private:
  sqlite3* db_ = nullptr;
};

// One prepared statement, finalized when the object goes.
// Reading: while (s.next()) { s.column_text(0) ... }, then failed() tells an
// error from the end of the rows.
// Writing: s.text(..).integer(..).real(..).insert() binds the parameters in
// order (1-based); empty strings and nullopts become NULL. insert() runs the
// statement, then resets it and its bindings for the next row.
class Statement {
 public:
  Statement(sqlite3* db, const char* sql) {
    if (sqlite3_prepare_v2(db, sql, -1, &s_, nullptr) != SQLITE_OK) {
      sqlite3_finalize(s_);
      s_ = nullptr;
    }
  }
  ~Statement() { sqlite3_finalize(s_); }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  bool ok() const { return s_ != nullptr; }

  bool next() {
    rc_ = sqlite3_step(s_);
    return rc_ == SQLITE_ROW;
  }
  bool failed() const { return rc_ != SQLITE_ROW && rc_ != SQLITE_DONE; }

  bool column_null(int i) const { return sqlite3_column_type(s_, i) == SQLITE_NULL; }
  std::string column_text(int i) const {
    auto* p = sqlite3_column_text(s_, i);
    return p ? std::string(reinterpret_cast<const char*>(p),
                           static_cast<std::size_t>(sqlite3_column_bytes(s_, i)))
             : std::string();
  }
  std::int64_t column_int(int i) const { return sqlite3_column_int64(s_, i); }
  std::optional<std::int64_t> column_opt_int(int i) const {
    if (column_null(i)) return std::nullopt;
    return column_int(i);
  }
  std::optional<double> column_opt_real(int i) const {
    if (column_null(i)) return std::nullopt;
    return sqlite3_column_double(s_, i);
  }
  // source, src_file, src_line at columns first, first + 1, first + 2.
  Provenance column_prov(int first) const {
    return Provenance{column_text(first), column_text(first + 1),
                      static_cast<int>(column_int(first + 2))};
  }

  Statement& text(std::string_view v) {
    ++bound_;
    if (v.empty())
      sqlite3_bind_null(s_, bound_);
    else
      sqlite3_bind_text(s_, bound_, v.data(), static_cast<int>(v.size()), SQLITE_TRANSIENT);
    return *this;
  }
  Statement& integer(std::optional<std::int64_t> v) {
    ++bound_;
    if (v)
      sqlite3_bind_int64(s_, bound_, *v);
    else
      sqlite3_bind_null(s_, bound_);
    return *this;
  }
  Statement& real(std::optional<double> v) {
    ++bound_;
    if (v)
      sqlite3_bind_double(s_, bound_, *v);
    else
      sqlite3_bind_null(s_, bound_);
    return *this;
  }
  // source, src_file, src_line.
  Statement& prov(const Provenance& p) { return text(p.source).text(p.file).integer(p.line); }
  bool insert() {
    const int rc = sqlite3_step(s_);
    sqlite3_reset(s_);
    sqlite3_clear_bindings(s_);
    bound_ = 0;
    return rc == SQLITE_DONE;
  }

 private:
  sqlite3_stmt* s_ = nullptr;
  int rc_ = SQLITE_DONE;
  int bound_ = 0;
};

}  // namespace lmcfg::db::sqlite
