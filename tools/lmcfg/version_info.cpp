#include "version_info.hpp"

#include "build_info.hpp"
#include "common/version.hpp"
#include "db/database.hpp"

namespace lmcfg::cli {

std::string version_text() {
  std::string s = std::string("lmcfg ") + kToolVersion + "\n";
  if (*kGitRevision) s += std::string("git revision: ") + kGitRevision + "\n";
  auto path = db::Database::default_path();
  auto opened = path ? db::Database::open(*path) : Result<db::Database>(path.error());
  if (!opened) {
    s += "UPID database: none (" + opened.error().message + ")";
    return s;
  }
  const db::DbInfo& info = opened->info();
  s += "UPID database: " + info.path + "\n";
  s += "  fingerprint: " + info.content_hash + "\n";
  s += "  schema version: " + std::to_string(info.schema_version) + "\n";
  s += "  profiles:";
  const auto& profiles = opened->profiles();
  if (profiles.empty()) s += " none";
  for (std::size_t i = 0; i < profiles.size(); ++i) s += (i ? ", " : " ") + profiles[i].id;
  return s;
}

}  // namespace lmcfg::cli
