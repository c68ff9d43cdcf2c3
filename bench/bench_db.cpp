// UPID database: open time (open() reads every table), lookup rates, search,
// and SQLite's own share of the open.
// Uses the database built from upid-db/ (LMCFG_DB_PATH) and a large synthetic
// database (20,000 parameter rows) that main() compiles at start-up with the
// project's own compiler (lmcfg::db::compile_upid_db), so it has the real
// schema and indexes.
#include <benchmark/benchmark.h>
#include <sqlite3.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "common/bytes.hpp"
#include "db/compiler.hpp"
#include "db/ct_entry.hpp"
#include "db/database.hpp"

namespace {

using lmcfg::db::Database;

// Rows of the synthetic database: one row per UPID of the four layer ranges
// (4 x 0F00h = 15,360 UPIDs), and a second profile row for the first 4,640, so
// 20,000 rows; every tenth row is an enum with three labels.
constexpr int kLargeRows = 20000;
std::string g_large_path;     // set by main()
std::filesystem::path g_tmp;  // removed at exit

Database open_or_die(const std::string& path) {
  auto r = Database::open(path);
  if (!r) {
    std::fprintf(stderr, "%s\n", r.error().message.c_str());
    std::exit(1);
  }
  return std::move(r).value();
}

const Database& db() {
  static const Database d = open_or_die(LMCFG_DB_PATH);
  return d;
}

const Database& large_db() {
  static const Database d = open_or_die(g_large_path);
  return d;
}

// Writes upid-db sources (upid-db/FORMAT.md) into dir and compiles them.
bool build_large_db(const std::filesystem::path& dir, const std::string& out) {
  std::filesystem::create_directories(dir);
  {
    std::ofstream f(dir / "profiles.tsv");
    f << "profile\tfamily\tsoftware\tversion\tdescription\tsource\n"
         "big-a\tE1100\tMC SW\t\tsynthetic\tentered by hand: benchmark\n"
         "big-b\tB1100\tMC SW\t\tsynthetic\tentered by hand: benchmark\n";
  }
  std::ofstream f(dir / "parameters.tsv");
  f << "upid\tprofiles\tlayer\tname\tpath\ttype\taddress_usage\tmin\tmax\tdefault\tunit\tscale\t"
       "enum\tcomm\tdescription\tsource\n";
  const char* layers[] = {"OS", "MC", "Intf", "Appl"};
  const int per_layer = 0x0F00;
  const int doubled = kLargeRows - 4 * per_layer;  // UPIDs with two profile rows
  int row = 0;
  for (int l = 0; l < 4; ++l) {
    for (int i = 0; i < per_layer; ++i) {
      const unsigned upid = static_cast<unsigned>(l * 0x1000 + i);
      const bool two = l * per_layer + i < doubled;
      for (int k = 0; k < (two ? 2 : 1); ++k, ++row) {
        const char* prof = two ? (k == 0 ? "big-a" : "big-b") : "big-a,big-b";
        f << lmcfg::hex(upid, 4) << '\t' << prof << '\t' << layers[l] << "\tSynthetic Parameter "
          << row << '\t' << layers[l] << "\\Group " << (i / 64) << "\\Parameter " << i << '\t';
        if (row % 10 == 0)
          f << "ENUM_DIR16\t000F\t0\t2\t1\t\t\t0=Off|1=On|2=Auto";
        else
          f << "UINT16\t000F\t0\t65535\t" << (row % 1000) << "\t\t\t";
        f << "\t\t\tentered by hand: benchmark\n";
      }
    }
  }
  f.close();
  auto rep = lmcfg::db::compile_upid_db(dir.string(), out);
  if (!rep.ok() || !rep.written) {
    for (const auto& d : rep.diagnostics) std::fprintf(stderr, "%s\n", d.str().c_str());
    return false;
  }
  return true;
}

// --- the shipped database ---------------------------------------------------

void BM_Open(benchmark::State& state) {
  for (auto _ : state) {
    auto r = Database::open(LMCFG_DB_PATH);
    benchmark::DoNotOptimize(r.ok());
  }
}
BENCHMARK(BM_Open)->Unit(benchmark::kMicrosecond);

// Open, then one find.
void BM_OpenFindCold(benchmark::State& state) {
  for (auto _ : state) {
    auto r = Database::open(LMCFG_DB_PATH);
    benchmark::DoNotOptimize(r->find(0x13A2));
  }
}
BENCHMARK(BM_OpenFindCold)->Unit(benchmark::kMicrosecond);

// Finds cycling through `upids` (each looked up once before the timing, too).
void find_cycle(benchmark::State& state, const Database& d,
                const std::vector<std::uint16_t>& upids) {
  for (auto u : upids) benchmark::DoNotOptimize(d.find(u));
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(d.find(upids[i]));
    if (++i == upids.size()) i = 0;
  }
  state.SetItemsProcessed(state.iterations());
}

