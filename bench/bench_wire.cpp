// lmcfg_bench_wire: backup and restore measured against the protocol's own
// limit (docs/performance.md). For each workload, side by side: the protocol minimum
// (bench/wire_workloads.hpp, docs/performance.md), the tool on the simulator's
// virtual clock with its telegram count, the ratio tool/minimum, the naive
// script a user would write as a ratio to the tool, and wall-clock figures with
// the simulated drive served in real time over a pseudo-terminal / loopback TCP.
//
//   build/bench/lmcfg_bench_wire [--no-realtime] [--no-db] [--fixtures DIR]
//
// Exit status 1 when an operation fails or a virtual-time ratio exceeds 1.05.
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "client/client.hpp"
#include "db/database.hpp"
#include "ops/backup.hpp"
#include "ops/restore.hpp"
#include "sim/link.hpp"
#include "sim/server.hpp"
#include "sim/state_file.hpp"
#include "transport/pty.hpp"
#include "transport/transport.hpp"
#include "wire_workloads.hpp"

using namespace lmcfg;
using benchwire::Cost;

namespace {

constexpr double kLimit = 1.05;

[[noreturn]] void die(const std::string& what, const Error& e) {
  std::fprintf(stderr, "lmcfg_bench_wire: %s: %s\n", what.c_str(), e.message.c_str());
  std::exit(1);
}
template <class T>
T must(Result<T> r, const std::string& what) {
  if (!r.ok()) die(what, r.error());
  return std::move(r).value();
}
void must(Result<void> r, const std::string& what) {
  if (!r.ok()) die(what, r.error());
}

// A simulated drive on its own line (or a client on a shared bus).
struct Rig {
  std::shared_ptr<sim::SimLink> link;
  std::unique_ptr<client::LinrsClient> client;
  std::shared_ptr<sim::Drive> drive;

