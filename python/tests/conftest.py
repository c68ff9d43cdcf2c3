"""Fixtures of the Python binding tests: the package built in build/python,
the simulated drives of tests/fixtures/sim, and the lmcfg program (ctest sets
PYTHONPATH, LMCFG_UPID_DB, LMCFG_TOOL and LMCFG_SOURCE_DIR: python/CMakeLists.txt)."""

import json
import os
import shutil
import subprocess
from pathlib import Path

import pytest

SOURCE_DIR = Path(os.environ.get("LMCFG_SOURCE_DIR", Path(__file__).resolve().parents[2]))
SIM_FIXTURES = SOURCE_DIR / "tests" / "fixtures" / "sim"


@pytest.fixture(autouse=True)
def _state_home(tmp_path, monkeypatch):
    # Restore's recovery records go to $XDG_STATE_HOME/lmcfg/: keep them in the test's folder.
    monkeypatch.setenv("XDG_STATE_HOME", str(tmp_path / "state"))


@pytest.fixture
def sim_copy(tmp_path):
    """sim_copy("commissioned-axis.json") -> a copy of that simulated drive in tmp_path."""

    def copy(name, as_name=None):
        dst = tmp_path / (as_name or name)
        shutil.copyfile(SIM_FIXTURES / name, dst)
        return dst

    return copy


@pytest.fixture
def tool():
    path = os.environ.get("LMCFG_TOOL")
    assert path, "LMCFG_TOOL (the lmcfg program) is not set: run through ctest"
    return path


def set_state_param(state_path, upid_hex, field, value):
    """Changes one field of a parameter of a simulated drive's state file."""
    state = json.loads(Path(state_path).read_text())
    for p in state["parameters"]:
        if p["upid"].upper() == upid_hex.upper():
            p[field] = value
            break
    else:
        raise AssertionError(f"{upid_hex} not in {state_path}")
    Path(state_path).write_text(json.dumps(state, indent=2))


class SimServer:
    """`lmcfg sim --pty` serving one or more state files (an RS485 line)."""

    def __init__(self, tool, states, fast=True):
        args = [tool, "sim", "--pty"] + (["--fast"] if fast else [])
        for s in states:
            args += ["--state", str(s)]
        self.proc = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                     text=True)
        self.port = self.proc.stdout.readline().strip()
        self.link_options = self.proc.stdout.readline().strip()
        assert self.port.startswith("/dev/"), (self.port, self.proc.stderr.read())

    def stop(self):
        self.proc.terminate()
        self.proc.wait(timeout=10)


@pytest.fixture
def sim_server(tool):
    servers = []

    def start(states, fast=True):
        s = SimServer(tool, states, fast)
        servers.append(s)
        return s

    yield start
    for s in servers:
        if s.proc.poll() is None:
            s.stop()
