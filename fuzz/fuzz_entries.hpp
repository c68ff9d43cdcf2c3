#pragma once
// Entry points shared by the libFuzzer targets (fuzz/fuzz_*.cpp) and the
// regression test (tests/config/test_reliability_regressions.cpp), so every input a
// fuzzer ever crashed on is replayed by the normal test suite with gcc.
// Each entry must return normally for any input; an invariant violation calls
// fuzz_fail(), which aborts: a crash for libFuzzer, and a loudly failed test
// run for the regression test, which calls the entries directly.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <string>
#include <string_view>

#include "client/client.hpp"
#include "codec/frame.hpp"
#include "config/config_io.hpp"
#include "transport/transport.hpp"

namespace lmcfg::fuzz {

[[noreturn]] inline void fuzz_fail(const char* what, const std::string& detail = {}) {
  std::fprintf(stderr, "fuzz invariant violated: %s %s\n", what, detail.c_str());
  std::abort();
}

// Byte 0 picks the checksum configuration, byte 1 the chunk size the stream is
// fed in; the rest is the stream. Every telegram the decoder returns must
// re-encode to bytes that decode to the same telegram; the decoder must
// consume everything (no bytes left after flush_idle).
inline void decoder_entry(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return;
  codec::ChecksumConfig cfg;
  cfg.mode = static_cast<codec::ChecksumMode>(data[0] % 3);
  cfg.coverage = static_cast<codec::ChecksumCoverage>((data[0] / 3) % 3);
  cfg.crc_init = (data[0] & 0x80) ? 0x0000 : 0xFFFF;
  const std::size_t step = 1 + data[1] % 64;
  codec::StreamDecoder dec(cfg);
  ByteView rest(data + 2, size - 2);
  std::size_t frames = 0;
  for (std::size_t off = 0; off < rest.size(); off += step) {
    dec.feed(rest.subspan(off, std::min(step, rest.size() - off)));
    while (auto item = dec.next()) {
      if (!item->ok()) continue;
      const codec::Telegram& t = item->value();
      ++frames;
      auto wire = codec::encode(t, cfg);
      if (!wire.ok()) fuzz_fail("decoded telegram does not re-encode", wire.error().message);
      auto back = codec::decode(*wire, cfg);
      if (!back.ok() || !(back.value() == t))
        fuzz_fail("re-encoded telegram does not decode to itself");
    }
  }
  (void)dec.flush_idle();
  if (dec.buffered() != 0) fuzz_fail("bytes left in the decoder after flush_idle");
  // One-shot decode of the whole input never throws either.
  (void)codec::decode(rest, cfg);
  (void)frames;
}

// A configuration file reader: whatever it accepts must write back out
// (validation included) and read again, in its own format and in the other.
inline void config_entry(const std::uint8_t* data, std::size_t size, config::FileFormat format) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  auto cfg = config::read_config_text(
      text, format == config::FileFormat::json ? "fuzz.json" : "fuzz.xml", format);
  if (!cfg.ok()) {
    if (cfg.error().message.empty()) fuzz_fail("reader error without a message");
    return;
  }
  auto out = config::write_config_text(*cfg, format);
  if (!out.ok()) fuzz_fail("accepted configuration does not write back", out.error().message);
  auto again = config::read_config_text(*out, "fuzz-roundtrip", format);
  if (!again.ok()) fuzz_fail("written configuration does not read back", again.error().message);
  // `lmcfg convert` takes any accepted file to the other format.
  const auto other =
      format == config::FileFormat::json ? config::FileFormat::xml : config::FileFormat::json;
  auto converted = config::write_config_text(*cfg, other);
  if (!converted.ok())
    fuzz_fail("accepted configuration does not convert", converted.error().message);
  auto back = config::read_config_text(*converted, "fuzz-converted", other);
  if (!back.ok()) fuzz_fail("converted configuration does not read back", back.error().message);
}