  explicit Rig(sim::DriveState s) {
    drive = std::make_shared<sim::Drive>(std::move(s));
    link = std::make_shared<sim::SimLink>(drive);
    client::ClientOptions o;
    o.id = drive->macid();
    client = std::make_unique<client::LinrsClient>(*link, o);
  }
  Rig(std::shared_ptr<sim::SimLink> shared, std::uint8_t macid) : link(std::move(shared)) {
    client::ClientOptions o;
    o.id = macid;
    client = std::make_unique<client::LinrsClient>(*link, o);
    drive = link->drive(macid);
  }
};

// Telegrams the master put on the line and virtual time spent by `f`.
template <class F>
Cost measure(sim::SimLink& link, F&& f) {
  const auto t0 = link.clock().now_ns();
  const auto n0 = link.stats().request_telegrams;
  f();
  return Cost{link.stats().request_telegrams - n0, link.clock().now_ns() - t0, 0};
}

struct RestoreRun {
  Cost plan, execute, verify;
  Cost without_verify() const { return plan + execute; }
  Cost total() const { return plan + execute + verify; }
};

// A restore onto a drive alone on its line restores everything: the fixtures'
// LinRS parameters select the same line. Drives sharing a line keep their own.
ops::RestoreOptions alone_on_line() {
  ops::RestoreOptions ro;
  ro.include_comm = true;
  return ro;
}

RestoreRun run_restore(Rig& rig, const config::DriveConfig& file, const db::Database& db,
                       const std::string& what, const ops::RestoreOptions& ro) {
  RestoreRun r;
  ops::Plan plan;
  r.plan = measure(*rig.link, [&] {
    plan = must(ops::plan_restore(*rig.client, file, db, ro), what + ": plan");
  });
  if (!plan.ok()) die(what, Error(Errc::plan_refused, plan.problems.front()));
  r.execute = measure(*rig.link,
                      [&] { must(ops::execute_plan(*rig.client, plan, ro), what + ": execute"); });
  // As ops::run_restore: a plan with nothing to do compared everything already.
  if (plan.nothing_to_do()) return r;
  ops::VerifyReport rep;
  r.verify = measure(*rig.link, [&] {
    rep = must(ops::verify_restore(*rig.client, plan, ro), what + ": verify");
  });
  if (!rep.ok()) die(what, Error(Errc::verify_mismatch, rep.mismatches.front()));
  return r;
}

// What a user would script without the tool: walk every UPID list and read every
// ROM-writable value (lmcfg backup --full does exactly that) ...
config::DriveConfig naive_backup(Rig& rig, const std::string& what) {
  ops::BackupOptions bo;
  bo.full = true;
  bo.ask_drive = false;  // a script records values only
  return must(ops::backup(*rig.client, bo, db::Database::empty()), what + ": naive backup");
}
// ... and restore by defaulting every layer and writing every value back, then
// the tables, then start and reset. No checks, no verify.
void naive_restore(client::Client& c, const config::DriveConfig& full, const std::string& what) {
  must(c.stop_mc(), what);
  for (int l = 1; l <= 4; ++l) must(c.default_layer(l), what);
  for (int l = 1; l <= 4; ++l)
    for (const auto& p : full.layer(l)) must(c.write_rom(p.upid, p.value), what);
  must(c.delete_all_ct(), what);
  for (const auto& e : full.ct_entries)
    must(c.write_ct_entry(static_cast<std::uint16_t>(e.id), e.raw), what);
  must(c.save_ct(), what);
  must(c.delete_all_curves(), what);
  for (const auto& cv : full.curves)
    must(c.write_curve(static_cast<std::uint16_t>(cv.id), cv.info, cv.data), what);
  must(c.save_curves(), what);
  must(c.start_mc(), what);
  must(c.reset(), what);
}

struct Row {
  std::string workload, op;
  Cost min, tool;
  double naive_s = -1;  // naive script, virtual seconds
  double wall_s = -1;   // real time over a pty / TCP
  std::string note;
};
std::vector<Row> rows;  // NOLINT
bool over_limit = false;

double ratio(const Cost& tool, const Cost& min) {
  return min.ns ? static_cast<double>(tool.ns) / static_cast<double>(min.ns) : 0.0;
}

// The 1.05 limit judges operations (backup, a whole restore, plan+write).
// Single restore phases are shown for information: the plan alone spends two
// extra telegrams per empty modified list to confirm it (docs/reliability.md),
// which is a large share of a short phase but not of the operation.
bool is_phase_row(const std::string& op) {
  return op == "restore: plan" || op == "restore: write" || op == "restore: verify";
}

void add(Row r) {
  if (!is_phase_row(r.op) && ratio(r.tool, r.min) > kLimit) over_limit = true;
  rows.push_back(std::move(r));
}

void print_table() {
  std::printf("\n%-34s %-20s %8s %8s %10s %10s %7s %10s %7s %9s\n", "workload", "operation",
              "min tel", "tool tel", "min s", "tool s", "tool/min", "naive s", "naive/t", "wall s");
  std::printf("%s\n", std::string(134, '-').c_str());
  for (const auto& r : rows) {
    char naive[16] = "-", nt[16] = "-", wall[16] = "-";
    if (r.naive_s >= 0) {
      std::snprintf(naive, sizeof naive, "%.3f", r.naive_s);
      std::snprintf(nt, sizeof nt, "%.2f", r.naive_s / r.tool.seconds());
    }
    if (r.wall_s >= 0) std::snprintf(wall, sizeof wall, "%.3f", r.wall_s);
    std::printf("%-34s %-20s %8llu %8llu %10.3f %10.3f %7.4f %10s %7s %9s%s%s\n",
                r.workload.c_str(), r.op.c_str(), static_cast<unsigned long long>(r.min.telegrams),
                static_cast<unsigned long long>(r.tool.telegrams), r.min.seconds(),
                r.tool.seconds(), ratio(r.tool, r.min), naive, nt, wall, r.note.empty() ? "" : "  ",
                r.note.c_str());
  }
}

// ------------------------------------------------------------ real time

// serve() delays each answer by turnaround + duration + the answer's wire time,
// but a pty or socket delivers the request at once: the served minimum is the
// protocol minimum without the requests' wire time.
std::string served_note(const char* how, double wall_s, const Cost& min) {
  char b[96];
  std::snprintf(b, sizeof b, "wall: %s real time, wall/served-min %.3f", how,
                wall_s / (static_cast<double>(min.ns - min.request_ns) / 1e9));
  return b;
}

// Serves `state` in real time on a pseudo-terminal (lib/sim/server.hpp serve()),
// runs `f` with a client on the slave through transport::open_serial, and
// returns the wall-clock seconds `f` took.
template <class F>
double over_pty(sim::DriveState state, F&& f) {
  auto pty = must(transport::open_pty(), "open_pty");
  sim::Drive drive(std::move(state));
  transport::SerialSettings line = drive.state().link;
  transport::FdTransport master(std::move(pty.master), "pty master");
  std::atomic<bool> stop{false};
  std::thread server([&] {
    sim::ServeOptions so;
    so.poll = transport::Millis(5);
    so.should_stop = [&] { return stop.load(); };
    (void)sim::serve(drive, master, so);
  });
  line.device = pty.slave_path;
  auto link = must(transport::open_serial(line), "open_serial " + pty.slave_path);
  client::ClientOptions o;
  o.id = drive.macid();
  client::LinrsClient c(*link, o);
  const auto t0 = std::chrono::steady_clock::now();
  f(c);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  stop = true;
  server.join();
  return s;
}

// `n` drives behind `n` loopback TCP gateways, each served in real time in its
// own thread, each backed up by its own client thread at once. Returns the wall
// clock from the first connect to the last backup done.
double tcp_gateways(const sim::DriveState& state, std::size_t n, const db::Database& db) {
  struct Gw {
    transport::UniqueFd listener;
    std::uint16_t port = 0;
  };
  std::vector<Gw> gws(n);
  for (auto& g : gws) g.listener = must(sim::listen_tcp("127.0.0.1", 0, g.port), "listen_tcp");
  std::atomic<bool> stop{false};
  std::vector<std::thread> servers;
  for (auto& g : gws) {
    servers.emplace_back([&, fd = g.listener.get()] {
      sim::Drive drive(state);
      auto conn = sim::accept_client(fd, transport::Millis(10000));
      if (!conn.ok() || !conn->valid()) return;
      transport::FdTransport t(std::move(conn).value(), "tcp");
      sim::ServeOptions so;
      so.poll = transport::Millis(5);
      so.should_stop = [&] { return stop.load(); };
      (void)sim::serve(drive, t, so);
    });
  }
  std::atomic<int> failures{0};
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<std::thread> clients;
  for (auto& g : gws) {
    clients.emplace_back([&, port = g.port] {
      auto link = transport::open_tcp("127.0.0.1", port, transport::Millis(3000));
      if (!link.ok()) {
        ++failures;
        return;
      }
      client::ClientOptions o;
      o.id = state.macid;
      client::LinrsClient c(**link, o);
      if (!ops::backup(c, ops::BackupOptions{}, db).ok()) ++failures;
    });
  }
  for (auto& t : clients) t.join();
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  stop = true;
  for (auto& t : servers) t.join();
  if (failures)
    die("TCP gateways", Error(Errc::io_error, std::to_string(failures.load()) + " backups failed"));
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  bool realtime = true, use_db = true;
  std::string fixtures = LMCFG_SOURCE_DIR "/tests/fixtures/sim";
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--no-realtime"))
      realtime = false;
    else if (!std::strcmp(argv[i], "--no-db"))
      use_db = false;
    else if (!std::strcmp(argv[i], "--fixtures") && i + 1 < argc)
      fixtures = argv[++i];
    else {
      std::fprintf(stderr, "usage: %s [--no-realtime] [--no-db] [--fixtures DIR]\n", argv[0]);
      return 2;
    }
  }
  std::optional<db::Database> database;
  if (use_db) {
    auto r = db::Database::open(LMCFG_DB_PATH);
    if (r.ok()) database = std::move(r).value();
  }
  const db::Database& db = database ? *database : db::Database::empty();
  std::printf(
      "lmcfg_bench_wire: virtual clock of the simulated drive (lib/sim), 57600 8N1, turnaround 1 "
      "ms,\n"
      "defaulting 1.2 s, flash save 2 s, reset 3 s, MC start 3 s. Demo axis with the UPID "
      "database: %s.\n"
      "Heavy axis without it (synthetic UPIDs). Minimum definitions: docs/performance.md.\n",
      !db.is_empty() ? "yes" : "no");

