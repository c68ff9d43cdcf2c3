// The installed layout (docs/install.md): where the program finds its UPID
// database, and what `lmcfg --version` says. The man page and completion are
// checked by tests/cli-docs-test.sh; `cmake --install` by scripts/test-install.sh.
#include <sys/wait.h>

#include <catch2/catch.hpp>
#include <cstdio>
#include <filesystem>
#include <string>

#include "common/version.hpp"
#include "db/database.hpp"
#include "db_test_support.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace tools_test_install {

namespace fs = std::filesystem;
using lmcfg::db::Database;

namespace {
struct Run {
  int rc = -1;
  std::string out;
};
// Runs a shell command from `/`, stdout and stderr together.
Run run(const std::string& cmd) {
  Run r;
  FILE* p = ::popen(("cd / && " + cmd + " 2>&1").c_str(), "r");
  if (!p) return r;
  char buf[4096];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) r.out.append(buf, n);
  int st = ::pclose(p);
  r.rc = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}
void copy_into(const fs::path& from, const fs::path& to) {
  fs::create_directories(to.parent_path());
  fs::copy_file(from, to, fs::copy_options::overwrite_existing);
}
}  // namespace

TEST_CASE("database lookup: $LMCFG_UPID_DB, next to the program, ../share/lmcfg/", "[install]") {
  auto root = lmcfg::db::test::scratch_dir("lookup");
  const fs::path bin = root / "bin";
  fs::create_directories(bin);
  const std::string beside = (bin / "lmcfg-upid.sqlite").string();
  const std::string shared = (root / "share" / "lmcfg" / "lmcfg-upid.sqlite").string();

  // Set: taken as given, even when missing (open() then names it).
  CHECK(Database::find_default_path("/x/my.sqlite", bin).value() == "/x/my.sqlite");

  auto none = Database::find_default_path(nullptr, bin);
  REQUIRE_FALSE(none);
  CHECK(none.error().code == lmcfg::Errc::file_error);
  CHECK(none.error().message ==
        "UPID database not found; looked in: $LMCFG_UPID_DB (not set), " + beside +
            " (next to the program), " + shared +
            " (../share/lmcfg/ relative to the program); expected lmcfg-upid.sqlite in one of "
            "them (pass --db PATH or set LMCFG_UPID_DB)");

  fs::create_directories(fs::path(shared).parent_path());
  lmcfg::db::test::write_file(shared, "x");
  CHECK(Database::find_default_path(nullptr, bin).value() == shared);
  CHECK(Database::find_default_path("", bin).value() == shared);  // empty = unset
  lmcfg::db::test::write_file(beside, "x");
  CHECK(Database::find_default_path(nullptr, bin).value() == beside);
}

TEST_CASE("installed layout: bin/lmcfg finds share/lmcfg/ from any folder", "[install]") {
  auto prefix = lmcfg::db::test::scratch_dir("prefix");
  const fs::path tool = prefix / "bin" / "lmcfg";
  copy_into(LMCFG_TOOL_PATH, tool);
  fs::permissions(tool, fs::perms::owner_all);
  const std::string env = "env -u LMCFG_UPID_DB ";

  auto missing = run(env + tool.string() + " db show 13A2");
  CHECK(missing.rc == 2);
  CHECK(missing.out == "lmcfg db: UPID database not found; looked in: $LMCFG_UPID_DB (not set), " +
                           (prefix / "bin" / "lmcfg-upid.sqlite").string() +
                           " (next to the program), " +
                           (prefix / "share" / "lmcfg" / "lmcfg-upid.sqlite").string() +
                           " (../share/lmcfg/ relative to the program); expected "
                           "lmcfg-upid.sqlite in one of them (pass --db PATH or set "
                           "LMCFG_UPID_DB)\n");

  auto version_none = run(env + tool.string() + " --version");
  CHECK(version_none.rc == 0);
  CHECK(version_none.out.rfind(std::string("lmcfg ") + lmcfg::kToolVersion + "\n", 0) == 0);
  CHECK(version_none.out.find("UPID database: none (UPID database not found; looked in: ") !=
        std::string::npos);

  const fs::path db = prefix / "share" / "lmcfg" / "lmcfg-upid.sqlite";
  copy_into(LMCFG_DB_PATH, db);
  auto shown = run(env + tool.string() + " db show 13A2");
  CHECK(shown.rc == 0);
  CHECK(shown.out.find("13A2") != std::string::npos);

  auto opened = Database::open(db.string());
  REQUIRE(opened);
  std::string profiles;
  for (const auto& p : opened->profiles()) profiles += (profiles.empty() ? " " : ", ") + p.id;
  REQUIRE_FALSE(opened->profiles().empty());
  auto version = run(env + tool.string() + " --version");
  CHECK(version.rc == 0);
  CHECK(version.out.find("UPID database: " + db.string() +
                         "\n  fingerprint: " + opened->info().content_hash +
                         "\n  schema version: " + std::to_string(opened->info().schema_version) +
                         "\n  profiles:" + profiles + "\n") != std::string::npos);

  // $LMCFG_UPID_DB wins over the installed file, and a missing one is named.
  auto env_missing = run("LMCFG_UPID_DB=/nonexistent/u.sqlite " + tool.string() + " db show 13A2");
  CHECK(env_missing.rc == 2);
  CHECK(env_missing.out.find("/nonexistent/u.sqlite") != std::string::npos);
}

}  // namespace tools_test_install
