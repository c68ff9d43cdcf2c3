// What the service knows about each position, and what must outlive it
// (docs/serve.md "State"): <state_dir>/states.json, written after each run
// and read back at start; pending/, one record per restore begun and not
// finished, resumed at the next start.
#include "serve/state_store.hpp"

#include <map>
#include <vector>

#include "common/bytes.hpp"
#include "config/atomic_file.hpp"
#include "fleet/history.hpp"

namespace lmcfg::serve::detail {

namespace {

std::int64_t state_unix_seconds(TimePoint t) {
  return std::chrono::duration_cast<std::chrono::seconds>(t.time_since_epoch()).count();
}
TimePoint state_from_unix(std::int64_t s) { return TimePoint(std::chrono::seconds(s)); }

Json time_or_null(const std::optional<TimePoint>& t) {
  return t ? Json(state_unix_seconds(*t)) : Json(nullptr);
}
std::optional<TimePoint> time_of(const Json& j, const char* key) {
  if (!j.contains(key) || !j[key].is_number_integer()) return std::nullopt;
  return state_from_unix(j[key].get<std::int64_t>());
}

// "press3/z" and MACID 11h on line "line1": "line1-11h.json" (names are
// archive paths, so '/' cannot be in a file name; a line's MACIDs are unique).
std::string pending_name(const fleet::LineEntry& line, const fleet::DriveEntry& d) {
  std::string n = line.name + "-" + hex(d.id, 2, "h") + ".json";
  for (char& c : n)
    if (c == '/') c = '_';
  return n;
}

Json state_json(const DriveState& st) {
  return {{"status", st.status},
          {"message", st.message},
          {"last_backup", time_or_null(st.last_backup)},
          {"last_attempt", time_or_null(st.last_attempt)},
          {"last_kind", st.last_kind},
          {"last_ok", st.last_ok},
          {"last_exit_code", st.last_exit_code},
          {"differences", st.differences},
          {"differing", st.differing},
          {"notified", st.notified},
          {"drive_state", st.drive_state},
          {"kept", st.kept}};
}

void state_from_json(const Json& j, DriveState& st) {
  st.status = j.value("status", st.status);
  st.message = j.value("message", st.message);
  st.last_backup = time_of(j, "last_backup");
  st.last_attempt = time_of(j, "last_attempt");
  st.last_kind = j.value("last_kind", "");
  st.last_ok = j.value("last_ok", false);
  st.last_exit_code = j.value("last_exit_code", 0);
  st.differences = j.value("differences", std::size_t{0});
  if (j.contains("differing") && j["differing"].is_array())
    for (const auto& t : j["differing"])
      if (t.is_string()) st.differing.push_back(t.get<std::string>());
  st.notified = j.value("notified", "");
  if (j.contains("kept") && j["kept"].is_array()) st.kept = j["kept"];
  if (j.contains("drive_state") && j["drive_state"].is_string())
    st.drive_state = j["drive_state"].get<std::string>();
}

// A record edited by hand: a field of another type reads as empty, not a throw at start.
PendingRestore pending_from_json(const Json& j) {
  auto text_of = [&j](const char* key) {
    return j.contains(key) && j[key].is_string() ? j[key].get<std::string>() : std::string();
  };
  PendingRestore p{text_of("drive"),
                   text_of("commit"),
                   text_of("who"),
                   text_of("reason"),
                   text_of("ticket"),
                   text_of("cause"),
                   j.contains("skip_incompatible") && j["skip_incompatible"].is_boolean() &&
                       j["skip_incompatible"].get<bool>(),
                   text_of("origin_job"),
                   text_of("drive_state"),
                   {},
                   j.contains("failed_attempts") && j["failed_attempts"].is_number_unsigned()
                       ? j["failed_attempts"].get<std::size_t>()
                       : 0};
  if (j.contains("failures") && j["failures"].is_array()) {
    for (const auto& f : j["failures"]) {
      if (!f.is_object()) continue;
      auto field = [&f](const char* key) {
        return f.contains(key) && f[key].is_string() ? f[key].get<std::string>() : std::string();
      };
      p.failures.push_back({field("time"), field("job"), field("reason")});
    }
  }
  return p;
}

}  // namespace

StateStore::StateStore(std::filesystem::path dir, std::function<void(const std::string&)> log)
    : dir_(std::move(dir)), log_(std::move(log)) {}

DriveState StateStore::state(const std::string& name) const {
  std::lock_guard<std::mutex> lock(mu_);
  auto it = data_.states.find(name);
  return it == data_.states.end() ? DriveState{} : it->second;
}

std::optional<PendingRestore> StateStore::pending(const std::string& name) const {
  std::lock_guard<std::mutex> lock(mu_);
  auto it = data_.pending.find(name);
  if (it == data_.pending.end()) return std::nullopt;
  return it->second;
}

bool StateStore::is_pending(const std::string& name) const {
  std::lock_guard<std::mutex> lock(mu_);
  return data_.pending.count(name) != 0;
}

void StateStore::save() {
  // The file's writers in turn, each with the states as they are then (the
  // last write holds the newest).
  std::lock_guard<std::mutex> file_lock(file_mu_);
  Json all = Json::object();
  {
    std::lock_guard<std::mutex> lock(mu_);
    for (const auto& [name, st] : data_.states) all[name] = state_json(st);
  }
  std::error_code ec;
  std::filesystem::create_directories(dir_, ec);
  const Json file{{"format", "lmcfg-serve-states"}, {"version", 1}, {"drives", all}};
  if (auto w = config::write_file_atomic(dir_ / "states.json", file.dump(1) + "\n"); !w.ok())
    log_("states: " + w.error().message);
}

void StateStore::load(const fleet::Inventory& inventory, fleet::Archive& archive) {
  const auto path = dir_ / "states.json";
  std::error_code ec;
  Json drives;
  if (std::filesystem::exists(path, ec)) {
    auto text = config::read_text_file(path, 1 << 24);
    Json j = text.ok() ? Json::parse(*text, nullptr, false) : Json();
    if (j.is_object() && j.contains("drives") && j["drives"].is_object())
      drives = j["drives"];
    else
      log_("states: " + path.string() + " is not a states file of lmcfg serve; states start empty");
  }
  auto saved = [&](const fleet::DriveEntry& d) {
    return drives.is_object() && drives.contains(d.name) && drives[d.name].is_object();
  };
  // No state saved (a first start, or one before states were kept): the last
  // backup that changed the position's file, as its file at HEAD says (one
  // read per position, none of the history: the start costs what the plant
  // has, not what the archive has lived through).
  std::vector<fleet::DriveEntry> unsaved;
  for (const auto& line : inventory.lines)
    for (const auto& d : line.drives)
      if (!saved(d)) unsaved.push_back(d);
  std::map<std::string, std::int64_t> backed_up;
  if (!unsaved.empty()) {
    auto times = fleet::last_backup_times(archive, unsaved);
    if (times.ok())
      backed_up = std::move(*times);
    else
      log_("states: the last backups could not be read from the archive (" + times.error().message +
           "); they show as never until the next backup");
  }
  for (const auto& line : inventory.lines) {
    for (const auto& d : line.drives) {
      DriveState st;
      if (auto a = fleet::read_approval(archive, d); a.ok()) st.approved = *a;
      if (saved(d)) {
        state_from_json(drives[d.name], st);
      } else if (auto t = backed_up.find(d.name); t != backed_up.end()) {
        st.last_backup = state_from_unix(t->second);
        st.message = "not read since the service started";
      }
      std::lock_guard<std::mutex> lock(mu_);
      data_.states[d.name] = std::move(st);
    }
  }
}

Result<void> StateStore::save_pending(const fleet::LineEntry& line, const fleet::DriveEntry& d,
                                      const PendingRestore& p) {
  Json failures = Json::array();
  for (const auto& f : p.failures)
    failures.push_back({{"time", f.time}, {"job", f.job}, {"reason", f.reason}});
  const Json j{{"drive", p.drive},
               {"commit", p.commit},
               {"who", p.who},
               {"reason", p.reason},
               {"ticket", p.ticket},
               {"cause", p.cause},
               {"skip_incompatible", p.skip_incompatible},
               {"origin_job", p.origin_job},
               {"drive_state", p.drive_state},
               {"failures", failures},
               {"failed_attempts", p.failed_attempts}};
  std::error_code ec;
  std::filesystem::create_directories(dir_ / "pending", ec);
  // The fields are checked UTF-8 (Service::execute); a resumed record's too.
  // Should one not be, U+FFFD stands for its bad bytes rather than a throw.
  LMCFG_TRY(
      config::write_file_atomic(dir_ / "pending" / pending_name(line, d),
                                j.dump(-1, ' ', false, Json::error_handler_t::replace) + "\n"));
  std::lock_guard<std::mutex> lock(mu_);
  data_.pending[d.name] = p;
  return {};
}

void StateStore::remove_pending(const fleet::LineEntry& line, const fleet::DriveEntry& d) {
  std::error_code ec;
  std::filesystem::remove(dir_ / "pending" / pending_name(line, d), ec);
  std::lock_guard<std::mutex> lock(mu_);
  data_.pending.erase(d.name);
}

std::vector<std::string> StateStore::load_pending(const fleet::Inventory& inventory) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dir_ / "pending", ec)) {
    const auto path = entry.path();
    if (path.extension() != ".json") continue;
    auto text = config::read_text_file(path, 1 << 16);
    Json j = text.ok() ? Json::parse(*text, nullptr, false) : Json();
    const fleet::DriveEntry* d = j.is_object() && j["drive"].is_string()
                                     ? inventory.find_drive(j["drive"].get<std::string>())
                                     : nullptr;
    if (!d) {
      log_("unfinished restore record " + path.string() +
           " names no drive of the inventory; left as it is");
      continue;
    }
    std::lock_guard<std::mutex> lock(mu_);
    data_.pending[d->name] = pending_from_json(j);
    names.push_back(d->name);
  }
  return names;
}

}  // namespace lmcfg::serve::detail