  const auto demo =
      must(sim::load_state(fixtures + "/commissioned-axis.json"), "commissioned-axis.json");
  const auto spare = must(sim::load_state(fixtures + "/used-spare.json"), "used-spare.json");
  const benchwire::HeavySpec hs;
  const auto heavy = benchwire::heavy_state(hs);
  const auto heavy_spare = benchwire::heavy_spare(hs, 120, 3, 10);

  // (a) / (b) backup, with the naive full walk.
  config::DriveConfig demo_file, heavy_file, demo_full, heavy_full;
  Cost demo_backup;
  for (int k = 0; k < 2; ++k) {
    const bool is_demo = k == 0;
    const auto& st = is_demo ? demo : heavy;
    const db::Database& d = is_demo ? db : db::Database::empty();
    const std::string name = is_demo ? "(a) demo axis" : "(b) heavy axis";
    Rig rig(st);
    config::DriveConfig file;
    Row r{name, "backup", benchwire::min_backup(st, {}, d), {}, -1, -1, {}};
    r.tool = measure(*rig.link,
                     [&] { file = must(ops::backup(*rig.client, ops::BackupOptions{}, d), name); });
    Rig naive(st);
    config::DriveConfig full;
    r.naive_s = measure(*naive.link, [&] { full = naive_backup(naive, name); }).seconds();
    if (is_demo && realtime) {
      r.wall_s = over_pty(st, [&](client::Client& c) {
        must(ops::backup(c, ops::BackupOptions{}, d), "pty backup");
      });
      r.note = served_note("pty", r.wall_s, r.min);
    }
    (is_demo ? demo_file : heavy_file) = file;
    (is_demo ? demo_full : heavy_full) = full;
    if (is_demo) demo_backup = r.tool;
    add(r);
  }

