// lmcfg_bench_cpu: the CPU side of backup/restore (docs/performance.md). Codec encode and
// decode of single telegrams, stream decoding of a capture of answers, and the
// diff of two heavy configurations (2,500 UPIDs, 20 curves of 500 setpoints,
// 64 command table entries). The wire costs milliseconds per telegram; these
// figures show the CPU is not what a backup waits for.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>

#include "client/client.hpp"
#include "codec/frame.hpp"
#include "codec/messages.hpp"
#include "db/database.hpp"
#include "ops/backup.hpp"
#include "ops/diff.hpp"
#include "sim/link.hpp"
#include "wire_workloads.hpp"

namespace {

using namespace lmcfg;

codec::ChecksumConfig crc() {
  codec::ChecksumConfig c;
  c.mode = codec::ChecksumMode::crc_ccitt;
  return c;
}

void BM_EncodeRequest(benchmark::State& state) {
  const auto cfg = state.range(0) ? crc() : codec::ChecksumConfig{};
  std::uint16_t upid = 0x13A2;
  for (auto _ : state) {
    auto b = codec::encode(codec::make_cfg(0x11, codec::CfgOp::read_rom, upid++), cfg);
    benchmark::DoNotOptimize(b);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}
BENCHMARK(BM_EncodeRequest)->Arg(0)->Arg(1)->ArgName("crc");

void BM_DecodeAnswer(benchmark::State& state) {
  const auto cfg = state.range(0) ? crc() : codec::ChecksumConfig{};
  const Bytes frame = codec::encode(codec::make_id_value(0x11, 0x50, 0, 0x13A2, 40), cfg).value();
  for (auto _ : state) {
    auto t = codec::decode(frame, cfg);
    auto r = codec::decode_id_value(t.value(), 0x50);
    benchmark::DoNotOptimize(r);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}
BENCHMARK(BM_DecodeAnswer)->Arg(0)->Arg(1)->ArgName("crc");

// 1,000 answers back to back (a curve read's worth), fed in 64-byte pieces as a
// serial port would deliver them, decoded as a stream.
void BM_StreamDecode(benchmark::State& state) {
  Bytes capture;
  for (std::uint32_t i = 0; i < 1000; ++i) {
    auto f = codec::encode(codec::make_id_value(0x11, 0x40, 0x04, 1, i)).value();
    capture.insert(capture.end(), f.begin(), f.end());
  }
  for (auto _ : state) {
    codec::StreamDecoder dec;
    std::size_t n = 0;
    for (std::size_t off = 0; off < capture.size(); off += 64) {
      dec.feed(ByteView(capture.data() + off, std::min<std::size_t>(64, capture.size() - off)));
      while (auto t = dec.next()) n += t->ok() ? 1 : 0;
    }
    if (n != 1000) state.SkipWithError("stream decode lost frames");
    benchmark::DoNotOptimize(n);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * 1000);
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * capture.size()));
}
BENCHMARK(BM_StreamDecode);

// Backups of two heavy drives that differ in every modified value, curve and entry.
const config::DriveConfig& heavy(int which, bool full) {
  static config::DriveConfig cache[2][2];
  static bool done[2][2] = {};
  auto& c = cache[which][full];
  if (!done[which][full]) {
    benchwire::HeavySpec spec;
    spec.salt = static_cast<std::uint32_t>(which * 3);
    auto drive = std::make_shared<sim::Drive>(benchwire::heavy_state(spec));
    sim::SimLink link(drive);
    client::LinrsClient cl(link, client::ClientOptions{});
    ops::BackupOptions bo;
    bo.full = full;
    auto r = ops::backup(cl, bo, db::Database::empty());
    if (!r.ok()) {
      std::fprintf(stderr, "backup of the heavy drive failed: %s\n", r.error().message.c_str());
      std::exit(1);
    }
    c = std::move(r).value();
    done[which][full] = true;
  }
  return c;
}

void BM_DiffHeavy(benchmark::State& state) {
  const bool full = state.range(0) != 0;
  const auto& a = heavy(0, full);
  const auto& b = heavy(1, full);
  std::size_t items = 0;
  for (auto _ : state) {
    auto r = ops::diff(a, b, db::Database::empty(), {}, ops::DiffOptions{true, false});
    items = r.items.size();
    benchmark::DoNotOptimize(r);
  }
  state.counters["differences"] = static_cast<double>(items);
  std::size_t params = 0;
  for (const auto& l : a.layers) params += l.size();
  state.counters["parameters"] = static_cast<double>(params);
}
BENCHMARK(BM_DiffHeavy)->Arg(0)->Arg(1)->ArgName("full")->Unit(benchmark::kMillisecond);

void BM_DiffHeavyText(benchmark::State& state) {
  const auto& a = heavy(0, false);
  const auto& b = heavy(1, false);
  const auto r = ops::diff(a, b, db::Database::empty(), {}, ops::DiffOptions{true, false});
  for (auto _ : state) {
    auto s = ops::render_text(r, "a", "b");
    benchmark::DoNotOptimize(s);
  }
}
BENCHMARK(BM_DiffHeavyText)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
