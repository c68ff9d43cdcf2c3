"""The lmcfg package against the built-in simulated drive (sim:) and the lmcfg
program: every result is checked against what the program does with the same
drive or file."""

import json
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

import lmcfg
from conftest import set_state_param


def backup(state, **kw):
    with lmcfg.Link(f"sim:{state}").open() as drive:
        return drive.backup(**kw)


def run(tool, *args):
    return subprocess.run([tool, *map(str, args)], capture_output=True, text=True)


def state_of(path):
    """What a simulated drive holds, as a backup of it reads it (its state file
    is rewritten on every close)."""
    return backup(path)


def unchanged(before, path):
    return lmcfg.diff(before, state_of(path), ignore_metadata=True) == []


# --- database ------------------------------------------------------------------

def test_db_parameter_matches_db_show(tool):
    p = lmcfg.db.parameter(0x13A2)
    assert p.upid == 0x13A2
    assert p.layer == "MC"
    shown = run(tool, "db", "show", "13A2")
    assert shown.returncode == 0, shown.stderr
    assert p.name and p.name in shown.stdout
    assert not lmcfg.db.is_empty
    assert Path(lmcfg.db.path).name == "lmcfg-upid.sqlite"


def test_db_unknown_upid():
    assert lmcfg.db.find(0x1EEE) is None
    with pytest.raises(KeyError, match="UPID 1EEEh is not in the UPID database"):
        lmcfg.db.parameter(0x1EEE)


def test_db_search_finds_13a2_by_its_name():
    name = lmcfg.db.parameter(0x13A2).name
    assert 0x13A2 in [p.upid for p in lmcfg.db.search(name)]


# --- backup, files, diff -----------------------------------------------------------

def test_backup_is_the_programs_backup(sim_copy, tmp_path, tool):
    axis = sim_copy("commissioned-axis.json")
    cfg = backup(axis)
    assert cfg.macid == "0x11"
    assert cfg.port == f"sim:{axis}"
    assert len(cfg.parameters) > 0
    assert cfg.parameter(0x13A2) is not None
    assert cfg.parameter(0x13A2).layer == 2
    r = run(tool, "backup", "--port", f"sim:{axis}", "-q", "-o", tmp_path / "cli.json")
    assert r.returncode == 0, r.stderr
    cli = lmcfg.Config.load(tmp_path / "cli.json")
    assert lmcfg.diff(cfg, cli, ignore_metadata=True) == []
    assert len(cli.parameters) == len(cfg.parameters)
    assert len(cli.curves) == len(cfg.curves)
    assert len(cli.ct_entries) == len(cfg.ct_entries)


def test_save_and_load_json_and_xml(sim_copy, tmp_path, tool):
    cfg = backup(sim_copy("commissioned-axis.json"), labels={"machine": "press3"})
    cfg.save(tmp_path / "axis.json")
    cfg.save(str(tmp_path / "axis.xml"))
    cfg.save(tmp_path / "axis.data", format="xml")
    j = lmcfg.Config.load(tmp_path / "axis.json")
    x = lmcfg.Config.load(tmp_path / "axis.xml")
    assert j == x
    assert lmcfg.Config.load(tmp_path / "axis.data", format="xml") == x
    assert j.labels == {"machine": "press3"}
    assert lmcfg.diff(cfg, j) == []
    assert lmcfg.Config.loads(j.dumps()) == j
    assert lmcfg.Config.loads(j.dumps("xml"), "xml") == j
    # The program reads what Python wrote, and converts it to the same bytes.
    r = run(tool, "convert", tmp_path / "axis.xml", tmp_path / "converted.json")
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "converted.json").read_text() == (tmp_path / "axis.json").read_text()


def test_diff_lists_what_diff_json_lists(sim_copy, tmp_path, tool):
    a = backup(sim_copy("commissioned-axis.json"))
    b = backup(sim_copy("used-spare.json"))
    a.save(tmp_path / "a.json")
    b.save(tmp_path / "b.json")
    items = lmcfg.diff(a, b)
    r = run(tool, "diff", "--json", tmp_path / "a.json", tmp_path / "b.json")
    assert r.returncode == 1, r.stderr
    listed = json.loads(r.stdout)["differences"]
    assert len(items) == len(listed) > 0
    for d, j in zip(items, listed):
        assert d.kind == j["kind"]
        assert (d.old, d.new, d.name) == (j["a"], j["b"], j["name"])
        if d.kind == "parameter":
            assert f"{d.upid:04X}" == j["upid"]
        else:
            assert d.upid is None
    params = [d for d in items if d.kind == "parameter"]
    assert params and all(isinstance(d.upid, int) for d in params)
    text = lmcfg.diff_text(a, b, "a.json", "b.json")
    assert "a.json" in text
    assert lmcfg.diff(a, a) == []


def test_diff_ignore_metadata(sim_copy):
    a = backup(sim_copy("commissioned-axis.json"))
    b = backup(sim_copy("commissioned-axis.json", "other.json"), labels={"axis": "2"})
    assert [d.kind for d in lmcfg.diff(a, b)] and all(
        d.kind == "metadata" for d in lmcfg.diff(a, b))
    assert lmcfg.diff(a, b, ignore_metadata=True) == []