  // (c) restore onto a factory-fresh unit and onto a used spare.
  struct Target {
    std::string name;
    sim::DriveState state;
    bool demo;
  };
  // The demo axis with one setpoint of its first curve changed (RAM and flash).
  auto one_curve_off = demo;
  for (auto* curves : {&one_curve_off.curves_flash, &one_curve_off.curves_ram}) {
    auto& data = curves->begin()->second.data;
    if (!data.empty()) data[0] = static_cast<std::uint8_t>(data[0] ^ 1);
  }
  const std::vector<Target> targets{
      {"(c) demo -> itself (matches)", demo, true},
      {"(c) demo -> one curve differs", one_curve_off, true},
      {"(c) demo -> factory-fresh", benchwire::factory_fresh(demo), true},
      {"(c) demo -> used spare", spare, true},
      {"(c) heavy -> factory-fresh", benchwire::factory_fresh(heavy), false},
      {"(c) heavy -> used spare", heavy_spare, false},
  };
  for (const auto& t : targets) {
    const db::Database& d = t.demo ? db : db::Database::empty();
    const auto& file = t.demo ? demo_file : heavy_file;
    const auto m = benchwire::min_restore(t.state, file, d, alone_on_line());
    Rig rig(t.state);
    const auto run = run_restore(rig, file, d, t.name, alone_on_line());
    Rig naive(t.state);
    const double naive_s = measure(*naive.link, [&] {
                             naive_restore(*naive.client, t.demo ? demo_full : heavy_full, t.name);
                           }).seconds();
    Row a{t.name, "restore: plan", m.plan, run.plan, -1, -1, {}};
    Row b{t.name, "restore: write", m.execute, run.execute, -1, -1, {}};
    Row c{t.name,
          "restore: plan+write",
          m.without_verify(),
          run.without_verify(),
          naive_s,
          -1,
          "naive: default all, rewrite all"};
    Row v{t.name, "restore: verify", m.verify, run.verify, -1, -1, {}};
    Row all{t.name, "restore: total", m.total(), run.total(), -1, -1, {}};
    if (t.demo && t.name.find("spare") != std::string::npos && realtime) {
      all.wall_s = over_pty(t.state, [&](client::Client& cl) {
        ops::RestoreOptions ro;
        ro.include_comm = true;  // the fixtures' LinRS parameters select the same line
        auto plan = must(ops::plan_restore(cl, file, d, ro), "pty plan");
        must(ops::execute_plan(cl, plan, ro), "pty execute");
        auto rep = must(ops::verify_restore(cl, plan, ro), "pty verify");
        if (!rep.ok()) die("pty verify", Error(Errc::verify_mismatch, rep.mismatches.front()));
      });
      all.note = served_note("pty", all.wall_s, all.min);
    }
    for (auto* r : {&a, &b, &c, &v, &all}) add(*r);
  }