inline void json_entry(const std::uint8_t* data, std::size_t size) {
  config_entry(data, size, config::FileFormat::json);
}
inline void xml_entry(const std::uint8_t* data, std::size_t size) {
  config_entry(data, size, config::FileFormat::xml);
}

// A transport whose "drive" answers arbitrary bytes: the input is split into
// answers at each 0xFE 0xFD marker pair (the marker is dropped); every write
// queues the next answer, read_some hands it out (empty = silence).
class FuzzTransport final : public transport::Transport {
 public:
  FuzzTransport(const std::uint8_t* data, std::size_t size) {
    Bytes cur;
    for (std::size_t i = 0; i < size; ++i) {
      if (i + 1 < size && data[i] == 0xFE && data[i + 1] == 0xFD) {
        answers_.push_back(std::move(cur));
        cur.clear();
        ++i;
        continue;
      }
      cur.push_back(data[i]);
    }
    answers_.push_back(std::move(cur));
  }
  Result<void> write(ByteView) override {
    if (++writes_ > 4000) return Error(Errc::link_closed, "fuzz: write budget used up");
    if (!answers_.empty()) {
      pending_.insert(pending_.end(), answers_.front().begin(), answers_.front().end());
      answers_.pop_front();
    }
    return {};
  }
  Result<Bytes> read_some(transport::Millis) override {
    if (++reads_ > 20000) return Error(Errc::link_closed, "fuzz: read budget used up");
    Bytes out;
    out.swap(pending_);
    return out;
  }
  void discard_input() override {}
  std::string describe() const override { return "fuzz"; }

 private:
  std::deque<Bytes> answers_;
  Bytes pending_;
  std::size_t writes_ = 0, reads_ = 0;
};

// Byte 0 picks the operation, byte 1 the checksum mode; the rest are answers.
// Every client call must return (value or Error with a message), never crash
// or hang, and block reads must return exactly the size they were asked for.
inline void client_entry(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return;
  const std::uint8_t op = data[0];
  client::ClientOptions o;
  o.timeout = transport::Millis(1);
  o.settle = transport::Millis(1);
  o.checksum.mode = static_cast<codec::ChecksumMode>(data[1] % 3);
  FuzzTransport link(data + 2, size - 2);
  client::LinrsClient c(link, o);
  auto check = [](const auto& r) {
    if (!r.ok() && r.error().message.empty()) fuzz_fail("client error without a message");
  };
  switch (op % 12) {
    case 0:
      check(c.read_rom(0x13A2));
      break;
    case 1:
      check(c.write_rom(0x13A2, 16));
      break;
    case 2:
      check(c.modified_list(1 + (op >> 4) % 4));
      break;
    case 3:
      check(c.upid_list(1 + (op >> 4) % 4));
      break;
    case 4: {
      auto r = c.read_curve(1);
      check(r);
      if (r.ok() && r.value()) {
        auto s = c.curve_sizes(1);
        (void)s;
      }
      break;
    }
    case 5: {
      auto r = c.read_curve_data(1, static_cast<std::uint16_t>(op));
      check(r);
      if (r.ok() && r->size() != op) fuzz_fail("block read returned the wrong size");
      break;
    }
    case 6:
      check(c.ct_defined_entries());
      break;
    case 7: {
      auto r = c.read_ct_entry(2);
      check(r);
      if (r.ok() && (r->empty() || r->size() > 0xFFFF))
        fuzz_fail("CT entry read returned an impossible size");
      break;
    }
    case 8: {
      const Bytes info(70, 0x11), data_block(20, 0x22);
      check(c.write_curve(3, info, data_block));
      break;
    }
    case 9:
      check(c.write_ct_entry(4, Bytes(64, 0x33)));
      break;
    case 10: {
      check(c.actual_error_text());
      check(c.error_counters());
      check(c.error_log_entry(1));
      break;
    }
    case 11: {
      check(c.default_response());
      check(c.stop_mc());
      check(c.save_curves());
      check(c.reset());
      break;
    }
  }
}

}  // namespace lmcfg::fuzz
