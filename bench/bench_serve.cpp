// lmcfg serve at plant scale: the service (serve::Service with its HTTP server
// on 127.0.0.1, as `lmcfg serve` runs them) over 32 lines of 8 simulated
// drives, each line a `sim:` port of 8 state files served in real time (57600
// Bd wire time and the drives' modelled turnaround, sleeping as a serial line
// waits). Schedule: backup_every 1h, status_every S (default 90 s). Prints:
//   - the CPU time the process used in an idle window between runs
//     (getrusage, user + system), as a share of one core;
//   - the peak resident memory (ru_maxrss; the simulated drives live in the
//     same process while a line runs, so this is an upper bound for the service);
//   - the time from a drift (a parameter of the last drive of a line changed
//     in its state file right after a drift check) to its `drift` event, and
//     the bound one status_every plus that line's read time.
// Not part of ctest; figures in docs/measurements.md.
#include <sys/resource.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "db/database.hpp"
#include "link/session.hpp"
#include "serve/http.hpp"
#include "serve/service.hpp"
#include "sim/state_file.hpp"

using namespace lmcfg;
namespace fs = std::filesystem;
using Steady = std::chrono::steady_clock;

namespace {

double cpu_seconds() {
  rusage u{};
  ::getrusage(RUSAGE_SELF, &u);
  auto s = [](const timeval& t) {
    return static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_usec) / 1e6;
  };
  return s(u.ru_utime) + s(u.ru_stime);
}

long peak_rss_kb() {
  rusage u{};
  ::getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss;
}

// VmRSS of /proc/self/status, in kB.
long rss_kb() {
  std::ifstream in("/proc/self/status");
  std::string key;
  long value = 0;
  while (in >> key) {
    if (key == "VmRSS:") {
      in >> value;
      return value;
    }
    in.ignore(1 << 16, '\n');
  }
  return 0;
}

// The demo axis at `macid`, with UPID 0010h at `value`.
void write_axis(const fs::path& path, int macid, int value) {
  std::ifstream in(LMCFG_SOURCE_DIR "/tests/fixtures/sim/commissioned-axis.json");
  std::stringstream text;
  text << in.rdbuf();
  auto j = nlohmann::json::parse(text.str());
  j["macid"] = macid;
  for (auto& p : j["parameters"])
    if (p["upid"] == "0010") p["rom"] = p["ram"] = value;
  std::ofstream(path) << j.dump(1);
}

double metric(const std::string& text, const std::string& name) {
  const auto at = text.find("\n" + name + " ");
  return at == std::string::npos ? -1 : std::atof(text.c_str() + at + name.size() + 2);
}

}  // namespace

