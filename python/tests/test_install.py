"""`cmake --install` puts the package where the prefix's python3 finds it
(docs/python.md): lib/python3/dist-packages for /usr (the Debian package),
lib/python3.X/dist-packages for any other prefix; the installed package finds
the installed database in PREFIX/share/lmcfg/."""

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

BINARY_DIR = os.environ.get("LMCFG_BINARY_DIR")


def install(prefix, destdir=None):
    assert BINARY_DIR, "LMCFG_BINARY_DIR is not set: run through ctest"
    env = dict(os.environ)
    if destdir:
        env["DESTDIR"] = str(destdir)
    r = subprocess.run(["cmake", "--install", BINARY_DIR, "--prefix", str(prefix), "--component",
                        "python"], capture_output=True, text=True, env=env)
    assert r.returncode == 0, r.stdout + r.stderr


def import_from(site, cwd):
    env = {k: v for k, v in os.environ.items() if k != "LMCFG_UPID_DB"}
    env["PYTHONPATH"] = str(site)
    return subprocess.run(
        [sys.executable, "-c",
         "import lmcfg; print(lmcfg.__file__); print(lmcfg.db.path); "
         "print(lmcfg.db.parameter(0x13A2).name)"],
        capture_output=True, text=True, env=env, cwd=cwd)


@pytest.mark.parametrize("prefix, site", [
    ("/usr", "lib/python3/dist-packages"),
    ("/opt/lmcfg", f"lib/python{sys.version_info.major}.{sys.version_info.minor}/dist-packages"),
    # As cpack builds the Debian package: prefix STAGING/usr, no DESTDIR.
    ("staging", "lib/python3/dist-packages"),
])
def test_installed_package_imports_and_finds_the_installed_database(prefix, site, tmp_path):
    root = tmp_path / "root"
    if prefix == "staging":
        root, prefix = tmp_path, "/root/lmcfg-0.1.0-Linux/usr"
        install(tmp_path / prefix.lstrip("/"))
    else:
        install(prefix, destdir=root)
    pkg = root / prefix.lstrip("/") / site / "lmcfg"
    assert sorted(p.name for p in pkg.iterdir() if not p.name.startswith("_lmcfg")) == [
        "__init__.py", "__init__.pyi", "py.typed"]
    assert len(list(pkg.glob("_lmcfg.*.so"))) == 1
    db_dir = root / prefix.lstrip("/") / "share" / "lmcfg"
    db_dir.mkdir(parents=True)
    shutil.copyfile(Path(BINARY_DIR) / "lmcfg-upid.sqlite", db_dir / "lmcfg-upid.sqlite")
    r = import_from(pkg.parent, tmp_path)
    assert r.returncode == 0, r.stderr
    file, db, name = r.stdout.splitlines()
    assert Path(file).parent == pkg
    assert Path(db) == db_dir / "lmcfg-upid.sqlite"
    assert name


def test_debians_python_searches_the_usr_local_directory():
    # The directory chosen for /usr/local is on Debian's python3 path.
    paths = subprocess.run([sys.executable, "-c", "import sys; print('\\n'.join(sys.path))"],
                           capture_output=True, text=True, env={}).stdout.split()
    v = f"{sys.version_info.major}.{sys.version_info.minor}"
    assert f"/usr/local/lib/python{v}/dist-packages" in paths
    assert "/usr/lib/python3/dist-packages" in paths
