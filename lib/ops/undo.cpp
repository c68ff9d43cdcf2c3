#include "ops/undo.hpp"

#include <algorithm>
#include <ctime>
#include <system_error>

#include "common/layers.hpp"
#include "common/utc_time.hpp"
#include "config/config_io.hpp"
#include "db/database.hpp"
#include "ops/backup.hpp"
#include "ops/recovery.hpp"

namespace lmcfg::ops {

namespace fs = std::filesystem;

namespace {

void add_layer(config::DriveConfig& cfg, int layer,
               const std::vector<client::ModifiedParam>& modified) {
  cfg.scope.layers[static_cast<std::size_t>(layer - 1)] = true;
  auto& out = cfg.layer(layer);
  out.clear();
  for (const auto& m : modified)
    out.push_back(config::Parameter{m.upid, m.value, std::nullopt, std::nullopt, {}, {}, {}});
}

// "20261124T171500Z" of `now`, and the ISO form for listings.
std::string stamp_of(std::chrono::system_clock::time_point now) {
  const std::time_t t = std::chrono::system_clock::to_time_t(now);
  const std::tm tm = utc_tm(t);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y%m%dT%H%M%SZ", &tm);
  return buf;
}

// A record's file name: "<stamp>[.<n>]-<command>.json"; n counts records of
// one drive saved within the same second (2, 3, ...).
struct RecordName {
  std::string stamp;
  unsigned seq = 1;
  std::string command;
  bool operator<(const RecordName& o) const {
    return stamp != o.stamp ? stamp < o.stamp : seq < o.seq;
  }
};

std::optional<RecordName> parse_name(const std::string& name) {
  constexpr std::size_t kStamp = 16;  // 20261124T171500Z
  if (name.size() < kStamp + 7 || name.compare(name.size() - 5, 5, ".json") != 0)
    return std::nullopt;
  for (std::size_t i = 0; i < kStamp; ++i) {
    const char ch = name[i];
    const bool ok = i == 8 ? ch == 'T' : i == 15 ? ch == 'Z' : (ch >= '0' && ch <= '9');
    if (!ok) return std::nullopt;
  }
  RecordName r;
  r.stamp = name.substr(0, kStamp);
  std::size_t pos = kStamp;
  if (name[pos] == '.') {
    std::size_t end = pos + 1;
    while (end < name.size() && name[end] >= '0' && name[end] <= '9') ++end;
    if (end == pos + 1) return std::nullopt;
    r.seq = static_cast<unsigned>(std::stoul(name.substr(pos + 1, end - pos - 1)));
    pos = end;
  }
  if (name[pos] != '-') return std::nullopt;
  r.command = name.substr(pos + 1, name.size() - 5 - pos - 1);
  if (r.command.empty()) return std::nullopt;
  return r;
}

std::string iso_time(const std::string& stamp) {  // 20261124T171500Z -> 2026-11-24T17:15:00Z
  return stamp.substr(0, 4) + "-" + stamp.substr(4, 2) + "-" + stamp.substr(6, 2) + "T" +
         stamp.substr(9, 2) + ":" + stamp.substr(11, 2) + ":" + stamp.substr(13, 2) + "Z";
}

// "MC 12 parameters, 2 curves, 5 command table entries" (what restoring it writes).
std::string holds_text(const fs::path& path) {
  auto cfg = config::read_config_file(path);
  if (!cfg.ok()) return "unreadable: " + cfg.error().message;
  std::string s;
  auto add = [&](const std::string& part) { s += (s.empty() ? "" : ", ") + part; };
  for (int layer = 1; layer <= lmcfg::layers::kCount; ++layer) {
    if (!cfg->scope.layers[static_cast<std::size_t>(layer - 1)]) continue;
    const auto n = cfg->layer(layer).size();
    add(std::string(lmcfg::layers::name(layer)) + " " + std::to_string(n) +
        (n == 1 ? " parameter" : " parameters"));
  }
  if (cfg->scope.curves)
    add(std::to_string(cfg->curves.size()) + (cfg->curves.size() == 1 ? " curve" : " curves"));
  if (cfg->scope.command_table)
    add(std::to_string(cfg->ct_entries.size()) +
        (cfg->ct_entries.size() == 1 ? " command table entry" : " command table entries"));
  return s.empty() ? "nothing in scope" : s;
}

Result<std::vector<std::pair<RecordName, fs::path>>> records_of(const fs::path& drive_dir) {
  std::vector<std::pair<RecordName, fs::path>> out;
  std::error_code ec;
  if (!fs::is_directory(drive_dir, ec)) return out;
  for (fs::directory_iterator it(drive_dir, ec), end; !ec && it != end; it.increment(ec)) {
    if (!it->is_regular_file(ec)) continue;
    if (auto n = parse_name(it->path().filename().string())) out.emplace_back(*n, it->path());
  }
  if (ec)
    return Error(Errc::file_error,
                 drive_dir.string() + ": cannot list the undo records: " + ec.message());
  std::sort(out.begin(), out.end(), [](auto& a, auto& b) { return b.first < a.first; });
  return out;
}

}  // namespace

Result<fs::path> undo_dir() {
  LMCFG_ASSIGN_OR_RETURN(auto dir, recovery_dir());
  return dir / "undo";
}

std::string undo_command(const std::string& port, std::uint8_t macid) {
  const bool plain = std::all_of(port.begin(), port.end(), [](char ch) {
    return (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') ||
           std::string_view("/._-:+@").find(ch) != std::string_view::npos;
  });
  std::string quoted = port;
  if (!plain) {
    quoted = "'";
    for (char ch : port) quoted += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
    quoted += "'";
  }
  char id[8];
  std::snprintf(id, sizeof id, "0x%02X", macid);
  return "lmcfg undo --port " + quoted + " --id " + id;
}

Result<config::DriveConfig> undo_config_from_plan(client::Client& c, const Plan& plan,
                                                  const config::Scope& scope,
                                                  const db::Database& db) {
  config::DriveConfig cfg = new_capture(c, db);
  for (int layer = 1; layer <= lmcfg::layers::kCount; ++layer) {
    const auto i = static_cast<std::size_t>(layer - 1);
    if (scope.layers[i] && plan.target.layers[i]) add_layer(cfg, layer, *plan.target.layers[i]);
  }
  if (scope.command_table && plan.target.ct_entries) {
    cfg.scope.command_table = true;
    for (const auto& [id, raw] : *plan.target.ct_entries) cfg.ct_entries.push_back({id, raw});
  }
  if (scope.curves && plan.target.curves) {
    cfg.scope.curves = true;
    for (const auto& seen : *plan.target.curves) {
      config::Curve cv{seen.id, seen.info, {}};
      if (seen.data) {
        cv.data = *seen.data;
      } else if (seen.data_size > 0) {
        // The plan saw this curve differ by its sizes or info block and did
        // not need its data; the restore deletes or replaces it.
        LMCFG_ASSIGN_OR_RETURN(cv.data, c.read_curve_data(seen.id, seen.data_size));
      }
      cfg.curves.push_back(std::move(cv));
    }
  }
  annotate(cfg, db);
  config::canonicalize(cfg);
  return cfg;
}

Result<config::DriveConfig> undo_config_for_default(
    client::Client& c,
    const std::array<std::optional<std::vector<client::ModifiedParam>>, 4>& layers, bool curves,
    bool command_table, const db::Database& db) {
  config::DriveConfig cfg = new_capture(c, db);
  if (curves || command_table) {
    // What default deletes, read the way a backup reads it (§11, §12).
    BackupOptions bo;
    bo.layers = {false, false, false, false};
    bo.curves = curves;
    bo.command_table = command_table;
    bo.ask_drive = false;
    LMCFG_ASSIGN_OR_RETURN(auto tables, backup(c, bo, db));
    cfg.curves = std::move(tables.curves);
    cfg.ct_entries = std::move(tables.ct_entries);
    cfg.scope.curves = curves;
    cfg.scope.command_table = command_table;
  }
  for (int layer = 1; layer <= lmcfg::layers::kCount; ++layer)
    if (const auto& m = layers[static_cast<std::size_t>(layer - 1)]) add_layer(cfg, layer, *m);
  annotate(cfg, db);
  config::canonicalize(cfg);
  return cfg;
}

Result<config::DriveConfig> undo_config_for_parameter(client::Client& c, std::uint16_t upid,
                                                      const db::Database& db) {
  const int layer = lmcfg::layers::of_upid(upid);
  if (layer == 0) {
    char hex[8];
    std::snprintf(hex, sizeof hex, "%04Xh", upid);
    return Error(Errc::invalid_argument,
                 std::string("UPID ") + hex +
                     " lies in no firmware layer (seed 003 §10.2), so no modified list holds its "
                     "old value for the undo record; --no-undo writes without one");
  }
  config::DriveConfig cfg = new_capture(c, db);
  LMCFG_ASSIGN_OR_RETURN(auto modified, c.modified_list(layer));
  add_layer(cfg, layer, modified);
  annotate(cfg, db);
  config::canonicalize(cfg);
  return cfg;
}

Result<UndoSaved> save_undo(const UndoOptions& o, const config::DriveConfig& cfg,
                            const db::Database& db, std::chrono::system_clock::time_point now) {
  const fs::path drive_dir = o.dir / drive_key(o.port, o.macid);
  // Every caller saves before its first write: a record it cannot save refuses the write.
  auto refused = [](const std::string& why) {
    return Error(Errc::file_error, "cannot save the undo record: " + why +
                                       "; nothing written (--no-undo writes without it)");
  };
  std::error_code ec;
  fs::create_directories(drive_dir, ec);
  if (ec) return refused(drive_dir.string() + ": cannot create the directory: " + ec.message());
  const std::string stamp = stamp_of(now);
  // A record of the same second (of any command) gets the next number, so
  // the listing orders them as they were saved.
  auto earlier = records_of(drive_dir);
  if (!earlier.ok()) return refused(earlier.error().message);
  unsigned seq = 0;
  for (const auto& [name, p] : *earlier)
    if (name.stamp == stamp) seq = std::max(seq, name.seq);
  const fs::path path = drive_dir / (stamp + (seq ? "." + std::to_string(seq + 1) : std::string()) +
                                     "-" + o.command + ".json");
  config::WriteOptions wo;
  std::optional<DatabaseCtDecoder> ct_decoder;
  if (!db.is_empty()) wo.ct_decoder = &ct_decoder.emplace(db);
  if (auto w = config::write_config_file(cfg, path, config::FileFormat::json, wo); !w.ok())
    return refused(w.error().message);
  UndoSaved saved{path, undo_command(o.port, o.macid), {}};
  // Rotation only after the new record is safely written.
  LMCFG_ASSIGN_OR_RETURN(auto all, records_of(drive_dir));
  for (std::size_t i = o.keep; i < all.size(); ++i) {
    fs::remove(all[i].second, ec);
    if (!ec) saved.removed.push_back(all[i].second);
  }
  return saved;
}

Result<std::vector<UndoEntry>> list_undo(const fs::path& dir, const std::string& drive) {
  std::vector<UndoEntry> out;
  std::vector<std::string> drives;
  std::error_code ec;
  if (!drive.empty()) {
    drives.push_back(drive);
  } else if (fs::is_directory(dir, ec)) {
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
      if (it->is_directory(ec)) drives.push_back(it->path().filename().string());
    if (ec)
      return Error(Errc::file_error,
                   dir.string() + ": cannot list the undo records: " + ec.message());
    std::sort(drives.begin(), drives.end());
  }
  for (const auto& d : drives) {
    LMCFG_ASSIGN_OR_RETURN(auto recs, records_of(dir / d));
    for (const auto& [name, path] : recs)
      out.push_back(UndoEntry{path, d, iso_time(name.stamp), name.command, holds_text(path)});
  }
  return out;
}

}  // namespace lmcfg::ops
