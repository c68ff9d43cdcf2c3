#!/usr/bin/env python3
"""lmcfg serve under connections that announce a body and never send it
(docs/serve.md "Limits"): the real `lmcfg serve` on 127.0.0.1 over one
simulated drive; 640 connections from 5 addresses (127.0.0.2-127.0.0.6, 128
each: the per-address limit), each sending a complete head with
`Content-Length: 4096` and no body, all closed and opened again every 10 s;
meanwhile legitimate `GET /api/v1/drives` on new connections from 127.0.0.1,
one every 0.5 s. Prints how many of the GETs got each status (or none), their
median and longest answer time, and how many of the held connections were
open at the end.
usage: bench_http_body_hold.py LMCFG_BINARY UPID_DB [GETS]  (GETS: default 31)
Not part of ctest; figures in docs/serve.md "Limits"."""
import os, shutil, socket, statistics, subprocess, sys, tempfile, threading, time

SOURCE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
HOLDERS = [f"127.0.0.{i}" for i in range(2, 7)]
PER_ADDRESS = 128
REOPEN_S = 10


def hold(port, stop, held):
    head = (f"POST /api/v1/drives HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\n"
            "Content-Type: application/json\r\nContent-Length: 4096\r\n\r\n").encode()
    while not stop.is_set():
        for s in held:
            s.close()
        held.clear()
        for addr in HOLDERS:
            for _ in range(PER_ADDRESS):
                s = socket.socket()
                try:
                    s.bind((addr, 0))
                    s.connect(("127.0.0.1", port))
                    s.sendall(head)
                    held.append(s)
                except OSError:
                    s.close()
        stop.wait(REOPEN_S)


def get(port):
    t0 = time.monotonic()
    s = socket.create_connection(("127.0.0.1", port), timeout=5)
    try:
        s.sendall(f"GET /api/v1/drives HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\n"
                  "Connection: close\r\n\r\n".encode())
        data = b""
        while b"\r\n" not in data:
            chunk = s.recv(4096)
            if not chunk:
                break
            data += chunk
        status = data.split(b" ")[1].decode() if data.startswith(b"HTTP/1.1 ") else "none"
    except OSError:
        status = "none"
    finally:
        s.close()
    return status, (time.monotonic() - t0) * 1000


def still_open(socks):
    n = 0
    for s in socks:
        try:
            s.setblocking(False)
            n += s.recv(1, socket.MSG_PEEK) != b""
        except BlockingIOError:
            n += 1
        except OSError:
            pass
    return n


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    lmcfg, db = sys.argv[1], sys.argv[2]
    gets = int(sys.argv[3]) if len(sys.argv) > 3 else 31
    d = tempfile.mkdtemp(prefix="lmcfg-bench-body-hold-")
    shutil.copy(os.path.join(SOURCE, "tests/fixtures/sim/commissioned-axis.json"),
                os.path.join(d, "a.json"))
    with open(os.path.join(d, "plant.toml"), "w") as f:
        f.write(f'[[line]]\nname = "line1"\nport = "sim:{d}/a.json"\n'
                '[[line.drive]]\nname = "press3/z"\nid = 0x11\n')
    serve = subprocess.Popen([lmcfg, "serve", os.path.join(d, "plant.toml"), "--archive",
                              os.path.join(d, "archive"), "--listen", "127.0.0.1:0", "--db", db],
                             stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    try:
        port = int(serve.stdout.readline().strip().rsplit(":", 1)[1])
        time.sleep(2)  # its first backup
        stop, held = threading.Event(), []
        t = threading.Thread(target=hold, args=(port, stop, held))
        t.start()
        time.sleep(2)
        results = []
        for _ in range(gets):
            results.append(get(port))
            time.sleep(0.5)
        open_now = still_open(list(held))
        stop.set()
        t.join()
        for s in held:
            s.close()
        counts = {}
        for status, _ in results:
            counts[status] = counts.get(status, 0) + 1
        ms = [m for _, m in results]
        print(f"lmcfg serve {lmcfg}: {len(HOLDERS) * PER_ADDRESS} held connections from "
              f"{len(HOLDERS)} addresses, reopened every {REOPEN_S} s; {gets} GETs from 127.0.0.1")
        print("statuses: " + ", ".join(f"{k} x{v}" for k, v in sorted(counts.items())))
        print(f"answer ms: median {statistics.median(ms):.1f}, max {max(ms):.1f}")
        print(f"held connections still open at the end: {open_now}")
    finally:
        serve.terminate()
        serve.wait()
        shutil.rmtree(d, ignore_errors=True)


if __name__ == "__main__":
    main()
