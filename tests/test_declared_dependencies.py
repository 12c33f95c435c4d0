"""The install the README gives (``pip install -e ".[test]"``) is enough for the tests.

A test that imports a package which only another extra brings (numpydoc came only with
``[docs]``) passes on a machine where that extra happens to be installed and fails on a
fresh one.  These tests read every import of the test suite (and the module-level
imports of the analysis scripts it imports) and check that each third-party module comes
from a distribution that the package's requirements, with the ``test`` extra, bring in:
declared there, or required by one that is (pillow by matplotlib, say).
"""
import ast
import importlib.metadata as md
import pathlib
import sys

import pytest
from packaging.requirements import Requirement

ROOT = pathlib.Path(__file__).resolve().parents[1]


def _local_modules():
    """Names importable from the project's own folders (tests, analysis scripts)."""
    names = {"vibimpact", "tests", "analyses", "conftest", "docs"}
    for folder in (ROOT / "tests", ROOT / "analyses"):
        for path in folder.rglob("*.py"):
            names.add(path.stem)
        for path in folder.rglob("*"):
            if path.is_dir():
                names.add(path.name)
    return names


def _imports(path, module_level_only=False):
    """Top-level names of the modules ``path`` imports (absolute imports only)."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    nodes = tree.body if module_level_only else ast.walk(tree)
    out = set()
    for node in nodes:
        if isinstance(node, ast.Import):
            out.update(a.name.split(".")[0] for a in node.names)
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            out.add(node.module.split(".")[0])
    return out


def third_party_imports():
    """{module: [file, ...]} of the third-party modules the test suite imports."""
    local = _local_modules()
    found = {}
    files = [(p, False) for p in (ROOT / "tests").rglob("*.py")]
    files += [(p, True) for p in (ROOT / "analyses").rglob("*.py")]
    for path, module_level in files:
        for name in _imports(path, module_level):
            if name in sys.stdlib_module_names or name in local or name == "__future__":
                continue
            found.setdefault(name, []).append(str(path.relative_to(ROOT)))
    return found


def _norm(name):
    return name.lower().replace("_", "-").replace(".", "-")


def required_distributions(dist="vibimpact", extras=("test",)):
    """The distributions the install ``dist[extras]`` brings in, transitively, with
    the environment markers evaluated for this interpreter."""
    seen, todo = set(), [(dist, frozenset(extras))]
    while todo:
        name, ext = todo.pop()
        key = (_norm(name), ext)
        if key in seen:
            continue
        seen.add(key)
        try:
            reqs = md.requires(name) or []
        except md.PackageNotFoundError:
            continue
        for text in reqs:
            req = Requirement(text)
            envs = [{"extra": e} for e in ext] or [{"extra": ""}]
            if req.marker is not None and not any(req.marker.evaluate(env) for env in envs):
                continue
            todo.append((req.name, frozenset(req.extras)))
    return {name for name, _ in seen}


def test_the_scan_sees_what_the_suite_imports():
    """Hypothesis: the scan finds the third-party modules the suite is known to use
    (numpy everywhere, compliance_checker in the CF test, numpydoc in the architecture
    test), so an empty answer cannot pass the test below."""
    found = third_party_imports()
    assert {"numpy", "pytest", "compliance_checker", "numpydoc"} <= set(found)


def test_the_requirements_walk_follows_extras_and_markers():
    """Hypothesis: the walk of the requirements brings pytest (the test extra), nolds
    (the crosscheck extra, through the test extra's own reference to it) and pillow
    (matplotlib's requirement), and not the docs' theme (the docs extra only)."""
    dists = required_distributions()
    assert {"pytest", "nolds", "pillow", "numpy"} <= dists
    assert "pydata-sphinx-theme" not in dists
    assert "pydata-sphinx-theme" in required_distributions(extras=("test", "docs"))


@pytest.mark.parametrize("module", sorted(third_party_imports()))
def test_every_module_the_tests_import_comes_with_the_test_install(module):
    """Hypothesis: each third-party module the suite imports belongs to a distribution
    that ``pip install -e ".[test]"`` brings in; numbalsoda (the optional ``bench``
    baseline) is imported only inside a function of an analysis script, so it is not
    scanned."""
    owners = md.packages_distributions().get(module)
    assert owners, f"{module} is imported by the tests but not installed here"
    assert {_norm(o) for o in owners} & required_distributions(), (
        f"{module} (from {owners}) is imported by {third_party_imports()[module]} but "
        "is not brought in by pip install -e '.[test]'; add it to the test extra")