# --- restore ----------------------------------------------------------------------

def test_plan_restore_then_restore_and_verify(sim_copy):
    axis = sim_copy("commissioned-axis.json")
    spare = sim_copy("used-spare.json")
    cfg = backup(axis)
    before = state_of(spare)
    with lmcfg.Link(f"sim:{spare}").open() as drive:
        plan = drive.plan_restore(cfg)
        assert plan.ok and plan.problems == []
        assert not plan.nothing_to_do
        writes = [s for s in plan.steps if s.action == "write_rom"]
        assert writes and all(s.new for s in writes) and any(s.name for s in writes)
        assert "stop_mc" == plan.steps[0].action
        assert json.loads(plan.json())["steps"][0]["action"] == "stop_mc"
        assert str(plan)
    assert unchanged(before, spare)  # planning reads only
    with lmcfg.Link(f"sim:{spare}").open() as drive:
        outcome = drive.restore(cfg, yes=True)
    assert outcome.stage == "restored and verified"
    assert outcome.written and outcome.mismatches == []
    # The spare keeps its own communication parameters (no include_comm): per-unit data.
    after = backup(spare)
    assert lmcfg.diff(cfg, after, ignore_metadata=True, ignore_unit=True) == []
    kept = lmcfg.diff(cfg, after, ignore_metadata=True)
    assert kept and all(lmcfg.db.parameter(d.upid).comm for d in kept)
    # Again: the drive matches, nothing written.
    with lmcfg.Link(f"sim:{spare}").open() as drive:
        again = drive.restore(cfg, yes=True)
    assert again.stage == "nothing to do"
    assert not again.written


def test_restore_dry_run_and_confirm_callback(sim_copy):
    cfg = backup(sim_copy("commissioned-axis.json"))
    spare = sim_copy("used-spare.json")
    before = state_of(spare)
    seen = []
    with lmcfg.Link(f"sim:{spare}").open() as drive:
        assert drive.restore(cfg, dry_run=True).stage == "dry run"
        out = drive.restore(cfg, confirm=lambda plan: seen.append(plan) or False)
    assert out.stage == "declined" and not out.written
    assert len(seen) == 1 and seen[0].steps
    assert unchanged(before, spare)


def test_restore_without_yes_is_invalid_input(sim_copy):
    cfg = backup(sim_copy("commissioned-axis.json"))
    spare = sim_copy("used-spare.json")
    before = state_of(spare)
    with lmcfg.Link(f"sim:{spare}").open() as drive:
        with pytest.raises(lmcfg.InvalidInput, match="pass yes=True") as e:
            drive.restore(cfg)
    assert e.value.exit_code == 2
    assert unchanged(before, spare)


def test_refused_plan_raises_plan_refused_like_the_program(sim_copy, tmp_path, tool):
    axis = sim_copy("commissioned-axis.json")
    cfg = backup(axis)
    cfg.save(tmp_path / "good.json")
    spare = sim_copy("used-spare.json")
    # The target reports a lower maximum than the file's value of 13A2h.
    set_state_param(spare, "13A2", "max", 30)
    before = state_of(spare)
    with lmcfg.Link(f"sim:{spare}").open() as drive:
        plan = drive.plan_restore(cfg)
        assert not plan.ok
        assert any("MC 13A2h" in p for p in plan.problems)
        with pytest.raises(lmcfg.PlanRefused) as e:
            drive.restore(cfg, yes=True)
    assert e.value.exit_code == 3
    assert isinstance(e.value, lmcfg.Error)
    assert e.value.problems == plan.problems
    assert not e.value.plan.ok
    assert "MC 13A2h" in str(e.value)
    assert unchanged(before, spare)
    r = run(tool, "restore", tmp_path / "good.json", "--port", f"sim:{spare}", "--yes")
    assert r.returncode == e.value.exit_code
    assert "MC 13A2h" in r.stderr


# --- errors -----------------------------------------------------------------------

def test_exception_classes_and_exit_codes():
    codes = {lmcfg.Error: 70, lmcfg.InvalidInput: 2, lmcfg.PlanRefused: 3, lmcfg.LinkError: 4,
             lmcfg.DriveRefused: 5, lmcfg.VerifyMismatch: 6, lmcfg.Interrupted: 130}
    for cls, code in codes.items():
        assert cls.exit_code == code
        assert issubclass(cls, lmcfg.Error) and issubclass(cls, Exception)


@pytest.mark.parametrize("port, cls, code", [
    # No such device: the port named is wrong (as the program says: exit 2).
    ("/dev/lmcfg-no-such-port", lmcfg.InvalidInput, 2),
    # Nobody listens: a link failure.
    ("tcp://127.0.0.1:1", lmcfg.LinkError, 4),
])
def test_bad_port_raises_with_the_programs_exit_code(port, cls, code, tmp_path, tool):
    with pytest.raises(cls) as e:
        lmcfg.Link(port).open()
    assert e.value.exit_code == code
    assert port.split("//")[-1] in str(e.value)
    r = run(tool, "backup", "--port", port, "-o", tmp_path / "x.json")
    assert r.returncode == e.value.exit_code, r.stderr


