# Type stubs of the lmcfg package (the extension module _lmcfg and the Python
# wrapper around it). docs/python.md describes each call.
from typing import Any, Callable, ClassVar, Dict, List, Optional, Sequence, Union
import os

Progress = Callable[[str, int, int], object]
PathLike = Union[str, "os.PathLike[str]"]

class Error(Exception):
    exit_code: ClassVar[int]  # 70: internal error
class InvalidInput(Error): ...  # exit_code 2
class PlanRefused(Error):  # exit_code 3
    plan: Plan
    problems: List[str]
    outcome: RestoreOutcome
class LinkError(Error): ...  # exit_code 4
class DriveRefused(Error): ...  # exit_code 5
class VerifyMismatch(Error):  # exit_code 6
    mismatches: List[str]
    outcome: RestoreOutcome
class Interrupted(Error): ...  # exit_code 130

class DbParameter:
    upid: int
    name: str
    path: str
    description: str
    comm: bool
    default: Optional[int]
    layer: str
    unit: str
    scale: Optional[float]
    min: Optional[int]
    max: Optional[int]
    type: Optional[str]
    labels: Dict[int, str]
    def format(self, raw: int) -> str: ...

class DbError:
    domain: str
    code: int
    text: str
    description: str
    action: str
    error_class: str

class Database:
    def __init__(self) -> None: ...
    @staticmethod
    def open(path: str) -> Database: ...
    is_empty: bool
    path: str
    content_hash: str
    def find(self, upid: int) -> Optional[DbParameter]: ...
    def parameter(self, upid: int) -> DbParameter: ...
    def search(self, text: str) -> List[DbParameter]: ...
    def error(self, domain: str, code: int) -> Optional[DbError]: ...

class Parameter:
    layer: int
    layer_name: str
    upid: int
    value: int
    type: Optional[int]
    default: Optional[int]
    name: str
    unit: str
    scaled: str

class Curve:
    id: int
    info: bytes
    data: bytes

class CtEntry:
    id: int
    raw: bytes

class Config:
    def __init__(self) -> None: ...
    @staticmethod
    def load(path: PathLike, format: Optional[str] = None) -> Config: ...
    @staticmethod
    def loads(text: str, format: str = "json", name: str = "<string>") -> Config: ...
    def save(self, path: PathLike, format: Optional[str] = None,
             db: Optional[Database] = None) -> None: ...
    def dumps(self, format: str = "json", db: Optional[Database] = None) -> str: ...
    parameters: List[Parameter]
    def parameter(self, upid: int) -> Optional[Parameter]: ...
    curves: List[Curve]
    ct_entries: List[CtEntry]
    macid: str
    firmware: str
    captured_at: str
    port: str
    labels: Dict[str, str]
    full: bool
    def __eq__(self, other: object) -> bool: ...

class DiffItem:
    kind: str  # "metadata", "parameter", "curve", "ct_entry", "scope", "devicenet"
    layer: int
    key: int
    upid: Optional[int]
    name: str
    old: str
    new: str
    detail: str
    old_invalid: str
    new_invalid: str

def diff(a: Config, b: Config, ignore_metadata: bool = False, ignore_unit: bool = False,
         db: Optional[Database] = None) -> List[DiffItem]: ...
def diff_text(a: Config, b: Config, a_name: str = "A", b_name: str = "B",
              ignore_metadata: bool = False, ignore_unit: bool = False,
              db: Optional[Database] = None) -> str: ...

class PlanStep:
    action: str
    layer: int
    key: int
    value: int
    old_value: Optional[int]
    text: str
    name: str
    old: str
    new: str
    why: str

class Plan:
    problems: List[str]
    steps: List[PlanStep]
    skipped: List[str]
    notes: List[str]
    losses: List[str]
    write_telegrams: int
    ok: bool
    nothing_to_do: bool
    def json(self) -> str: ...

class RestoreOutcome:
    stage: str
    plan: Plan
    mismatches: List[str]
    written: bool
    link_after: Optional[str]

class Drive:
    def backup(self, layers: Sequence[str] = ..., curves: bool = True,
               command_table: bool = True, full: bool = False, describe: bool = True,
               labels: Dict[str, str] = ..., progress: Optional[Progress] = None) -> Config: ...
    def plan_restore(self, config: Config, default_first: bool = True,
                     include_comm: bool = False, progress: Optional[Progress] = None) -> Plan: ...
    def restore(self, config: Config, yes: bool = False,
                confirm: Optional[Callable[[Plan], bool]] = None, dry_run: bool = False,
                default_first: bool = True, include_comm: bool = False, reset: bool = True,
                recovery: bool = True, progress: Optional[Progress] = None) -> RestoreOutcome: ...
    def close(self) -> None: ...
    port: str
    describe: str
    telegrams: int
    def __enter__(self) -> Drive: ...
    def __exit__(self, *args: Any) -> bool: ...

class Link:
    port: str
    baud: int
    id: int
    checksum: str
    parity: str
    stop_bits: int
    checksum_coverage: str
    timeout_ms: int
    retries: int
    agreeing_reads: int
    trace: str
    def __init__(self, port: str, baud: int = 57600, id: int = 0x11, checksum: str = "none",
                 parity: str = "none", stop_bits: int = 1, checksum_coverage: str = "id",
                 timeout_ms: int = 200, retries: int = 2, agreeing_reads: int = 0,
                 trace: str = "") -> None: ...
    def open(self, db: Optional[Database] = None) -> Drive: ...

db: Database
def database_path() -> Optional[str]: ...
def open_database(path: Optional[str] = None) -> Database: ...
