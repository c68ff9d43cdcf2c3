#include "ops/recovery.hpp"

#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <system_error>

#include "config/atomic_file.hpp"
#include "config/io_common.hpp"
#include "ops/platform.hpp"

namespace lmcfg::ops {

namespace fs = std::filesystem;

Result<fs::path> recovery_dir() { return state_dir(); }

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

namespace {

// The record's values are written back to the drive: one that does not fit
// its field (a hand-edited or damaged file) is refused, never truncated onto
// another UPID or value.
std::uint32_t unsigned_member(const nlohmann::json& j, const char* name, std::uint32_t max,
                              const std::string& where = {}) {
  const auto& v = j.at(name);
  const std::string field = where.empty() ? name : where + "." + name;
  if (!v.is_number_unsigned() || v.get<std::uint64_t>() > max)
    throw std::runtime_error(field + " is " + v.dump() + ", expected an integer 0.." +
                             std::to_string(max));
  return static_cast<std::uint32_t>(v.get<std::uint64_t>());
}

// "200E": the UPID as save_recovery writes it, four hexadecimal digits.
std::uint16_t upid_member(const nlohmann::json& k, const std::string& where) {
  const auto& v = k.at("upid");
  const auto upid =
      v.is_string() ? config::detail::parse_upid_hex(v.get<std::string>()) : std::nullopt;
  if (!upid)
    throw std::runtime_error(where + ".upid is " + v.dump() +
                             ", expected 4 hexadecimal digits (\"200E\")");
  return *upid;
}

}  // namespace

Result<std::optional<RecoveryRecord>> load_recovery(const fs::path& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) return std::optional<RecoveryRecord>();
  LMCFG_ASSIGN_OR_RETURN(auto text, config::read_text_file(path));
  try {
    auto j = nlohmann::json::parse(text);
    RecoveryRecord r;
    r.command = j.at("command").get<std::string>();
    r.port = j.at("port").get<std::string>();
    r.macid = static_cast<std::uint8_t>(unsigned_member(j, "macid", 0xFF));
    r.created = j.at("created").get<std::string>();
    r.expect = j.value("expect", std::string());
    std::size_t n = 0;
    for (const auto& k : j.at("keep")) {
      const std::string where = "keep[" + std::to_string(n++) + "]";
      r.keep.push_back(client::ModifiedParam{upid_member(k, where),
                                             unsigned_member(k, "value", 0xFFFFFFFF, where)});
    }
    // Written by versions that know unacknowledged steps (docs/field.md); absent before.
    if (auto u = j.find("unacknowledged"); u != j.end())
      for (const auto& step : *u) r.unacknowledged.push_back(step.get<std::string>());
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
    j["keep"].push_back({{"upid", config::detail::upid_hex(k.upid)}, {"value", k.value}});
  }
  if (!rec.unacknowledged.empty()) j["unacknowledged"] = rec.unacknowledged;
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
