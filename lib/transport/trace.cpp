// Trace decorator and sinks (--trace): one timestamped hex line per chunk.
#include <errno.h>
#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>

#include "transport/pty.hpp"

// The C runtime of Windows (MinGW) has open/write but no close-on-exec (no
// exec), and opens in text mode unless told: the same bytes as on Linux.
#ifndef O_CLOEXEC
#define O_CLOEXEC 0
#endif
#ifndef O_BINARY
#define O_BINARY 0
#endif

namespace lmcfg::transport {

namespace {

// The C runtime's descriptor of the trace file, closed with the sink (not a
// UniqueFd: on Windows that holds a socket, winsock_win32.hpp).
class FileTrace final : public TraceSink {
 public:
  explicit FileTrace(int fd) : fd_(fd), start_(Clock::now()) {}
  FileTrace(const FileTrace&) = delete;
  FileTrace& operator=(const FileTrace&) = delete;
  ~FileTrace() override { ::close(fd_); }

  void record(bool tx, ByteView bytes) override {
    const double secs = std::chrono::duration<double>(Clock::now() - start_).count();
    char stamp[32];
    std::snprintf(stamp, sizeof stamp, "%.6f", secs);
    std::string line = stamp;
    line += tx ? " TX" : " RX";
    if (!bytes.empty()) line += ' ' + to_hex(bytes);
    line += '\n';
    std::lock_guard<std::mutex> lock(mu_);
    // One write(2) per line (O_APPEND): in the kernel as soon as it returns.
    std::size_t off = 0;
    for (int tries = 0; off < line.size() && tries < 100; ++tries) {
      // A line is far below 4 GiB: the count fits Windows' unsigned int too.
      const auto n = ::write(fd_, line.data() + off, static_cast<unsigned>(line.size() - off));
      if (n > 0)
        off += static_cast<std::size_t>(n);
      else if (n < 0 && errno != EINTR)
        break;  // tracing is best effort
    }
  }

 private:
  std::mutex mu_;
  int fd_;
  Clock::time_point start_;
};

class TracedTransport final : public Transport {
 public:
  TracedTransport(std::unique_ptr<Transport> inner, std::shared_ptr<TraceSink> sink)
      : inner_(std::move(inner)), sink_(std::move(sink)) {}

  Result<void> write(ByteView bytes) override {
    if (!bytes.empty()) sink_->record(true, bytes);
    return inner_->write(bytes);
  }
  Result<Bytes> read_some(Millis timeout) override {
    auto r = inner_->read_some(timeout);
    if (r.ok() && !r.value().empty()) sink_->record(false, r.value());
    return r;
  }
  void discard_input() override { inner_->discard_input(); }
  std::string describe() const override { return inner_->describe(); }
  double byte_time_us() const override { return inner_->byte_time_us(); }
  Result<void> reconfigure(const SerialSettings& s) override { return inner_->reconfigure(s); }
  double receive_latency_ms() const override { return inner_->receive_latency_ms(); }
  std::int64_t now_ns() const override { return inner_->now_ns(); }

 private:
  std::unique_ptr<Transport> inner_;
  std::shared_ptr<TraceSink> sink_;
};

}  // namespace

Result<std::unique_ptr<TraceSink>> open_file_trace(const std::string& path) {
  const int fd =
      ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_APPEND | O_CLOEXEC | O_BINARY, 0644);
  if (fd < 0) {
    return Error(Errc::file_error, "cannot open trace file " + path + ": " + std::strerror(errno));
  }
  return std::unique_ptr<TraceSink>(std::make_unique<FileTrace>(fd));
}

std::unique_ptr<TraceSink> make_file_trace(const std::string& path) {
  auto r = open_file_trace(path);
  if (!r.ok()) return nullptr;
  return std::move(r).value();
}

std::unique_ptr<Transport> make_traced(std::unique_ptr<Transport> inner,
                                       std::shared_ptr<TraceSink> sink) {
  if (!sink || !inner) return inner;
  return std::make_unique<TracedTransport>(std::move(inner), std::move(sink));
}

void MemoryTrace::record(bool tx, ByteView bytes) {
  std::lock_guard<std::mutex> lock(mu_);
  records_.push_back(TraceRecord{tx, Bytes(bytes.begin(), bytes.end())});
}

std::vector<TraceRecord> MemoryTrace::records() const {
  std::lock_guard<std::mutex> lock(mu_);
  return records_;
}

std::size_t MemoryTrace::count(bool tx) const {
  std::lock_guard<std::mutex> lock(mu_);
  std::size_t n = 0;
  for (const auto& r : records_) n += r.tx == tx ? 1 : 0;
  return n;
}

Bytes MemoryTrace::all_bytes(bool tx) const {
  std::lock_guard<std::mutex> lock(mu_);
  Bytes out;
  for (const auto& r : records_)
    if (r.tx == tx) out.insert(out.end(), r.bytes.begin(), r.bytes.end());
  return out;
}

void MemoryTrace::clear() {
  std::lock_guard<std::mutex> lock(mu_);
  records_.clear();
}

}  // namespace lmcfg::transport
