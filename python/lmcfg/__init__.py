"""Back up, diff and restore LinMot drive configurations over LinRS.

The library of the ``lmcfg`` program, for Python (docs/python.md)::

    import lmcfg
    link = lmcfg.Link("/dev/ttyUSB0", baud=57600, id=0x11, checksum="crc")
    with link.open() as drive:
        cfg = drive.backup()
    cfg.save("axis.json")
    for d in lmcfg.diff(cfg, lmcfg.Config.load("spare.json")):
        print(d.kind, d.upid, d.old, d.new)
    with link.open() as drive:
        outcome = drive.restore(cfg, yes=True)

Ports are those of the program's ``--port``: a serial device, ``tcp://host:port``
(a serial-to-Ethernet gateway) or ``sim:STATE.json`` (the built-in simulated
drive; its state is saved back to the file when the link closes).

Errors raise subclasses of :class:`Error`; each has the ``exit_code`` the
``lmcfg`` program exits with for the same failure.
"""

from __future__ import annotations

import os
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Optional

from ._lmcfg import (
    Config,
    CtEntry,
    Curve,
    Database,
    DbError,
    DbParameter,
    DiffItem,
    Drive,
    DriveRefused,
    Error,
    Interrupted,
    InvalidInput,
    LinkError,
    Parameter,
    Plan,
    PlanRefused,
    PlanStep,
    RestoreOutcome,
    VerifyMismatch,
    diff,
    diff_text,
)
from . import _lmcfg

__all__ = [
    "Config", "CtEntry", "Curve", "Database", "DbError", "DbParameter", "DiffItem", "Drive",
    "DriveRefused", "Error", "Interrupted", "InvalidInput", "Link", "LinkError", "Parameter",
    "Plan", "PlanRefused", "PlanStep", "RestoreOutcome", "VerifyMismatch", "db", "diff",
    "diff_text", "database_path", "open_database",
]

_DB_FILE = "lmcfg-upid.sqlite"


def database_path() -> Optional[str]:
    """Where the UPID database is looked for, in this order: ``$LMCFG_UPID_DB``;
    ``PREFIX/share/lmcfg/`` of an installed package (the package lives in
    ``PREFIX/lib/python3*/dist-packages/lmcfg/``); the build tree's database next
    to the ``lmcfg`` program (``build/python/lmcfg/`` -> ``build/``). None when
    none exists."""
    env = os.environ.get("LMCFG_UPID_DB")
    if env:
        return env
    here = Path(__file__).resolve().parent
    for candidate in (here.parents[3] / "share" / "lmcfg" / _DB_FILE if len(here.parents) > 3
                      else None,
                      here.parents[1] / _DB_FILE):
        if candidate is not None and candidate.is_file():
            return str(candidate)
    return None


def open_database(path: Optional[str] = None) -> Database:
    """Opens the UPID database at ``path`` (default: :func:`database_path`).
    Without one, an empty database with a warning: values are shown raw, as
    the program does."""
    path = path or database_path()
    if path is None:
        warnings.warn("lmcfg: UPID database not found (set LMCFG_UPID_DB); showing raw values")
        return Database()
    return Database.open(path)


#: The UPID database every call uses unless given ``db=``.
db: Database = open_database()


@dataclass
class Link:
    """The link options of the ``lmcfg`` program (README "Link options").

    ``open()`` opens the link and returns a :class:`Drive`, a context manager
    that closes it."""

    port: str
    baud: int = 57600
    id: int = 0x11
    checksum: str = "none"
    parity: str = "none"
    stop_bits: int = 1
    checksum_coverage: str = "id"
    timeout_ms: int = 200
    retries: int = 2
    agreeing_reads: int = 0
    trace: str = ""

    def open(self, db: Optional[Database] = None) -> Drive:
        """Opens the link (raises :class:`LinkError` or :class:`InvalidInput`)."""
        return _lmcfg.open(self.port, baud=self.baud, parity=self.parity,
                           stop_bits=self.stop_bits, id=self.id, checksum=self.checksum,
                           checksum_coverage=self.checksum_coverage,
                           timeout_ms=self.timeout_ms, retries=self.retries,
                           agreeing_reads=self.agreeing_reads, trace=self.trace, db=db)
