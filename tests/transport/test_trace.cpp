// Trace decorator: file format and the in-memory sink.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <deque>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "transport/transport.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace transport_test_trace {

using namespace lmcfg;
using namespace lmcfg::transport;
using namespace std::chrono_literals;

namespace {

// Returns queued answers one per read_some; records writes.
class ScriptedTransport : public Transport {
 public:
  std::deque<Bytes> answers;
  Bytes written;
  int discards = 0;

  Result<void> write(ByteView bytes) override {
    written.insert(written.end(), bytes.begin(), bytes.end());
    return {};
  }
  Result<Bytes> read_some(Millis) override {
    if (answers.empty()) return Bytes{};
    Bytes b = std::move(answers.front());
    answers.pop_front();
    return b;
  }
  void discard_input() override { ++discards; }
  std::string describe() const override { return "scripted"; }
  double byte_time_us() const override { return 173.6; }
};

std::vector<std::string> read_lines(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::vector<std::string> lines;
  std::string line;
  for (int i = 0; i < 1000 && std::getline(in, line); ++i) lines.push_back(line);
  return lines;
}

// "<digits>.<6 digits> TX|RX XX XX ..." with upper-case hex pairs.
bool well_formed(const std::string& l) {
  const auto dot = l.find('.');
  if (dot == std::string::npos || dot == 0 || l.size() < dot + 7 + 3) return false;
  for (std::size_t i = 0; i < dot; ++i)
    if (l[i] < '0' || l[i] > '9') return false;
  for (std::size_t i = dot + 1; i < dot + 7; ++i)
    if (l[i] < '0' || l[i] > '9') return false;
  const std::string dir = l.substr(dot + 7, 3);
  if (dir != " TX" && dir != " RX") return false;
  const std::string hex = l.substr(dot + 10);
  if (hex.empty() || hex.size() % 3 != 0) return false;
  for (std::size_t i = 0; i < hex.size(); i += 3) {
    const auto is_hex = [](char c) { return (c >= '0' && c <= '9') || (c >= 'A' && c <= 'F'); };
    if (hex[i] != ' ' || !is_hex(hex[i + 1]) || !is_hex(hex[i + 2])) return false;
  }
  return true;
}

std::filesystem::path temp_trace(const char* name) {
  return std::filesystem::temp_directory_path() /
         ("lmcfg-test-" + std::to_string(::getpid()) + "-" + name + ".trace");
}

}  // namespace

TEST_CASE("file trace writes one timestamped hex line per chunk", "[transport]") {
  const auto path = temp_trace("format");
  {
    auto sink = make_file_trace(path.string());
    REQUIRE(sink != nullptr);
    auto inner = std::make_unique<ScriptedTransport>();
    inner->answers = {Bytes{0x01, 0x00, 0x05, 0x02, 0x00, 0x03, 0x04}, Bytes{}, Bytes{0xAB}};
    auto* raw = inner.get();
    auto t = make_traced(std::move(inner), std::shared_ptr<TraceSink>(std::move(sink)));
    CHECK(t->describe() == "scripted");
    CHECK(t->byte_time_us() == 173.6);

    REQUIRE(t->write(Bytes{0x01, 0x11, 0x05, 0x02, 0x00, 0x03, 0xA2, 0x13, 0x04}).ok());
    REQUIRE(t->write(Bytes{}).ok());  // empty chunks are not traced
    auto a = t->read_some(10ms);
    REQUIRE(a.ok());
    auto b = t->read_some(10ms);  // timeout: not traced
    REQUIRE(b.ok());
    CHECK(b->empty());
    t->discard_input();
    CHECK(raw->discards == 1);
    auto c = t->read_some(10ms);
    REQUIRE(c.ok());

    // Already on disk while the transport is still open (survives a crash).
    const auto lines = read_lines(path);
    REQUIRE(lines.size() == 3);
    for (const auto& l : lines) CHECK(well_formed(l));
    CHECK_FALSE(well_formed("1.23456 TX 01"));
    CHECK_FALSE(well_formed("1.234567 TX 0a"));
    CHECK_FALSE(well_formed("1.234567 XX 01"));
    CHECK(lines[0].substr(lines[0].find(' ')) == " TX 01 11 05 02 00 03 A2 13 04");
    CHECK(lines[1].substr(lines[1].find(' ')) == " RX 01 00 05 02 00 03 04");
    CHECK(lines[2].substr(lines[2].find(' ')) == " RX AB");
    double prev = 0.0;
    for (const auto& l : lines) {
      const double s = std::stod(l.substr(0, l.find(' ')));
      CHECK(s >= prev);
      CHECK(s < 60.0);
      prev = s;
    }
  }
  std::filesystem::remove(path);
}

TEST_CASE("file trace open errors", "[transport]") {
  CHECK(make_file_trace("/nonexistent-lmcfg-dir/x.trace") == nullptr);
  auto r = open_file_trace("/nonexistent-lmcfg-dir/x.trace");
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == Errc::file_error);
  CHECK(r.error().message ==
        "cannot open trace file /nonexistent-lmcfg-dir/x.trace: No such file or directory");
}

TEST_CASE("memory trace records writes and reads in order", "[transport]") {
  auto mem = std::make_shared<MemoryTrace>();
  auto inner = std::make_unique<ScriptedTransport>();
  inner->answers = {Bytes{0x10, 0x20}, Bytes{0x30}};
  auto t = make_traced(std::move(inner), mem);

  CHECK(mem->count(true) == 0);  // "zero write telegrams on the wire"
  REQUIRE(t->read_some(1ms).ok());
  CHECK(mem->count(true) == 0);
  CHECK(mem->count(false) == 1);

  REQUIRE(t->write(Bytes{0x01, 0x02}).ok());
  REQUIRE(t->read_some(1ms).ok());
  REQUIRE(t->read_some(1ms).ok());  // empty, not recorded
  const auto recs = mem->records();
  REQUIRE(recs.size() == 3);
  CHECK(recs[0] == TraceRecord{false, Bytes{0x10, 0x20}});
  CHECK(recs[1] == TraceRecord{true, Bytes{0x01, 0x02}});
  CHECK(recs[2] == TraceRecord{false, Bytes{0x30}});
  CHECK(mem->count(true) == 1);
  CHECK(mem->all_bytes(false) == Bytes{0x10, 0x20, 0x30});
  CHECK(mem->all_bytes(true) == Bytes{0x01, 0x02});
  mem->clear();
  CHECK(mem->records().empty());
}

TEST_CASE("make_traced without a sink returns the transport itself", "[transport]") {
  auto inner = std::make_unique<ScriptedTransport>();
  Transport* raw = inner.get();
  auto t = make_traced(std::move(inner), nullptr);
  CHECK(t.get() == raw);
}

}  // namespace transport_test_trace
