#pragma once
// SQLite schema of lmcfg-upid.sqlite (documented in docs/upid-db.md). Bump
// kSchemaVersion (database.hpp) whenever this text changes incompatibly.
namespace lmcfg::db {

// Every content row carries provenance: `source` (the seed citation from the
// TSV), `src_file` and `src_line` (where the row was written).
inline constexpr const char* kSchemaSql = R"SQL(
CREATE TABLE meta(
  key   TEXT PRIMARY KEY,
  value TEXT NOT NULL);
CREATE TABLE profiles(
  profile TEXT PRIMARY KEY, family TEXT, software TEXT, version TEXT, description TEXT,
  source TEXT NOT NULL, src_file TEXT NOT NULL, src_line INTEGER NOT NULL);
CREATE TABLE parameters(
  id INTEGER PRIMARY KEY,
  upid INTEGER NOT NULL,
  upid_hex TEXT NOT NULL,
  profiles TEXT NOT NULL,
  layer TEXT NOT NULL,
  name TEXT,
  path TEXT,
  type_code INTEGER,
  type TEXT,
  address_usage INTEGER,
  ram_read INTEGER, ram_write INTEGER, rom_read INTEGER, rom_write INTEGER, no_hash INTEGER,
  min INTEGER, max INTEGER, default_value INTEGER,
  unit TEXT, scale REAL,
  comm INTEGER NOT NULL,
  description TEXT,
  source TEXT NOT NULL, src_file TEXT NOT NULL, src_line INTEGER NOT NULL);
CREATE INDEX parameters_upid ON parameters(upid);
CREATE TABLE enum_labels(
  parameter_id INTEGER NOT NULL REFERENCES parameters(id),
  raw INTEGER NOT NULL, label TEXT NOT NULL,
  source TEXT NOT NULL, src_file TEXT NOT NULL, src_line INTEGER NOT NULL,
  PRIMARY KEY(parameter_id, raw));
CREATE TABLE errors(
  domain TEXT NOT NULL, code INTEGER NOT NULL, code_text TEXT NOT NULL,
  text TEXT, description TEXT, action TEXT, class TEXT,
  source TEXT NOT NULL, src_file TEXT NOT NULL, src_line INTEGER NOT NULL,
  PRIMARY KEY(domain, code));
CREATE TABLE motion_commands(
  master INTEGER NOT NULL, sub INTEGER NOT NULL, header INTEGER NOT NULL UNIQUE,
  name TEXT NOT NULL, products TEXT, description TEXT,
  source TEXT NOT NULL, src_file TEXT NOT NULL, src_line INTEGER NOT NULL,
  PRIMARY KEY(master, sub));
CREATE TABLE motion_command_params(
  master INTEGER NOT NULL, sub INTEGER NOT NULL, idx INTEGER NOT NULL, offset INTEGER NOT NULL,
  name TEXT, type_code INTEGER, type TEXT, unit TEXT, scale REAL,
  range_text TEXT, min INTEGER, max INTEGER, scaled INTEGER NOT NULL,
  source TEXT NOT NULL, src_file TEXT NOT NULL, src_line INTEGER NOT NULL,
  PRIMARY KEY(master, sub, idx),
  FOREIGN KEY(master, sub) REFERENCES motion_commands(master, sub));
CREATE TABLE devicenet_parameters(
  seq INTEGER PRIMARY KEY,
  id TEXT NOT NULL UNIQUE, profile TEXT NOT NULL REFERENCES profiles(profile),
  name TEXT, path TEXT, type_code INTEGER, type TEXT,
  min INTEGER, max INTEGER, default_value INTEGER, unit TEXT, scale REAL,
  comm INTEGER NOT NULL, description TEXT,
  source TEXT NOT NULL, src_file TEXT NOT NULL, src_line INTEGER NOT NULL);
CREATE TABLE devicenet_parameter_labels(
  parameter_id TEXT NOT NULL REFERENCES devicenet_parameters(id),
  raw INTEGER NOT NULL, label TEXT NOT NULL,
  source TEXT NOT NULL, src_file TEXT NOT NULL, src_line INTEGER NOT NULL,
  PRIMARY KEY(parameter_id, raw));
CREATE TABLE devicenet_commands(
  id INTEGER PRIMARY KEY, id_text TEXT NOT NULL, profile TEXT NOT NULL REFERENCES profiles(profile),
  direction TEXT, name TEXT NOT NULL, table_name TEXT, range_text TEXT,
  min INTEGER, max INTEGER, unit TEXT, scale REAL, unit_text TEXT,
  addressed INTEGER NOT NULL, direct INTEGER NOT NULL, description TEXT,
  source TEXT NOT NULL, src_file TEXT NOT NULL, src_line INTEGER NOT NULL);
CREATE TABLE devicenet_command_labels(
  command_id INTEGER NOT NULL REFERENCES devicenet_commands(id),
  raw INTEGER NOT NULL, label TEXT NOT NULL,
  source TEXT NOT NULL, src_file TEXT NOT NULL, src_line INTEGER NOT NULL,
  PRIMARY KEY(command_id, raw));
)SQL";

}  // namespace lmcfg::db
