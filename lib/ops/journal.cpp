#include "ops/journal.hpp"

#include <fstream>

#include "common/bytes.hpp"
#include "config/atomic_file.hpp"
#include "ops/backup.hpp"
#include "ops/recovery.hpp"

namespace lmcfg::ops {

namespace fs = std::filesystem;

Result<fs::path> journal_path() {
  LMCFG_ASSIGN_OR_RETURN(auto dir, recovery_dir());
  return dir / "journal.jsonl";
}

nlohmann::ordered_json journal_record(const JournalEntry& e) {
  auto text_or_null = [](const std::string& s) {
    return s.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(s);
  };
  nlohmann::ordered_json j;
  j["time"] = e.time.empty() ? utc_now() : e.time;
  j["who"] = e.audit.who;
  j["reason"] = text_or_null(e.audit.reason);
  j["ticket"] = text_or_null(e.audit.ticket);
  j["command"] = e.command;
  nlohmann::ordered_json drive;
  drive["port"] = e.port;
  drive["id"] = hex(e.macid, 2, "h");
  if (!e.position.empty()) drive["position"] = e.position;
  j["drive"] = std::move(drive);
  j["file"] = text_or_null(e.file);
  j["steps"] = e.steps.is_array() ? e.steps : nlohmann::ordered_json::array();
  j["outcome"] = e.outcome;
  j["exit_code"] = e.exit_code;
  j["exit_category"] = e.exit_category;
  j["error"] = text_or_null(e.error);
  j["undo"] = text_or_null(e.undo);
  return j;
}

Result<void> append_journal(const fs::path& path, const nlohmann::ordered_json& record) {
  std::error_code ec;
  fs::create_directories(path.parent_path(), ec);
  if (ec)
    return Error(Errc::file_error, "journal " + path.string() + ": cannot create " +
                                       path.parent_path().string() + ": " + ec.message());
  // Invalid UTF-8 in a reason (a terminal in another encoding) is replaced,
  // not a reason to lose the record.
  const std::string line =
      record.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
  // One append: a concurrent writer's line goes before or after this one.
  if (auto r = config::append_file(path, line); !r)
    return Error(r.error().code, "journal " + r.error().message);
  return {};
}

Result<std::vector<nlohmann::ordered_json>> read_journal(const fs::path& path,
                                                         const std::string& port,
                                                         std::optional<std::uint8_t> macid) {
  std::vector<nlohmann::ordered_json> out;
  std::error_code ec;
  if (!fs::exists(path, ec)) return out;
  std::ifstream in(path);
  if (!in) return Error(Errc::file_error, "journal " + path.string() + ": cannot open");
  const std::string id = macid ? hex(*macid, 2, "h") : std::string();
  std::string line;
  std::size_t number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty()) continue;
    auto j = nlohmann::ordered_json::parse(line, nullptr, false);
    if (j.is_discarded() || !j.is_object())
      return Error(Errc::parse_error, path.string() + ":" + std::to_string(number) +
                                          ": not a JSON object (expected one record per line)");
    const auto drive = j.contains("drive") ? j["drive"] : nlohmann::ordered_json();
    if (!port.empty() && !(drive.is_object() && drive.value("port", "") == port)) continue;
    if (!id.empty() && !(drive.is_object() && drive.value("id", "") == id)) continue;
    out.push_back(std::move(j));
  }
  return out;
}

}  // namespace lmcfg::ops
