#pragma once
// The commands' `--json` reports (docs/json-reports.md), built in one place
// so the CLI, the service and Python produce the same JSON from the same code.
// Each function builds the object; the caller prints it (`dump()` or
// `dump(2)` as the document says) or adds the fields only it knows.
//
// Other JSON reports live next to the model they describe: ops::render_json
// (diff), ops::render_info_json (info), ops::plan_json (restore plan),
// fleet::render_json / history_json (fleet), ops::journal_record (journal).
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "config/config_io.hpp"
#include "config/model.hpp"
#include "db/database.hpp"
#include "link/linudp_scan.hpp"
#include "link/scan.hpp"
#include "ops/db_scan.hpp"
#include "ops/factory_reset.hpp"
#include "ops/link_settings.hpp"
#include "ops/restore_run.hpp"
#include "ops/undo.hpp"

namespace lmcfg::report {

using Json = nlohmann::ordered_json;

// backup --json of a LinRS drive: the file and what it holds, telegrams sent.
Json backup_json(const std::string& file, const config::DriveConfig& cfg, std::uint64_t telegrams);
// backup --json of a DeviceNet controller (seed 000): MAC ID, counts, the runtime note.
Json devicenet_backup_json(const std::string& file, const config::DriveConfig& cfg);

// convert --json: input, output, format and what the written file holds.
Json convert_json(const std::string& input, const std::string& output, config::FileFormat format,
                  std::size_t bytes, const config::DriveConfig& cfg, bool ct_decoded);

// restore --json (and undo, fleet restore): the file, the outcome, the link
// after a relink, the plan's items (LinRS or DeviceNet), the second pass's
// steps, the mismatches, the undo record and the error.
Json restore_json(const ops::RestoreOutcome& out, const std::string& file);
// The restore's steps as the journal records them: the report's, the second
// pass's after the first; a DeviceNet Set command's old and new as raw words
// (docs/audit.md).
Json restore_steps_json(const ops::RestoreOutcome& out);

// {"path", "command"} of an undo record saved before a write.
Json undo_json(const ops::UndoSaved& u);
// undo --list --json: the directory and the records, newest first.
Json undo_list_json(const std::filesystem::path& dir, const std::vector<ops::UndoEntry>& records);

// default --json: outcome ("defaulted", "failed"), steps, the communication
// values kept; `rep` null when it failed before a report.
Json default_json(const char* outcome, const ops::DefaultReport* rep, const db::Database& db,
                  const std::string& error);
// What default does as the journal's steps (the shape of restore --json's
// steps): each layer defaulted, the curves and command table deleted, the
// communication values written back.
Json default_steps_json(const ops::DefaultOptions& d, const ops::DefaultReport* rep,
                        const db::Database& db);

// journal --json: the journal's path and the records as written.
Json journal_json(const std::filesystem::path& journal, const std::vector<Json>& records);

// link --json: the drive, its link options and its settings as the ROM holds them.
Json link_json(const std::string& port, const ops::LinkState& now);
// One object per setting: setting, upid, rom, value, note.
Json link_settings_json(const ops::LinkState& st);
// The plan's writes and the link options after the reset, added to link_json's object.
void add_link_plan(Json& j, const ops::LinkPlan& plan);
// A change applied: outcome "changed", how the drive was found, the settings read back.
void add_link_changed(Json& j, const ops::LinkApplyReport& rep);

// get/set --json: one parameter's value. `text` is the value as shown
// (scaled, labelled), `where` the memory ("RAM", "ROM").
Json param_json(std::uint16_t upid, const db::Parameter* d, const db::ValueSpec& spec,
                const char* where, std::uint32_t value, const std::string& text,
                const std::optional<ops::UndoSaved>& undo);
// set's journal step: the write with the old and the new value, as shown.
Json param_write_step_json(const char* action, std::uint16_t upid, const db::Parameter* d,
                           const db::ValueSpec& spec, std::optional<std::uint32_t> old,
                           std::uint32_t value);

// scan --json: the drives found with their link options, the passes tried.
// Plain nlohmann::json (keys sorted), as the report has always been.
nlohmann::json scan_json(const link::ScanReport& r);
// `lmcfg scan --port linudp://RANGE --json` (docs/json-reports.md).
nlohmann::json linudp_scan_json(const link::LinudpScanReport& r);

// lmcfg db --json (json_db.cpp): the database's rows, plain nlohmann::json.
nlohmann::json db_provenance_json(const db::Provenance& p);
nlohmann::json db_parameter_json(const db::Parameter& p);
// db show: the UPID, whether it is known, its definitions (one per profile).
nlohmann::json db_show_json(std::uint16_t upid, const std::vector<const db::Parameter*>& found);
nlohmann::json db_parameters_json(const std::vector<const db::Parameter*>& v);  // db find
nlohmann::json db_errors_json(const std::vector<const db::ErrorEntry*>& v);
nlohmann::json db_commands_json(const std::vector<db::MotionCommand>& v);
nlohmann::json db_value_spec_json(const db::ValueSpec& s);
nlohmann::json db_devicenet_command_json(const db::DevicenetCommand& c);
nlohmann::json db_devicenet_commands_json(const std::vector<db::DevicenetCommand>& v);
nlohmann::json db_devicenet_parameters_json(const std::vector<db::DevicenetParameter>& v);
nlohmann::json db_info_json(const db::DbInfo& i);
// db scan --json; `merged_into` "" when the fragment was not merged.
nlohmann::json db_scan_json(const std::string& file, const ops::DbScanResult& r,
                            std::uint64_t telegrams, const std::string& merged_into);
nlohmann::json db_merge_json(const std::string& into, const ops::MergeReport& m);

}  // namespace lmcfg::report
