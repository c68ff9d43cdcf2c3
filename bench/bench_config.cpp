// Read and write of a large drive configuration (5,000 parameters, 100 curves
// of 500 setpoints, 255 command table entries) in both file formats.
#include <benchmark/benchmark.h>

#include "common/layers.hpp"
#include "config/config_io.hpp"

namespace {
using namespace lmcfg;
using namespace lmcfg::config;

DriveConfig big_config() {
  DriveConfig c;
  c.identity.macid = "bench";
  c.identity.captured_at = "2024-01-01T00:00:00Z";
  c.identity.labels = {{"machine", "bench"}, {"axis", "X"}};
  c.scope.parameters = ParamSet::full;
  // 5,000 parameters: 1,250 per layer.
  std::uint32_t x = 12345;
  for (int l = 1; l <= lmcfg::layers::kCount; ++l) {
    const auto base = lmcfg::layers::base_upid(l);
    for (std::uint16_t i = 0; i < 1250; ++i) {
      Parameter p;
      p.upid = static_cast<std::uint16_t>(base + i);
      x = x * 1103515245u + 12345u;
      p.value = x;
      p.type = static_cast<std::uint8_t>(i % 7);
      if (i % 4 == 0) {
        p.name = "Parameter " + std::to_string(i);
        p.scaled = std::to_string(x % 1000) + ".5";
        p.unit = "mm";
      }
      c.layer(l).push_back(std::move(p));
    }
  }
  // 100 curves of 500 setpoints (70-byte info block, 4 bytes per setpoint).
  for (std::uint16_t id = 1; id <= 100; ++id) {
    Curve cv;
    cv.id = id;
    cv.info.assign(70, 0);
    auto put16 = [&](std::size_t off, std::uint16_t v) {
      cv.info[off] = static_cast<std::uint8_t>(v & 0xFF);
      cv.info[off + 1] = static_cast<std::uint8_t>(v >> 8);
    };
    put16(0, 70);
    put16(2, 0x0003);
    put16(4, 500);
    put16(6, 4);
    const char name[] = "BenchCurve";
    for (std::size_t i = 0; i + 1 < sizeof(name); ++i)
      cv.info[8 + i] = static_cast<std::uint8_t>(name[i]);
    put16(30, id);
    for (int s = 0; s < 500; ++s) put_u32le(cv.data, static_cast<std::uint32_t>(s * 2000));
    c.curves.push_back(std::move(cv));
  }
  // 255 command table entries of 64 bytes.
  for (std::uint32_t id = 0; id < 255; ++id) {
    CtEntry e;
    e.id = id;
    for (std::uint32_t i = 0; i < 64; ++i)
      e.raw.push_back(static_cast<std::uint8_t>((id + i) & 0xFF));
    c.ct_entries.push_back(std::move(e));
  }
  return c;
}

const DriveConfig& config() {
  static const DriveConfig c = big_config();
  return c;
}

void write_bench(benchmark::State& state, FileFormat f) {
  std::size_t bytes = 0;
  for (auto _ : state) {
    auto r = write_config_text(config(), f);
    if (!r.ok()) {
      state.SkipWithError(r.error().message.c_str());
      return;
    }
    bytes = r->size();
    benchmark::DoNotOptimize(r->data());
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * bytes));
  state.counters["file_bytes"] = static_cast<double>(bytes);
}

void read_bench(benchmark::State& state, FileFormat f) {
  auto text = write_config_text(config(), f);
  if (!text.ok()) {
    state.SkipWithError(text.error().message.c_str());
    return;
  }
  for (auto _ : state) {
    auto r = read_config_text(*text, "bench", f);
    if (!r.ok()) {
      state.SkipWithError(r.error().message.c_str());
      return;
    }
    benchmark::DoNotOptimize(r->curves.data());
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * text->size()));
}

void BM_WriteJson(benchmark::State& s) { write_bench(s, FileFormat::json); }
void BM_WriteXml(benchmark::State& s) { write_bench(s, FileFormat::xml); }
void BM_ReadJson(benchmark::State& s) { read_bench(s, FileFormat::json); }
void BM_ReadXml(benchmark::State& s) { read_bench(s, FileFormat::xml); }

BENCHMARK(BM_WriteJson)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ReadJson)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_WriteXml)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ReadXml)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
