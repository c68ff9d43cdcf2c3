#pragma once
// Helpers shared by the restore phases (restore_*.cpp); not a public API.
#include <cstdint>
#include <map>
#include <optional>
#include <string>

#include "config/model.hpp"
#include "db/database.hpp"
#include "ops/restore.hpp"

namespace lmcfg::ops::detail {

// "MC 13A2h P Gain" (name from the database, else from the file's record).
std::string param_label(int layer, std::uint16_t upid, const db::Parameter* d,
                        const config::Parameter* p);
std::string param_name(std::uint16_t upid, const db::Parameter* d, const config::Parameter* p);
// A curve's name from its info block (offset 8, up to 22 characters, §11 /
// docs/config-files.md); "" when the block is too short.
std::string curve_name(const Bytes& info);

inline bool refused(const Error& e) { return e.code == ErrorClass::drive_refusal; }

// Telegrams of a block of n bytes written in 4-byte chunks (§11, §12).
inline std::size_t chunks(std::size_t n) { return (n + 3) / 4; }

// One parameter the plan writes, with the target's value before.
struct Write {
  config::Parameter p;
  std::optional<std::uint32_t> old;
  std::string old_note;  // " (default)" when `old` was inferred, not read
  WriteReason reason = WriteReason::differs;
};

// The plan under construction: its steps and their write telegrams.
struct Builder {
  client::Client& c;
  const db::Database& db;
  const RestoreOptions& opt;
  Plan& plan;
  // The target refused 05h/03h once (the seed's generation): the other layers
  // do not ask again.
  bool no_address_usage_request = false;

  void add(PlanStep s, std::size_t telegrams) {
    plan.steps.push_back(std::move(s));
    plan.write_telegrams += telegrams;
  }
  void add(PlanStep::Action a, std::uint32_t key, std::string text, std::size_t telegrams) {
    PlanStep s;
    s.action = a;
    s.key = key;
    s.text = std::move(text);
    add(std::move(s), telegrams);
  }
  void add_write(int layer, const Write& w);  // restore_plan.cpp
  // The type a value is shown by: `recorded` (the file's), else the one a
  // capture of the target recorded (RestoreOptions::known_types).
  std::optional<std::uint8_t> shown_type(std::uint16_t upid,
                                         std::optional<std::uint8_t> recorded) const {
    if (recorded) return recorded;
    const auto it = opt.known_types.find(upid);
    return it == opt.known_types.end() ? std::nullopt : std::optional<std::uint8_t>(it->second);
  }
};

// restore_check.cpp: one parameter the restore will write checked against the
// target; problems, incompatible values and notes go to `plan`. True when the
// target can take it; link errors propagate. `listed`: the target's UPID list
// of the layer (§10.3) where the database lacks an address usage.
// `usage`: address usages the target answered one by one (05h/03h, LinRS
// 3V27 p27), where the database lacks them and no list was read.
Result<bool> check_parameter(client::Client& c, const db::Database& db, const RestoreOptions& opt,
                             int layer, const config::Parameter& p,
                             const std::map<std::uint16_t, client::UpidInfo>* listed,
                             const std::map<std::uint16_t, std::uint16_t>* usage, Plan& plan);
// restore_check.cpp: the file's curves and command table entries against the
// drive's limits; returns the file less (with skip_incompatible) what the
// target cannot take.
config::DriveConfig check_tables(const config::DriveConfig& file, const RestoreOptions& opt,
                                 Plan& plan);

// restore_tables.cpp: the target's command table and curves read and compared
// with `file`'s; the deletes, writes and one flash save of each table that
// differs (or always, with `force_save`).
Result<void> plan_command_table(Builder& b, const config::DriveConfig& file, bool force_save);
Result<void> plan_curves(Builder& b, const config::DriveConfig& file, bool force_save);

}  // namespace lmcfg::ops::detail