// Every UPID of the database in turn.
void BM_FindUpid(benchmark::State& state) {
  const auto& d = db();
  std::vector<std::uint16_t> upids;
  for (const auto& p : d.parameters()) upids.push_back(p.upid);
  find_cycle(state, d, upids);
}
BENCHMARK(BM_FindUpid);

// One UPID, looked up again and again.
void BM_FindCached(benchmark::State& state) {
  const auto& d = db();
  benchmark::DoNotOptimize(d.find(0x13A2));
  for (auto _ : state) benchmark::DoNotOptimize(d.find(0x13A2));
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_FindCached);

// A UPID the database does not have.
void BM_FindAbsent(benchmark::State& state) {
  const auto& d = db();
  benchmark::DoNotOptimize(d.find(0x9999));
  for (auto _ : state) benchmark::DoNotOptimize(d.find(0x9999));
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_FindAbsent);

void BM_SearchName(benchmark::State& state) {
  const auto& d = db();
  for (auto _ : state) benchmark::DoNotOptimize(d.search("voltage"));
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_SearchName);

void BM_Error(benchmark::State& state) {
  const auto& d = db();
  for (auto _ : state) benchmark::DoNotOptimize(d.error("mc", 0x000C));
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_Error);

void BM_DecodeCtEntry(benchmark::State& state) {
  const auto& d = db();
  lmcfg::Bytes e =
      *lmcfg::from_hex("01 A7 FF FF 00 01 40 42 0F 00 20 A1 07 00 40 0D 03 00 40 0D 03 00");
  e.resize(64, 0);
  for (auto _ : state) {
    auto r = lmcfg::db::decode_ct_entry(d, e);
    benchmark::DoNotOptimize(r.ok());
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_DecodeCtEntry);

// --- SQLite's own floor under BM_Open ---------------------------------------
// What every open of this file costs in SQLite alone, opened the way open()
// opens it (read-only, immutable): the connection, then the first statement,
// which parses the schema (every CREATE statement of the file). Each iteration
// also closes the connection, as BM_Open's does.

std::string immutable_uri(const char* path) {
  return std::string("file://") + std::filesystem::absolute(path).string() + "?immutable=1";
}

void BM_SqliteConnect(benchmark::State& state) {
  const std::string uri = immutable_uri(LMCFG_DB_PATH);
  for (auto _ : state) {
    sqlite3* d = nullptr;
    sqlite3_open_v2(uri.c_str(), &d, SQLITE_OPEN_READONLY | SQLITE_OPEN_NOMUTEX | SQLITE_OPEN_URI,
                    nullptr);
    sqlite3_close(d);
  }
}
BENCHMARK(BM_SqliteConnect)->Unit(benchmark::kMicrosecond);

void BM_SqliteConnectReadMeta(benchmark::State& state) {
  const std::string uri = immutable_uri(LMCFG_DB_PATH);
  for (auto _ : state) {
    sqlite3* d = nullptr;
    sqlite3_open_v2(uri.c_str(), &d, SQLITE_OPEN_READONLY | SQLITE_OPEN_NOMUTEX | SQLITE_OPEN_URI,
                    nullptr);
    sqlite3_stmt* s = nullptr;
    sqlite3_prepare_v2(d, "SELECT key, value FROM meta", -1, &s, nullptr);
    while (sqlite3_step(s) == SQLITE_ROW) benchmark::DoNotOptimize(sqlite3_column_text(s, 1));
    sqlite3_finalize(s);
    sqlite3_close(d);
  }
}
BENCHMARK(BM_SqliteConnectReadMeta)->Unit(benchmark::kMicrosecond);

// SQLite's floor under open() reading every table: the connection, then a
// plain scan of each table fetching every text column (what Database::open
// cannot avoid before copying into its vectors).
void BM_SqliteReadAll(benchmark::State& state) {
  const std::string uri = immutable_uri(LMCFG_DB_PATH);
  static constexpr const char* kTables[] = {"meta",
                                            "profiles",
                                            "parameters",
                                            "enum_labels",
                                            "errors",
                                            "motion_commands",
                                            "motion_command_params",
                                            "devicenet_parameters",
                                            "devicenet_parameter_labels",
                                            "devicenet_commands",
                                            "devicenet_command_labels"};
  for (auto _ : state) {
    sqlite3* d = nullptr;
    sqlite3_open_v2(uri.c_str(), &d, SQLITE_OPEN_READONLY | SQLITE_OPEN_NOMUTEX | SQLITE_OPEN_URI,
                    nullptr);
    for (const char* t : kTables) {
      sqlite3_stmt* s = nullptr;
      sqlite3_prepare_v2(d, (std::string("SELECT * FROM ") + t).c_str(), -1, &s, nullptr);
      while (sqlite3_step(s) == SQLITE_ROW)
        for (int i = 0, n = sqlite3_column_count(s); i < n; ++i)
          if (sqlite3_column_type(s, i) == SQLITE_TEXT)
            benchmark::DoNotOptimize(sqlite3_column_bytes(s, i));
      sqlite3_finalize(s);
    }
    sqlite3_close(d);
  }
}
BENCHMARK(BM_SqliteReadAll)->Unit(benchmark::kMicrosecond);

// --- the large synthetic database (20,000 rows) -----------------------------

void BM_OpenLarge(benchmark::State& state) {
  for (auto _ : state) {
    auto r = Database::open(g_large_path);
    benchmark::DoNotOptimize(r.ok());
  }
  state.counters["rows"] = kLargeRows;
}
BENCHMARK(BM_OpenLarge)->Unit(benchmark::kMicrosecond);

void BM_OpenFindColdLarge(benchmark::State& state) {
  for (auto _ : state) {
    auto r = Database::open(g_large_path);
    benchmark::DoNotOptimize(r->find(0x2A0B));
  }
  state.counters["rows"] = kLargeRows;
}
BENCHMARK(BM_OpenFindColdLarge)->Unit(benchmark::kMicrosecond);

// Open, then a search by name over the whole parameter table.
void BM_OpenSearchLarge(benchmark::State& state) {
  for (auto _ : state) {
    auto r = Database::open(g_large_path);
    benchmark::DoNotOptimize(r->search("parameter 12345"));
  }
  state.counters["rows"] = kLargeRows;
}
BENCHMARK(BM_OpenSearchLarge)->Unit(benchmark::kMicrosecond);

// Finds over every UPID of the large database.
void BM_FindUpidLarge(benchmark::State& state) {
  const auto& d = large_db();
  std::vector<std::uint16_t> upids;
  for (unsigned l = 0; l < 4; ++l)
    for (unsigned i = 0; i < 0x0F00; ++i)
      upids.push_back(static_cast<std::uint16_t>(l * 0x1000 + i));
  find_cycle(state, d, upids);
}
BENCHMARK(BM_FindUpidLarge);

void BM_SearchNameLarge(benchmark::State& state) {
  const auto& d = large_db();
  for (auto _ : state) benchmark::DoNotOptimize(d.search("parameter 12345"));
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_SearchNameLarge)->Unit(benchmark::kMicrosecond);

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 2;
  g_tmp = std::filesystem::temp_directory_path() / ("lmcfg-bench-db-" + std::to_string(::getpid()));
  g_large_path = (g_tmp / "large.sqlite").string();
  if (!build_large_db(g_tmp / "src", g_large_path)) {
    std::fprintf(stderr, "lmcfg_bench_db: the synthetic database does not compile\n");
    std::filesystem::remove_all(g_tmp);
    return 1;
  }
  std::printf("lmcfg_bench_db: shipped database %s; synthetic database %s (%d parameter rows)\n",
              LMCFG_DB_PATH, g_large_path.c_str(), kLargeRows);
  std::fflush(stdout);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  std::error_code ec;
  std::filesystem::remove_all(g_tmp, ec);
  return 0;
}
