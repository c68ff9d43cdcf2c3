#pragma once
// The local audit journal (docs/audit.md): every write to a drive from this
// host (restore, fleet restore, default, set, undo) appends one JSON object
// per line to <state directory>/journal.jsonl, the state directory of the
// undo and recovery records (ops/recovery.hpp): who, when, what (the plan's
// steps), why (reason, ticket), on which drive, and the outcome. The archive's
// commit trailers (ops/audit.hpp) say the same where there is an archive; the
// journal is there whether or not there is one.
//
// Append-only: the file is opened with O_APPEND and each record is one
// write() of one line, so records of concurrent writers never interleave (the
// kernel positions and writes an O_APPEND write as one step on a local file).
// Nothing is ever rewritten or removed by lmcfg.
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "common/result.hpp"
#include "ops/audit.hpp"

namespace lmcfg::ops {

struct JournalEntry {
  std::string time;  // ISO 8601 UTC ("2026-11-24T20:30:00Z"); utc_now() when empty
  Audit audit;
  std::string command;  // "restore", "fleet-restore", "default", "set", "undo"
  // The drive: its port and MACID (LinRS reads no serial or article number,
  // LinRS §10), the fleet position where there is one, the file restored.
  std::string port;
  std::uint8_t macid = 0;
  std::string position;
  std::string file;
  // The steps, each as `restore --json` gives them (plan_json): action, and
  // where it applies layer, upid, name, old, new ({raw, display}), id.
  nlohmann::ordered_json steps = nlohmann::ordered_json::array();
  std::string outcome;        // "restored and verified", "defaulted", "written", "failed", ...
  int exit_code = 0;          // the tool's exit code
  std::string exit_category;  // its meaning: "ok", "verify_mismatch", "comm_failure", ...
  std::string error;          // the error's message, "" without one
  std::string undo;           // the undo record saved before the first write, "" none
};

// <recovery_dir()>/journal.jsonl.
Result<std::filesystem::path> journal_path();

// The record as one JSON object (keys in a fixed order, docs/audit.md).
nlohmann::ordered_json journal_record(const JournalEntry& e);

// Appends `record` as one line to `path` (directories created, the file
// created with mode 0600), with a single write() on an O_APPEND descriptor.
// Errc::file_error naming the path and the OS error.
Result<void> append_journal(const std::filesystem::path& path,
                            const nlohmann::ordered_json& record);

// The journal's records, oldest first, those of one drive when `port` is set
// (and `macid`, when set, too). A missing file is an empty list; a line that is
// not a JSON object is an error naming the file and line.
Result<std::vector<nlohmann::ordered_json>> read_journal(const std::filesystem::path& path,
                                                         const std::string& port = "",
                                                         std::optional<std::uint8_t> macid = {});

}  // namespace lmcfg::ops
