"""The type stubs (lmcfg/__init__.pyi, shipped with py.typed) name what the
package has: every public name, and every attribute and method of each class."""

import ast
from pathlib import Path

import lmcfg

PACKAGE = Path(lmcfg.__file__).parent


def stub_tree():
    return ast.parse((PACKAGE / "__init__.pyi").read_text())


def test_package_ships_stubs_and_py_typed():
    assert (PACKAGE / "py.typed").is_file()
    assert (PACKAGE / "__init__.pyi").is_file()


def test_every_public_name_has_a_stub_and_every_stub_exists():
    stubbed = set()
    for node in stub_tree().body:
        if isinstance(node, (ast.ClassDef, ast.FunctionDef)):
            stubbed.add(node.name)
        elif isinstance(node, ast.AnnAssign):
            stubbed.add(node.target.id)
    public = set(lmcfg.__all__)
    assert public <= stubbed, public - stubbed
    helpers = {"Progress", "PathLike"}  # type aliases of the stub
    for name in stubbed - helpers:
        assert hasattr(lmcfg, name), name


def test_class_members_in_the_stubs_exist():
    for node in stub_tree().body:
        if not isinstance(node, ast.ClassDef):
            continue
        cls = getattr(lmcfg, node.name)
        for member in node.body:
            if isinstance(member, ast.FunctionDef):
                name = member.name
            elif isinstance(member, ast.AnnAssign):
                name = member.target.id
            else:
                continue
            if name.startswith("__") and name not in ("__enter__", "__exit__"):
                continue
            # Instance attributes of exceptions are set when raised.
            if issubclass(cls, BaseException) and name != "exit_code":
                continue
            if cls is lmcfg.Link:  # dataclass fields
                assert name in lmcfg.Link.__dataclass_fields__ or hasattr(cls, name), name
                continue
            assert hasattr(cls, name), f"{node.name}.{name}"


def test_docstrings():
    for name in ("Drive", "Config", "Database", "Plan", "Error", "Link"):
        assert getattr(lmcfg, name).__doc__
    assert lmcfg.Drive.backup.__doc__ and "lmcfg backup" in lmcfg.Drive.backup.__doc__
    assert lmcfg.diff.__doc__
