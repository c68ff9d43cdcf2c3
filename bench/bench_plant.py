#!/usr/bin/env python3
"""lmcfg at plant size: the costs that grow with the number of positions N
and with the archive's history, measured on the real `lmcfg` program.

For each N: N simulated drives (the demo axis, tests/fixtures/sim), 10 per
line, each line a `sim:` port of its drives' state files; then
  - `lmcfg fleet backup` into a new archive (the first backup) and again
    (nothing changed: the repeated backup), and `lmcfg fleet status`: wall
    time of each run;
  - a history of HISTORY backups in all: after the first, commits that each
    change one position's file (its capture time and one value, as a drift
    found by a backup), made with git;
  - `lmcfg serve` on that archive without a schedule: the time from the
    start to the first answer of GET /api/v1/drives, without
    <archive>/.git/lmcfg-serve/states.json (a first start) and with it (a
    restart); the service's resident memory (VmRSS) after the start; the
    median and longest answer time of GET /api/v1/drives, of one position
    (GET /api/v1/drives/NAME) and of the console's overview (GET /), and
    its peak resident memory (VmHWM) after them.
Prints one table row per N.

usage: bench_plant.py LMCFG_BINARY [N ...] [--history H] [--keep]
       (N: default 500 5000; H: default 100)
Not part of ctest; figures in docs/measurements.md ("Plant size")."""
import json, os, shutil, signal, socket, statistics, subprocess, sys, tempfile, time

SOURCE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PER_LINE = 10


def run(cmd, **kw):
    t0 = time.monotonic()
    r = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, **kw)
    return time.monotonic() - t0, r


def plant(folder, n):
    """N state files and the inventory; the inventory's path."""
    axis = json.load(open(os.path.join(SOURCE, "tests/fixtures/sim/commissioned-axis.json")))
    os.makedirs(os.path.join(folder, "drives"))
    toml = []
    for line in range(0, n, PER_LINE):
        ports, drives = [], []
        for i in range(min(PER_LINE, n - line)):
            axis["macid"] = 0x11 + i
            for param in axis["parameters"]:
                if param["upid"] == "2076":  # the MACID it keeps after a restart
                    param["rom"] = param["ram"] = 0x11 + i
            path = os.path.join(folder, "drives", f"l{line // PER_LINE}d{i}.json")
            with open(path, "w") as f:
                json.dump(axis, f)
            ports.append(path)
            drives.append(f'[[line.drive]]\nname = "line{line // PER_LINE + 1}/axis{i + 1}"\n'
                          f"id = {0x11 + i}\n")
        toml.append(f'[[line]]\nname = "line{line // PER_LINE + 1}"\n'
                    f'port = "sim:{",".join(ports)}"\n' + "".join(drives))
    inventory = os.path.join(folder, "plant.toml")
    with open(inventory, "w") as f:
        f.write("\n".join(toml))
    return inventory


