"""The public API carries type hints (PEP 484) that resolve, and ships ``py.typed``.

The annotations are strings (``from __future__ import annotations``) whose names come
from the module or from its ``if TYPE_CHECKING:`` block; these tests evaluate them the
way a type checker or ``typing.get_type_hints`` would.
"""
import ast
import dataclasses
import importlib
import inspect
import pathlib
import typing

import pytest

import vibimpact

PKG = pathlib.Path(vibimpact.__file__).parent
#: the modules whose public names users call
PUBLIC = ("vibimpact", "vibimpact.analysis", "vibimpact.maps", "vibimpact.plotting",
          "vibimpact.io", "vibimpact.sweeps", "vibimpact.models.presets", "vibimpact.points")


def _public_callables():
    """{function: public name} of every public function and public method."""
    found = {}
    for modname in PUBLIC:
        mod = importlib.import_module(modname)
        for name in getattr(mod, "__all__", [n for n in dir(mod) if not n.startswith("_")]):
            obj = getattr(mod, name, None)
            if inspect.isfunction(obj):
                found.setdefault(obj, f"{modname}.{name}")
            elif inspect.isclass(obj) and obj.__module__.startswith("vibimpact"):
                if not dataclasses.is_dataclass(obj) and "__init__" in vars(obj):
                    found.setdefault(obj.__init__, f"{modname}.{name}.__init__")
                for key, value in vars(obj).items():
                    if isinstance(value, (classmethod, staticmethod)):
                        value = value.__func__
                    if inspect.isfunction(value) and not key.startswith("_"):
                        found.setdefault(value, f"{modname}.{name}.{key}")
    return found


def _type_checking_names(module):
    """The module's globals plus what its ``if TYPE_CHECKING:`` block imports."""
    ns = dict(vars(module))
    tree = ast.parse(pathlib.Path(module.__file__).read_text())
    for node in tree.body:
        if isinstance(node, ast.If) and getattr(node.test, "id", None) == "TYPE_CHECKING":
            code = compile(ast.Module(body=node.body, type_ignores=[]), module.__file__,
                           "exec")
            exec(code, ns)
    return ns


CALLABLES = _public_callables()


def test_the_public_api_is_large_enough_to_mean_something():
    """The enumeration finds the public API (a broken one would pass every test below)."""
    names = set(CALLABLES.values())
    assert len(names) >= 70
    assert {"vibimpact.simulate", "vibimpact.sweep", "vibimpact.map2d",
            "vibimpact.analysis.lyapunov_spectrum"} <= names


@pytest.mark.parametrize("fn", list(CALLABLES), ids=list(CALLABLES.values()))
def test_every_public_callable_is_fully_annotated_and_resolves(fn):
    """Every parameter (but self/cls, *args, **kwargs) and the return (but of __init__)
    of a public function or method is annotated, and every annotation evaluates to a
    type in the module's namespace plus its TYPE_CHECKING imports."""
    sig = inspect.signature(fn)
    missing = [n for n, p in sig.parameters.items()
               if n not in ("self", "cls") and p.annotation is inspect.Parameter.empty
               and p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD)]
    if fn.__name__ != "__init__" and sig.return_annotation is inspect.Signature.empty:
        missing.append("return")
    assert not missing, missing
    ns = _type_checking_names(importlib.import_module(fn.__module__))
    hints = typing.get_type_hints(fn, globalns=ns)
    assert set(hints) >= {n for n, p in sig.parameters.items()
                          if p.annotation is not inspect.Parameter.empty}


def test_the_package_declares_its_hints():
    """py.typed (PEP 561) is in the package and declared as package data."""
    assert (PKG / "py.typed").is_file()
    assert '"py.typed"' in (PKG.parent / "pyproject.toml").read_text()
