#include "ops/recovery.hpp"

#include <cstdlib>
#include <nlohmann/json.hpp>
#include <system_error>

#include "config/atomic_file.hpp"

namespace lmcfg::ops {

namespace fs = std::filesystem;

Result<fs::path> recovery_dir() {
  const char* xdg = std::getenv("XDG_STATE_HOME");
  if (xdg && *xdg == '/') return fs::path(xdg) / "lmcfg";
  const char* home = std::getenv("HOME");
  if (home && *home) return fs::path(home) / ".local" / "state" / "lmcfg";
  return Error(Errc::file_error,
               "no place for the recovery record: neither $XDG_STATE_HOME (absolute) nor $HOME "
               "is set");
}

std::string drive_key(const std::string& port, std::uint8_t macid) {
  std::string key;
  for (char ch : port) {
    const bool plain = (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') ||
                       (ch >= '0' && ch <= '9') || ch == '.' || ch == '-';
    key.push_back(plain ? ch : '_');
  }
  char id[8];
  std::snprintf(id, sizeof id, "%02Xh", macid);
  return key + "-" + id;
}

Result<fs::path> recovery_path(const std::string& command, const std::string& port,
                               std::uint8_t macid) {
  LMCFG_ASSIGN_OR_RETURN(auto dir, recovery_dir());
  return dir / (command + "-" + drive_key(port, macid) + ".json");
}

Result<std::optional<RecoveryRecord>> load_recovery(const fs::path& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) return std::optional<RecoveryRecord>();
  LMCFG_ASSIGN_OR_RETURN(auto text, config::read_text_file(path));
  try {
    auto j = nlohmann::json::parse(text);
    RecoveryRecord r;
    r.command = j.at("command").get<std::string>();
    r.port = j.at("port").get<std::string>();
    r.macid = j.at("macid").get<std::uint8_t>();
    r.created = j.at("created").get<std::string>();
    r.expect = j.value("expect", std::string());
    for (const auto& k : j.at("keep")) {
      r.keep.push_back(client::ModifiedParam{
          static_cast<std::uint16_t>(std::stoul(k.at("upid").get<std::string>(), nullptr, 16)),
          k.at("value").get<std::uint32_t>()});
    }
    return std::optional<RecoveryRecord>(std::move(r));
  } catch (const std::exception& e) {
    return Error(Errc::parse_error, path.string() + ": damaged recovery record (" + e.what() +
                                        "); expected the JSON lmcfg wrote. Inspect it, then "
                                        "delete it to go on");
  }
}

Result<void> save_recovery(const fs::path& path, const RecoveryRecord& rec) {
  std::error_code ec;
  fs::create_directories(path.parent_path(), ec);
  if (ec)
    return Error(Errc::file_error, path.parent_path().string() +
                                       ": cannot create the recovery directory: " + ec.message());
  nlohmann::ordered_json j;
  j["command"] = rec.command;
  j["port"] = rec.port;
  j["macid"] = rec.macid;
  j["created"] = rec.created;
  if (!rec.expect.empty()) j["expect"] = rec.expect;
  j["keep"] = nlohmann::ordered_json::array();
  for (const auto& k : rec.keep) {
    char upid[8];
    std::snprintf(upid, sizeof upid, "%04X", k.upid);
    j["keep"].push_back({{"upid", upid}, {"value", k.value}});
  }
  return config::write_file_atomic(path, j.dump(2) + "\n");
}

Result<void> remove_recovery(const fs::path& path) {
  std::error_code ec;
  fs::remove(path, ec);
  if (ec)
    return Error(Errc::file_error,
                 path.string() + ": cannot delete the finished recovery record: " + ec.message());
  return {};
}

}  // namespace lmcfg::ops
