// lmcfg fleet at plant scale: 32 lines of 8 simulated drives each, every line
// behind its own loopback TCP gateway serving in real time (57600 Bd wire time
// and the drives' modelled turnaround). Prints the wall time of one line alone
// (three sample lines; all lines are identical), of `fleet backup` over all 32
// lines, the commit phase of that run, and a commit of 256 changed files.
// Not part of ctest; figures in docs/measurements.md.
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <thread>

#include "db/database.hpp"
#include "fleet/fleet.hpp"
#include "sim/server.hpp"
#include "sim/state_file.hpp"

using namespace lmcfg;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

double since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// One RS485 line of drives behind a loopback TCP gateway, served in real time.
class Gateway {
 public:
  Gateway(const sim::DriveState& base, int drives) {
    for (int i = 0; i < drives; ++i) {
      auto s = base;
      s.macid = static_cast<std::uint8_t>(0x11 + i);
      drives_.push_back(std::make_unique<sim::Drive>(std::move(s)));
    }
    auto fd = sim::listen_tcp("127.0.0.1", 0, port_);
    if (!fd.ok()) throw std::runtime_error(fd.error().message);
    listen_ = std::move(fd).value();
    thread_ = std::thread([this] { run(); });
  }
  ~Gateway() {
    stop_ = true;
    thread_.join();
  }
  std::string port() const { return "tcp://127.0.0.1:" + std::to_string(port_); }

 private:
  void run() {
    std::vector<sim::Drive*> line;
    for (auto& d : drives_) line.push_back(d.get());
    sim::ServeOptions o;
    o.real_time = true;
    o.should_stop = [this] { return stop_.load(); };
    while (!stop_) {
      auto c = sim::accept_client(listen_.get(), transport::Millis(50));
      if (!c.ok() || !c->valid()) continue;
      transport::FdTransport t(std::move(c).value(), "gateway");
      (void)sim::serve_bus(line, t, o);
    }
  }
  std::vector<std::unique_ptr<sim::Drive>> drives_;
  transport::UniqueFd listen_;
  std::uint16_t port_ = 0;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

fleet::Inventory inventory(const std::vector<std::unique_ptr<Gateway>>& gws, std::size_t first,
                           std::size_t count, int drives) {
  fleet::Inventory inv;
  inv.path = "bench.toml";
  for (std::size_t l = first; l < first + count; ++l) {
    fleet::LineEntry line;
    line.name = "line" + std::to_string(l + 1);
    line.port = gws[l]->port();
    for (int i = 0; i < drives; ++i) {
      fleet::DriveEntry d;
      d.name = line.name + "/axis" + std::to_string(i + 1);
      d.id = static_cast<std::uint8_t>(0x11 + i);
      line.drives.push_back(d);
    }
    inv.lines.push_back(std::move(line));
  }
  return inv;
}

struct Timed {
  double wall = 0, read = 0;
  std::size_t failed = 0, drives = 0;
  bool committed = false;
};

Timed backup(const fleet::Inventory& inv, const fs::path& dir, const db::Database& db) {
  fs::remove_all(dir);
  auto archive = fleet::Archive::open(dir.string(), true);
  if (!archive.ok()) throw std::runtime_error(archive.error().message);
  fleet::FleetOptions fo;
  fo.db = db;
  for (const auto& l : inv.lines) {
    link::LinkSpec link;
    link.port = *link::parse_port(l.port);
    fo.links.push_back(link);
  }
  const auto start = Clock::now();
  auto run = fleet::fleet_backup(inv, *archive, fo);
  Timed t;
  t.wall = since(start);
  if (!run.ok()) throw std::runtime_error(run.error().message);
  t.read = run->seconds;
  t.failed = run->count(fleet::DriveResult::Status::failed);
  t.drives = run->drives.size();
  t.committed = run->commit.has_value();
  return t;
}

}  // namespace

int main(int argc, char** argv) {
  const int lines = argc > 1 ? std::atoi(argv[1]) : 32;
  const int per_line = argc > 2 ? std::atoi(argv[2]) : 8;
  auto base = sim::load_state(LMCFG_SOURCE_DIR "/tests/fixtures/sim/commissioned-axis.json");
  if (!base.ok()) {
    std::fprintf(stderr, "%s\n", base.error().message.c_str());
    return 2;
  }
  auto db = db::Database::open(LMCFG_DB_PATH);
  const db::Database& dbp = db.ok() ? *db : db::Database::empty();
  std::vector<std::unique_ptr<Gateway>> gws;
  for (int l = 0; l < lines; ++l) gws.push_back(std::make_unique<Gateway>(*base, per_line));
  const fs::path tmp =
      fs::temp_directory_path() / ("lmcfg-bench-fleet-" + std::to_string(::getpid()));

  std::printf("fleet backup, %d line(s) of %d drive(s), real time over loopback TCP gateways\n",
              lines, per_line);
  double slowest = 0;
  for (std::size_t l :
       {std::size_t{0}, static_cast<std::size_t>(lines / 2), static_cast<std::size_t>(lines - 1)}) {
    auto t = backup(inventory(gws, l, 1, per_line), tmp / "single", dbp);
    std::printf("  line %zu alone: %.2f s wall (%.2f s reading, %zu failed)\n", l + 1, t.wall,
                t.read, t.failed);
    slowest = std::max(slowest, t.wall);
  }
  auto all = backup(inventory(gws, 0, static_cast<std::size_t>(lines), per_line), tmp / "all", dbp);
  std::printf(
      "  all %d lines: %.2f s wall (%.2f s reading, %.3f s writing and committing %zu "
      "files), %zu failed\n",
      lines, all.wall, all.read, all.wall - all.read, all.drives, all.failed);
  std::printf("  ratio all / slowest single line: %.2fx (goal <= 1.2x)\n", all.wall / slowest);

  // A commit where every file changed: rewrite each with one more byte.
  auto archive = fleet::Archive::open((tmp / "all").string(), false);
  std::vector<std::string> paths;
  for (const auto& e : fs::recursive_directory_iterator(tmp / "all")) {
    if (!e.is_regular_file() || e.path().extension() != ".json") continue;
    if (e.path().string().find("/.git/") != std::string::npos) continue;
    std::FILE* f = std::fopen(e.path().c_str(), "a");
    std::fputc('\n', f);
    std::fclose(f);
    paths.push_back(fs::relative(e.path(), tmp / "all").string());
  }
  const auto c0 = Clock::now();
  auto commit = archive->commit(paths, "bench: every file changed\n");
  const double commit_s = since(c0);
  std::printf("  git commit of %zu changed files (libgit2): %.3f s%s\n", paths.size(), commit_s,
              commit.ok() && *commit ? "" : " (FAILED)");
  fs::remove_all(tmp);
  const bool ok = all.failed == 0 && all.committed && all.wall / slowest <= 1.2 && commit.ok();
  return ok ? 0 : 1;
}