def history(archive, n, commits):
    """`commits` commits after the first backup, each changing one position's file."""
    env = dict(os.environ, GIT_AUTHOR_NAME="bench", GIT_AUTHOR_EMAIL="bench@example.org",
               GIT_COMMITTER_NAME="bench", GIT_COMMITTER_EMAIL="bench@example.org")
    for k in range(commits):
        line, i = (k * 7919) % (n // PER_LINE), k % min(PER_LINE, n)
        rel = f"line{line + 1}/axis{i + 1}.json"
        path = os.path.join(archive, rel)
        cfg = json.load(open(path))
        cfg["identity"]["captured_at"] = f"2026-01-01T00:{k // 60 % 60:02d}:{k % 60:02d}Z"
        cfg["parameters"][0]["params"][0]["value"] = k
        with open(path, "w") as f:
            json.dump(cfg, f, indent=2)
        subprocess.run(["git", "-C", archive, "commit", "-q", "-m",
                        f"fleet backup: 1 changed, {n - 1} unchanged, 0 new, 0 failed", "--", rel],
                       check=True, env=env)


def free_port():
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
    s.close()
    return port


def get(port, path, method="GET"):
    """(status, seconds, body) of one request without a body on a new connection."""
    t0 = time.monotonic()
    s = socket.create_connection(("127.0.0.1", port), timeout=60)
    s.sendall(f"{method} {path} HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nContent-Length: 0\r\n"
              "Connection: close\r\n\r\n".encode())
    chunks = []  # joined once: adding each to the last copies megabytes per answer
    while True:
        chunk = s.recv(1 << 16)
        if not chunk:
            break
        chunks.append(chunk)
    s.close()
    data = b"".join(chunks)
    status = int(data.split(b" ", 2)[1]) if data.startswith(b"HTTP/1.1 ") else 0
    return status, time.monotonic() - t0, data.split(b"\r\n\r\n", 1)[-1]


def rss_mb(pid, field="VmRSS"):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith(field + ":"):
                return int(line.split()[1]) / 1024
    return -1


def serve(lmcfg, inventory, archive):
    """Starts lmcfg serve; (seconds to the first answer, RSS MB, latencies, process)."""
    port = free_port()
    t0 = time.monotonic()
    p = subprocess.Popen([lmcfg, "serve", inventory, "--archive", archive, "--listen",
                          f"127.0.0.1:{port}"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    while True:
        if p.poll() is not None:
            raise SystemExit(f"lmcfg serve exited with {p.returncode} before answering")
        if time.monotonic() - t0 > 600:
            stop(p)
            raise SystemExit("lmcfg serve did not answer within 600 s")
        try:
            if get(port, "/api/v1/drives")[0] == 200:
                break
        except OSError:
            time.sleep(0.02)
    started = time.monotonic() - t0
    p.port = port
    try:
        time.sleep(1)
        rss = rss_mb(p.pid)
        lat = {}
        for name, path, count in (("drives", "/api/v1/drives", 20),
                                  ("one", "/api/v1/drives/line1/axis1", 50), ("overview", "/", 20)):
            times = []
            for _ in range(count):
                status, t, _ = get(port, path)
                if status != 200:
                    raise SystemExit(f"GET {path}: status {status}")
                times.append(t)
            lat[name] = (statistics.median(times) * 1000, max(times) * 1000)
        p.peak = rss_mb(p.pid, "VmHWM")  # after the requests (their answers built)
    except BaseException:
        stop(p)  # never leave the service running behind a failed measurement
        raise
    return started, rss, lat, p


def backup_line(port, line):
    """POST /api/v1/lines/LINE/backup and its job to the end: the service saves
    every position's state (states.json) after a run."""
    status, _, body = get(port, f"/api/v1/lines/{line}/backup", "POST")
    if status != 202:
        raise SystemExit(f"POST /api/v1/lines/{line}/backup: status {status}: {body[:300]}")
    job = json.loads(body)["job"]
    while True:
        status, _, body = get(port, f"/api/v1/jobs/{job}")
        if json.loads(body).get("state") in ("done", "failed"):
            return
        time.sleep(0.1)


def stop(p):
    p.send_signal(signal.SIGINT)
    p.wait(timeout=120)


def main(argv):
    keep = "--keep" in argv
    argv = [a for a in argv if a != "--keep"]
    commits = 100
    if "--history" in argv:
        k = argv.index("--history")
        commits = int(argv[k + 1])
        del argv[k:k + 2]
    if not argv:
        print(__doc__)
        return 2
    lmcfg, sizes = os.path.abspath(argv[0]), [int(a) for a in argv[1:]] or [500, 5000]
    print(f"lmcfg at plant size: {PER_LINE} simulated drives per line (sim: ports), "
          f"{commits} backups in the history")
    print(f"{'N':>6} {'first':>7} {'repeat':>7} {'status':>7} {'start':>7} {'restart':>8} "
          f"{'RSS MB':>7} {'peak MB':>8} {'drives ms':>14} {'one ms':>12} {'overview ms':>14}")
    for n in sizes:
        folder = tempfile.mkdtemp(prefix=f"lmcfg-bench-plant-{n}-")
        try:
            inventory = plant(folder, n)
            archive = os.path.join(folder, "archive")
            figures = []
            for what in (["fleet", "backup"], ["fleet", "backup"], ["fleet", "status"]):
                t, r = run([lmcfg, *what, inventory, "--archive", archive, "--quiet"])
                if r.returncode != 0:
                    raise SystemExit(f"lmcfg {' '.join(what)}: exit {r.returncode}: {r.stderr[-500:]}")
                figures.append(t)
            history(archive, n, commits - 1)
            state = os.path.join(archive, ".git", "lmcfg-serve", "states.json")
            if os.path.exists(state):
                os.remove(state)
            first, _, _, p = serve(lmcfg, inventory, archive)
            try:
                backup_line(p.port, "line1")
            finally:
                stop(p)
            if not os.path.exists(state):
                raise SystemExit(f"no {state} after the first start")
            again, rss, lat, p = serve(lmcfg, inventory, archive)
            stop(p)
            fmt = lambda ms: f"{ms[0]:.1f} / {ms[1]:.1f}"
            print(f"{n:>6} {figures[0]:>6.1f}s {figures[1]:>6.1f}s {figures[2]:>6.1f}s {first:>6.2f}s "
                  f"{again:>7.2f}s {rss:>7.1f} {p.peak:>8.1f} {fmt(lat['drives']):>14} {fmt(lat['one']):>12} "
                  f"{fmt(lat['overview']):>14}", flush=True)
        finally:
            if keep:
                print(f"  kept {folder}")
            else:
                shutil.rmtree(folder, ignore_errors=True)
    print("first/repeat: lmcfg fleet backup; status: lmcfg fleet status (wall time); "
          "start/restart: lmcfg serve to the first answer without and with states.json; "
          "latencies: median / longest over 20, 50, 20 GETs")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
