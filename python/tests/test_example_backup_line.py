"""examples/python/backup_line.py against `lmcfg sim --pty` serving a line of
two simulated drives (MACIDs 11h and 12h) on one pseudo-terminal."""

import json
import os
import subprocess
import sys
from pathlib import Path

import lmcfg
from conftest import SOURCE_DIR

EXAMPLE = SOURCE_DIR / "examples" / "python" / "backup_line.py"


def drive_as(src, dst, macid_hex):
    state = json.loads(Path(src).read_text())
    state["macid"] = macid_hex
    Path(dst).write_text(json.dumps(state, indent=2))
    return dst


def run_example(*args):
    return subprocess.run([sys.executable, str(EXAMPLE), *map(str, args)], capture_output=True,
                          text=True, env=dict(os.environ))


def test_backs_up_every_drive_of_the_line(sim_copy, sim_server, tmp_path):
    a = sim_copy("commissioned-axis.json")  # MACID 11h
    b = drive_as(sim_copy("used-spare.json"), tmp_path / "spare-12.json", "12")
    server = sim_server([a, b])
    r = run_example("--port", server.port, "--id", "0x11", "--id", "0x12", "--out-dir",
                    tmp_path / "out")
    assert r.returncode == 0, r.stderr
    files = sorted(p.name for p in (tmp_path / "out").iterdir())
    assert files == ["drive-11.json", "drive-12.json"]
    d11 = lmcfg.Config.load(tmp_path / "out" / "drive-11.json")
    d12 = lmcfg.Config.load(tmp_path / "out" / "drive-12.json")
    assert (d11.macid, d12.macid) == ("0x11", "0x12")
    assert d11.labels == {"line_port": server.port}
    # Each file holds its own drive: the same as a backup of that state alone.
    server.stop()
    with lmcfg.Link(f"sim:{a}").open() as drive:
        assert lmcfg.diff(d11, drive.backup(), ignore_metadata=True) == []
    with lmcfg.Link(f"sim:{b}", id=0x12).open() as drive:
        assert lmcfg.diff(d12, drive.backup(), ignore_metadata=True) == []
    assert lmcfg.diff(d11, d12, ignore_metadata=True) != []


def test_a_silent_drive_fails_with_the_link_exit_code(sim_copy, sim_server, tmp_path):
    server = sim_server([sim_copy("commissioned-axis.json")])
    r = run_example("--port", server.port, "--id", "0x11", "--id", "0x2A", "--out-dir",
                    tmp_path / "out", )
    assert r.returncode == 4, r.stderr
    assert "drive 2Ah:" in r.stderr and "(exit 4)" in r.stderr
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == ["drive-11.json"]