def test_missing_sim_state_file(tmp_path, tool):
    with pytest.raises(lmcfg.Error) as e:
        lmcfg.Link(f"sim:{tmp_path}/absent.json").open()
    assert "absent.json" in str(e.value)
    r = run(tool, "backup", "--port", f"sim:{tmp_path}/absent.json", "-o", tmp_path / "x.json")
    assert r.returncode == e.value.exit_code


@pytest.mark.parametrize("kw, message", [
    ({"id": 300}, "id 300 is not a MACID 0..255"),
    ({"checksum": "md5"}, "md5"),
    ({"parity": "mark"}, "mark"),
    ({"baud": 1234}, "1234"),
])
def test_bad_link_options_are_invalid_input(kw, message, sim_copy):
    with pytest.raises(lmcfg.InvalidInput, match=message) as e:
        lmcfg.Link(f"sim:{sim_copy('commissioned-axis.json')}", **kw).open()
    assert e.value.exit_code == 2


def test_bad_files_are_invalid_input(tmp_path, tool):
    bad = tmp_path / "bad.json"
    bad.write_text('{"format": "lmcfg", "format_version": 2, "parameters": 7}')
    with pytest.raises(lmcfg.InvalidInput) as e:
        lmcfg.Config.load(bad)
    assert e.value.exit_code == 2
    assert "bad.json" in str(e.value)
    r = run(tool, "convert", bad, tmp_path / "out.xml")
    assert r.returncode == e.value.exit_code
    with pytest.raises(lmcfg.InvalidInput):
        lmcfg.Config.load(tmp_path / "absent.json")
    with pytest.raises(lmcfg.InvalidInput, match="yaml"):
        lmcfg.Config.load(bad, format="yaml")


def test_closed_drive_refuses(sim_copy):
    drive = lmcfg.Link(f"sim:{sim_copy('commissioned-axis.json')}").open()
    drive.close()
    drive.close()  # twice is fine
    with pytest.raises(lmcfg.InvalidInput, match="the drive's link is closed"):
        drive.backup()


# --- GIL and callbacks ---------------------------------------------------------------

def test_progress_callback_is_called(sim_copy):
    calls = []
    backup(sim_copy("commissioned-axis.json"),
           progress=lambda phase, done, total: calls.append((phase, done, total)))
    assert calls
    assert all(isinstance(p, str) and isinstance(d, int) and isinstance(t, int)
               for p, d, t in calls)
    assert len({p for p, _, _ in calls}) > 1  # several phases (layers, curves, CT)


def test_progress_callback_exception_stops_the_backup(sim_copy):
    calls = []

    def boom(phase, done, total):
        calls.append(phase)
        raise ValueError("stop here")

    axis = sim_copy("commissioned-axis.json")
    with lmcfg.Link(f"sim:{axis}").open() as drive:
        with pytest.raises(ValueError, match="stop here"):
            drive.backup(progress=boom)
        assert len(calls) == 1
        # The drive is usable again afterwards.
        assert drive.backup(layers=["os"], curves=False, command_table=False).parameters


def test_gil_released_during_drive_io(sim_copy, sim_server):
    # A real-time simulated drive on a pty: the backup waits on the wire.
    server = sim_server([sim_copy("commissioned-axis.json")], fast=False)
    count = 0
    stop = threading.Event()

    def spin():
        nonlocal count
        while not stop.is_set():
            count += 1

    t = threading.Thread(target=spin)
    t.start()
    try:
        with lmcfg.Link(server.port).open() as drive:
            start_count, start = count, time.monotonic()
            cfg = drive.backup(layers=["os", "mc"], curves=False, command_table=False)
            spun, took = count - start_count, time.monotonic() - start
    finally:
        stop.set()
        t.join()
    assert cfg.parameters
    assert took > 0.05  # the wire took time
    # The other thread ran during the backup: the GIL was released.
    assert spun > 1000, (spun, took)


def test_ctrl_c_interrupts_a_backup_between_two_telegrams(sim_copy, sim_server, tmp_path):
    # A real-time drive on a pty; SIGINT to the Python process while it reads.
    server = sim_server([sim_copy("commissioned-axis.json")], fast=False)
    script = tmp_path / "read.py"
    script.write_text(
        "import sys, lmcfg\n"
        "with lmcfg.Link(sys.argv[1]).open() as drive:\n"
        "    print('reading', flush=True)\n"
        "    try:\n"
        "        drive.backup()\n"
        "    except KeyboardInterrupt:\n"
        "        print('interrupted', drive.telegrams, flush=True)\n"
        "        sys.exit(130)\n"
        "print('finished', flush=True)\n")
    proc = subprocess.Popen([sys.executable, str(script), server.port], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    assert proc.stdout.readline().strip() == "reading"
    time.sleep(1.0)
    sent = time.monotonic()
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=30)
    assert proc.returncode == 130, (out, err)
    assert out.startswith("interrupted"), (out, err)
    assert time.monotonic() - sent < 5.0
