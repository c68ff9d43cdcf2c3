// UPID database: open time (loads every table into memory) and lookup rates.
// Uses the database built from upid-db/ (LMCFG_DB_PATH).
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>

#include "common/bytes.hpp"
#include "db/ct_entry.hpp"
#include "db/database.hpp"

namespace {

using lmcfg::db::Database;

const Database& db() {
  static const Database d = [] {
    auto r = Database::open(LMCFG_DB_PATH);
    if (!r) {
      std::fprintf(stderr, "%s\n", r.error().message.c_str());
      std::exit(1);
    }
    return std::move(r).value();
  }();
  return d;
}

void BM_Open(benchmark::State& state) {
  for (auto _ : state) {
    auto r = Database::open(LMCFG_DB_PATH);
    benchmark::DoNotOptimize(r.ok());
  }
}
BENCHMARK(BM_Open)->Unit(benchmark::kMicrosecond);

void BM_FindUpid(benchmark::State& state) {
  const auto& d = db();
  std::vector<std::uint16_t> upids;
  for (const auto& p : d.parameters()) upids.push_back(p.upid);
  upids.push_back(0x9999);  // a miss
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(d.find(upids[i]));
    if (++i == upids.size()) i = 0;
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_FindUpid);

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

}  // namespace

BENCHMARK_MAIN();