  // (d) 32 drives behind 32 gateways: one SimLink (own virtual clock) each, in parallel.
  {
    constexpr std::size_t n = 32;
    std::vector<Cost> backups(n), restores(n);
    std::vector<std::thread> th;
    std::atomic<int> bad{0};
    for (std::size_t i = 0; i < n; ++i) {
      th.emplace_back([&, i] {
        Rig b(demo);
        backups[i] = measure(*b.link, [&] {
          if (!ops::backup(*b.client, ops::BackupOptions{}, db).ok()) ++bad;
        });
        Rig r(spare);
        const ops::RestoreOptions ro = alone_on_line();
        restores[i] = measure(*r.link, [&] {
          auto plan = ops::plan_restore(*r.client, demo_file, db, ro);
          if (!plan.ok() || !plan->ok() || !ops::execute_plan(*r.client, *plan, ro).ok()) {
            ++bad;
            return;
          }
          auto v = ops::verify_restore(*r.client, *plan, ro);
          if (!v.ok() || !v->ok()) ++bad;
        });
      });
    }
    for (auto& t : th) t.join();
    if (bad)
      die("(d) gateways", Error(Errc::io_error, std::to_string(bad.load()) + " drives failed"));
    auto total = [](const std::vector<Cost>& v) {
      Cost c;
      for (const auto& x : v) {
        c.telegrams += x.telegrams;
        c.ns = std::max(c.ns, x.ns);
      }
      return c;
    };
    const Cost single_b = benchwire::min_backup(demo, {}, db);
    const Cost single_r = benchwire::min_restore(spare, demo_file, db, alone_on_line()).total();
    const Cost min_b{single_b.telegrams * n, single_b.ns, single_b.request_ns};
    const Cost min_r{single_r.telegrams * n, single_r.ns, single_r.request_ns};
    const Cost tb = total(backups), tr = total(restores);
    char note[96];
    std::snprintf(note, sizeof note, "total/single-drive %.4f",
                  static_cast<double>(tb.ns) / static_cast<double>(backups[0].ns));
    Row rb{"(d) 32 drives, 32 gateways", "backup (max of 32)", min_b, tb, -1, -1, note};
    std::snprintf(note, sizeof note, "total/single-drive %.4f",
                  static_cast<double>(tr.ns) / static_cast<double>(restores[0].ns));
    Row rr{"(d) 32 drives, 32 gateways", "restore+verify (max)", min_r, tr, -1, -1, note};
    if (realtime) {
      const double one = tcp_gateways(demo, 1, db);
      const double all = tcp_gateways(demo, n, db);
      rb.wall_s = all;
      std::snprintf(note, sizeof note,
                    "total/single-drive %.4f; wall TCP: 1 drive %.3f s, 32 drives %.3f s (x%.3f); ",
                    static_cast<double>(tb.ns) / static_cast<double>(backups[0].ns), one, all,
                    all / one);
      rb.note = note + served_note("TCP", all, single_b);
    }
    add(rb);
    add(rr);
  }

  // (e) 8 drives on one RS485 line: one Bus, MACIDs 11h..18h, strictly sequential.
  {
    constexpr int n = 8;
    for (int k = 0; k < 2; ++k) {
      const bool backup = k == 0;
      auto bus = std::make_shared<sim::Bus>(demo.link);
      std::vector<sim::DriveState> states;
      for (int i = 0; i < n; ++i) {
        sim::DriveState s = backup ? demo : spare;
        s.macid = static_cast<std::uint8_t>(0x11 + i);
        states.push_back(s);
        bus->add(std::make_shared<sim::Drive>(s));
      }
      auto link = std::make_shared<sim::SimLink>(bus);
      Cost min, tool;
      for (int i = 0; i < n; ++i) {
        Rig rig(link, states[static_cast<std::size_t>(i)].macid);
        const std::string what = "(e) drive " + std::to_string(i);
        if (backup) {
          min += benchwire::min_backup(states[static_cast<std::size_t>(i)], {}, db);
          tool += measure(*link,
                          [&] { must(ops::backup(*rig.client, ops::BackupOptions{}, db), what); });
        } else {
          // Eight drives on one line keep their own MACIDs: no --include-comm.
          min += benchwire::min_restore(states[static_cast<std::size_t>(i)], demo_file, db, {})
                     .total();
          tool += run_restore(rig, demo_file, db, what, {}).total();
        }
      }
      add(Row{"(e) 8 drives, one RS485 line",
              backup ? "backup (sequential)" : "restore+verify (seq.)", min, tool, -1, -1,
              backup ? "8 demo axes" : "demo file onto 8 used spares"});
    }
  }

  print_table();
  std::printf(
      "\nmin: protocol minimum (telegrams the operation cannot avoid, exact wire time at the line "
      "settings\n"
      "+ turnaround + documented durations); tool: lmcfg on the virtual clock; naive: a script "
      "that walks\n"
      "every UPID list and reads every ROM-writable value / defaults every layer and rewrites "
      "every value\n"
      "(restore row 'plan+write': the naive script has no checks and no verify); wall: real "
      "time.\n");
  if (over_limit) {
    std::printf("FAIL: an operation's tool/min ratio exceeds %.2f\n", kLimit);
    return 1;
  }
  std::printf(
      "every operation's tool/min ratio <= %.2f (single restore phases are informational)\n",
      kLimit);
  return 0;
}