int main(int argc, char** argv) {
  const int lines = argc > 1 ? std::atoi(argv[1]) : 32;
  const int per_line = argc > 2 ? std::atoi(argv[2]) : 8;
  const int status_s = argc > 3 ? std::atoi(argv[3]) : 90;
  const fs::path tmp =
      fs::temp_directory_path() / ("lmcfg-bench-serve-" + std::to_string(::getpid()));
  fs::remove_all(tmp);
  fs::create_directories(tmp / "states");

  std::string toml =
      "[schedule]\nbackup_every = \"1h\"\nstatus_every = \"" + std::to_string(status_s) + "s\"\n";
  for (int l = 0; l < lines; ++l) {
    std::string port = "sim:";
    std::string drives;
    for (int i = 0; i < per_line; ++i) {
      const fs::path state =
          tmp / "states" / ("l" + std::to_string(l) + "d" + std::to_string(i) + ".json");
      write_axis(state, 0x11 + i, 5);
      port += (i ? "," : "") + state.string();
      drives += "[[line.drive]]\nname = \"line" + std::to_string(l + 1) + "/axis" +
                std::to_string(i + 1) + "\"\nid = " + std::to_string(0x11 + i) + "\n";
    }
    toml += "[[line]]\nname = \"line" + std::to_string(l + 1) + "\"\nport = \"" + port + "\"\n" +
            drives;
  }
  auto inv = fleet::parse_inventory(toml, "bench.toml");
  if (!inv.ok()) {
    std::fprintf(stderr, "%s\n", inv.error().message.c_str());
    return 2;
  }
  link::register_scheme("sim", sim::state_file_link_factory());
  auto db = db::Database::open(LMCFG_DB_PATH);

  std::mutex mu;
  std::optional<Steady::time_point> drift_seen;
  std::atomic<int> events{0};
  serve::ServiceOptions so;
  so.inventory = *inv;
  so.archive = (tmp / "archive").string();
  for (const auto& l : inv->lines) {
    link::LinkSpec link;
    link.port = *link::parse_port(l.port);
    link.real_time_sim = true;
    so.links.push_back(link);
  }
  if (db.ok()) so.db = *db;
  so.notify = [&](const serve::Json& e) {
    ++events;
    std::lock_guard<std::mutex> lock(mu);
    if (e["event"] == "drift" && !drift_seen) drift_seen = Steady::now();
  };
  auto service = serve::Service::create(std::move(so));
  if (!service.ok()) {
    std::fprintf(stderr, "%s\n", service.error().message.c_str());
    return 2;
  }
  serve::HttpOptions ho;
  ho.listen = {"127.0.0.1", 0};
  serve::HttpServer http(**service, ho);
  if (!http.bind().ok()) return 2;
  std::thread http_thread([&] { http.serve(); });
  std::atomic<bool> stop{false};
  // The CLI's loop: a scheduling pass every 200 ms.
  std::thread ticker([&] {
    while (!stop) {
      (*service)->tick(serve::Clock::now());
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
  });
  // Waits until every line has run `n` jobs; the seconds waited.
  auto wait_runs = [&](int n) {
    const auto t0 = Steady::now();
    for (;;) {
      const std::string m = (*service)->metrics();
      int done = 0;
      for (int l = 0; l < lines; ++l)
        done += metric(m, "lmcfg_line_runs_total{line=\"line" + std::to_string(l + 1) + "\"}") >= n;
      if (done == lines) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    return std::chrono::duration<double>(Steady::now() - t0).count();
  };
  std::printf(
      "lmcfg serve, %d line(s) of %d drive(s), sim: ports in real time, status_every %d s\n", lines,
      per_line, status_s);
  const auto start = Steady::now();
  const double first = wait_runs(2);  // the first backup, then the first drift check
  std::printf("  first backup + drift check of every line: %.1f s\n", first);

  // Idle: from now until shortly before the next drift check is due.
  const auto next = (*service)->next_status();
  const double until_next = std::chrono::duration<double>(*next - serve::Clock::now()).count();
  const double window = until_next - 2;
  if (window < 5) {
    std::fprintf(stderr, "idle window %.1f s too short: give a longer status_every\n", window);
    stop = true;
    ticker.join();
    http.stop();
    http_thread.join();
    return 1;
  }
  const double cpu0 = cpu_seconds();
  const auto w0 = Steady::now();
  std::this_thread::sleep_for(std::chrono::duration<double>(window));
  const double idle_cpu = cpu_seconds() - cpu0;
  const double idle_wall = std::chrono::duration<double>(Steady::now() - w0).count();
  const long rss_idle = rss_kb();
  std::printf("  idle between runs: %.3f s CPU in %.1f s = %.3f %% of a core (goal < 2 %%)\n",
              idle_cpu, idle_wall, 100 * idle_cpu / idle_wall);
  std::printf("  resident now: %.1f MB\n", static_cast<double>(rss_idle) / 1024.0);

  // The second drift check runs; right after it, a drift on the last drive of line 1.
  wait_runs(3);
  const std::string m = (*service)->metrics();
  const double line_read = metric(m, "lmcfg_line_last_run_seconds{line=\"line1\"}");
  write_axis(tmp / "states" / ("l0d" + std::to_string(per_line - 1) + ".json"), 0x11 + per_line - 1,
             7);
  const auto drift_at = Steady::now();
  const auto drift_wall = serve::Clock::now();
  const auto next_due = (*service)->next_status();
  for (;;) {
    {
      std::lock_guard<std::mutex> lock(mu);
      if (drift_seen) break;
    }
    if (Steady::now() - drift_at > std::chrono::seconds(3 * status_s + 120)) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  double latency = -1;
  {
    std::lock_guard<std::mutex> lock(mu);
    if (drift_seen) latency = std::chrono::duration<double>(*drift_seen - drift_at).count();
  }
  const double to_due = std::chrono::duration<double>(*next_due - drift_wall).count();
  std::printf(
      "  drift -> drift event: %.1f s (the check was due %.1f s after the drift; line 1's read "
      "%.1f s; bound status_every + read = %.1f s)\n",
      latency, to_due, line_read, status_s + line_read);
  std::printf("  peak resident (ru_maxrss, simulated drives included): %.1f MB (goal < 64 MB)\n",
              static_cast<double>(peak_rss_kb()) / 1024.0);
  std::printf("  total %.0f s, %d event(s)\n",
              std::chrono::duration<double>(Steady::now() - start).count(), events.load());
  stop = true;
  ticker.join();
  http.stop();
  http_thread.join();
  (*service)->stop();
  service->reset();
  fs::remove_all(tmp);
  const bool ok = latency >= 0 && latency <= status_s + line_read + 1 &&
                  100 * idle_cpu / idle_wall < 2 && peak_rss_kb() < 64 * 1024;
  return ok ? 0 : 1;
}
