"""The package's structure: one door into the kernel, imports that run one way, small
functions, analysers that take a System."""
import ast
import inspect
import pathlib

import pytest

PKG = pathlib.Path(__file__).resolve().parents[1] / "vibimpact"
MAX_LINES = 120


def _modules():
    return sorted(PKG.rglob("*.py"))


def _tree(path):
    return ast.parse(path.read_text(), filename=str(path))


def _module_name(path):
    rel = path.relative_to(PKG.parent).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join(parts)


def _resolve(path, node):
    """Absolute module name of an ``ImportFrom`` in ``path``."""
    if node.level == 0:
        return node.module or ""
    base = _module_name(path).split(".")
    if path.name != "__init__.py":
        base = base[:-1]
    base = base[:len(base) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))


def _imports(path):
    """``(module, name)`` of every ``from module import name`` in ``path``."""
    for node in ast.walk(_tree(path)):
        if isinstance(node, ast.ImportFrom):
            mod = _resolve(path, node)
            for alias in node.names:
                yield mod, alias.name
        elif isinstance(node, ast.Import):
            for alias in node.names:
                yield alias.name, None


def _is_module(dotted):
    rel = pathlib.Path(*dotted.split("."))
    return (PKG.parent / rel).with_suffix(".py").exists() or (PKG.parent / rel).is_dir()


def _body_lines(fn):
    """Lines of a function without its docstring."""
    n = fn.end_lineno - fn.lineno + 1
    body = fn.body
    if body and isinstance(body[0], ast.Expr) and isinstance(
            getattr(body[0], "value", None), ast.Constant) and isinstance(
            body[0].value.value, str):
        n -= body[0].end_lineno - body[0].lineno + 1
    return n


def test_no_function_is_longer_than_120_lines():
    """Every function and method of the package is at most 120 lines long, docstring
    excluded (a reader sees one on a screen or two)."""
    long = []
    for path in _modules():
        for node in ast.walk(_tree(path)):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                n = _body_lines(node)
                if n > MAX_LINES:
                    long.append(f"{path.relative_to(PKG)}:{node.name} ({n} lines)")
    assert not long, long


def test_no_module_imports_a_private_name_of_another_module():
    """``from x import _name`` appears only for private *modules* (``_validate``,
    ``_kernel``, ``_limits``): a module's underscore names are its own."""
    bad = []
    for path in _modules():
        for mod, name in _imports(path):
            if name and name.startswith("_") and not name.startswith("__") \
                    and mod.startswith("vibimpact") and not _is_module(f"{mod}.{name}"):
                bad.append(f"{path.relative_to(PKG)}: from {mod} import {name}")
    assert not bad, bad


def test_everything_above_the_kernel_imports_only_its_boundary():
    """Outside ``vibimpact/_kernel/`` the only kernel module any module imports is
    ``_kernel/boundary.py`` (no exception for any module): every kernel call, kernel
    model and kernel constant is reached through the boundary."""
    bad = []
    for path in _modules():
        if "_kernel" in path.relative_to(PKG).parts:
            continue
        for mod, name in _imports(path):
            full = f"{mod}.{name}" if name and _is_module(f"{mod}.{name}") else mod
            if full.startswith("vibimpact._kernel") and full not in (
                    "vibimpact._kernel.boundary",):
                bad.append(f"{path.relative_to(PKG)}: {full}")
    assert not bad, bad


def test_the_public_runners_take_at_most_8_parameters():
    """``vi.simulate``, ``vi.sweep`` and ``vi.map2d`` take at most eight parameters:
    solver settings and execution settings are one object each, not a keyword each."""
    import vibimpact as vi

    for fn in (vi.simulate, vi.sweep, vi.map2d):
        params = [p for p in inspect.signature(fn).parameters.values()
                  if p.kind not in (p.VAR_KEYWORD, p.VAR_POSITIONAL)]
        assert len(params) <= 8, (fn.__name__, [p.name for p in params])


def test_imports_run_downwards():
    """The kernel imports nothing above it; the library never imports the command line
    (the CLI is on top, the kernel at the bottom)."""
    bad = []
    for path in _modules():
        rel = path.relative_to(PKG)
        in_kernel = rel.parts[0] == "_kernel"
        is_cli = rel.name.startswith("cli") or rel.name in ("_cli_common.py", "__main__.py")
        for mod, name in _imports(path):
            if not mod.startswith("vibimpact"):
                continue
            full = f"{mod}.{name}" if name else mod
            if in_kernel and not mod.startswith("vibimpact._kernel"):
                bad.append(f"{rel}: {full}")
            if not is_cli and (".cli" in full or "_cli_common" in full):
                bad.append(f"{rel}: {full}")
    assert not bad, bad


ANALYSERS = [
    ("vibimpact.analysis", "lyapunov_spectrum"),
    ("vibimpact.analysis", "largest_lyapunov"),
    ("vibimpact.analysis", "floquet_lyapunov"),
    ("vibimpact.analysis", "shoot_periodic_orbit"),
    ("vibimpact.analysis", "monodromy"),
    ("vibimpact.analysis", "continue_orbit"),
    ("vibimpact.analysis", "locate_bifurcation"),
    ("vibimpact.points", "classify_params"),
    ("vibimpact.analysis", "strobe_map_jacobian"),
]


@pytest.mark.parametrize("module, name", ANALYSERS, ids=[a[1] for a in ANALYSERS])
def test_analysers_take_a_system_and_at_most_8_further_parameters(module, name):
    """Each analyser of a model's trajectories takes a ``System`` first (model,
    parameters, solver settings in one value) and no more than eight parameters of the
    analysis itself."""
    import importlib
    fn = getattr(importlib.import_module(module), name)
    params = list(inspect.signature(fn).parameters.values())
    assert params[0].name == "system", (name, params[0].name)
    further = [p for p in params[1:] if p.kind not in (p.VAR_KEYWORD, p.VAR_POSITIONAL)]
    assert len(further) <= 8, (name, [p.name for p in further])


#: the package's layers, top to bottom: a module may import its own layer and those below
LAYERS = (("sweeps", "maps", "plotting"), ("engine",), ("points",), ("analysis",),
          ("simulation",), ("system", "solver"), ("_kernel",))


def _layer(dotted):
    parts = dotted.split(".")
    top = parts[1] if len(parts) > 1 else ""
    for i, names in enumerate(LAYERS):
        if top in names:
            return i
    return None


def test_packages_import_no_layer_above_their_own():
    """Hypothesis: sweeps and maps stand on the engine, the engine on the point pipeline,
    the point pipeline on the analysers, they on simulate, simulate on System and its
    solver (one layer: a Solver integrates a System), they on the kernel; no module
    imports from a layer above its own (so no two packages import each other)."""
    bad = []
    for path in _modules():
        own = _layer(_module_name(path))
        if own is None:
            continue
        for mod, name in _imports(path):
            if not mod.startswith("vibimpact"):
                continue
            sub = f"{mod}.{name}" if name else mod
            other = _layer(sub if name and _is_module(sub) else mod)
            if other is not None and other < own:
                bad.append(f"{path.relative_to(PKG)}: {mod}")
    assert not bad, bad
