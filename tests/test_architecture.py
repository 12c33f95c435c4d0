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


def _runner_settings():
    """The names a public runner must not take as parameters: every field of
    ``SolverSettings``, ``Execution`` and ``Continuation`` (each travels as one object:
    ``solver=``, ``execution=``, ``continuation=``) and every argument of ``System``
    that is one setting rather than a whole object (``params``, ``model`` and
    ``solver`` are the objects a runner may take beside a bare parameter set)."""
    import dataclasses

    import vibimpact as vi

    fields = {f.name for cls in (vi.SolverSettings, vi.Execution, vi.Continuation)
              for f in dataclasses.fields(cls)}
    return fields | (set(inspect.signature(vi.System).parameters)
                     - {"params", "model", "solver"})


def _signature_names(fn):
    return [("**" if p.kind == p.VAR_KEYWORD else "*" if p.kind == p.VAR_POSITIONAL else "")
            + p.name for p in inspect.signature(fn).parameters.values()]


def _runners():
    import vibimpact as vi

    return [vi.simulate, vi.sweep, vi.map2d]


@pytest.mark.parametrize("fn", _runners(), ids=lambda f: f.__name__)
def test_the_public_runners_take_settings_as_objects_not_keywords(fn):
    """Hypothesis: ``vi.simulate``, ``vi.sweep`` and ``vi.map2d`` take no parameter named
    like a field of ``SolverSettings``, ``Execution`` or ``Continuation`` or like a
    single setting among ``System``'s arguments (the rule that replaced a parameter
    count set to today's maximum of eight): solver, execution and continuation settings
    are one object each, not a keyword each."""
    clash = sorted(set(inspect.signature(fn).parameters) & _runner_settings())
    assert clash == [], (fn.__name__, clash)


@pytest.mark.parametrize("fn", _runners(), ids=lambda f: f.__name__)
def test_every_runner_parameter_is_documented_in_signature_order(fn):
    """Hypothesis: the numpydoc Parameters section of each public runner lists exactly
    its signature's parameters, in order (``**kwargs`` with its stars): a parameter
    added, removed, renamed or moved without its documentation fails."""
    assert _documented_parameters(fn) == _signature_names(fn), fn.__name__


def test_the_runner_rules_catch_a_setting_keyword_and_an_undocumented_parameter():
    """Hypothesis: the two runner rules can fail: a runner taking ``workers`` (an
    Execution field), ``rtol`` (a solver setting and a System argument) or ``blocks`` (a
    Continuation field) clashes, and one whose Parameters section omits its ``**kwargs``
    or swaps two parameters is not in signature order; the shipped names ``p``,
    ``model``, ``solver``, ``execution`` pass."""
    def bad(p, eta, *, workers=1, rtol=1e-9, blocks=4, model=None, solver=None,
            execution=None, **extra):
        """Bad.

        Parameters
        ----------
        eta : array_like
        p : Params
        """

    assert sorted(set(inspect.signature(bad).parameters) & _runner_settings()) == [
        "blocks", "rtol", "workers"]
    assert _documented_parameters(bad) != _signature_names(bad)
    assert _documented_parameters(bad) == ["eta", "p"]


def test_imports_run_downwards():
    """The kernel imports nothing above it; the library never imports the command line
    (the CLI is on top, the kernel at the bottom)."""
    bad = []
    for path in _modules():
        rel = path.relative_to(PKG)
        in_kernel = rel.parts[0] == "_kernel"
        is_cli = rel.parts[0] == "cli" or rel.name == "__main__.py"
        for mod, name in _imports(path):
            if not mod.startswith("vibimpact"):
                continue
            full = f"{mod}.{name}" if name else mod
            if in_kernel and not mod.startswith("vibimpact._kernel"):
                bad.append(f"{rel}: {full}")
            if not is_cli and full.startswith("vibimpact.cli"):
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


def _system_settings():
    """The names of what a ``System`` holds: its constructor's parameters (parameter set,
    model, solver settings) and every field of ``SolverSettings``."""
    import dataclasses

    import vibimpact as vi

    return ({p for p in inspect.signature(vi.System).parameters}
            | {f.name for f in dataclasses.fields(vi.SolverSettings)})


def _takes_a_system(fn):
    params = list(inspect.signature(fn).parameters.values())
    return bool(params) and params[0].name == "system"


def _analysers():
    """``ANALYSERS`` and every other public function of the analysis packages whose first
    parameter is a ``system`` (a new analyser is checked without being listed)."""
    import importlib

    found = {(m, n) for m, n in ANALYSERS}
    for module in ("vibimpact.analysis", "vibimpact.points", "vibimpact.orbits",
                   "vibimpact.census"):
        mod = importlib.import_module(module)
        for name in getattr(mod, "__all__", ()):
            obj = getattr(mod, name)
            if inspect.isfunction(obj) and _takes_a_system(obj):
                found.add((module, name))
    return sorted(found)


def _documented_parameters(fn):
    """Parameter names of ``fn``'s numpydoc Parameters section, in order (``a, b : x``
    documents two; ``**changes`` keeps its stars)."""
    from numpydoc.docscrape import FunctionDoc

    names = []
    for p in FunctionDoc(fn)["Parameters"]:
        names += [n.strip() for n in p.name.split(",") if n.strip()]
    return names


@pytest.mark.parametrize("module, name", _analysers(), ids=[a[1] for a in _analysers()])
def test_analysers_take_a_system_and_no_setting_of_it(module, name):
    """Hypothesis: each analyser of a model's trajectories takes a ``System`` first and
    none of the System's own settings beside it: no parameter is named like an argument
    of ``System`` (``params``, ``model``, ``method``, ``rtol``, ``atol``, ...) or a field
    of ``SolverSettings`` (the rule that replaced a parameter count tuned to today's
    maximum: the model, its parameters and the solver travel in one value)."""
    import importlib

    fn = getattr(importlib.import_module(module), name)
    params = list(inspect.signature(fn).parameters.values())
    assert params[0].name == "system", (name, params[0].name)
    clash = sorted({p.name for p in params[1:]} & _system_settings())
    assert not clash, (name, clash)


@pytest.mark.parametrize("module, name", _analysers(), ids=[a[1] for a in _analysers()])
def test_every_analyser_parameter_is_documented_in_signature_order(module, name):
    """Hypothesis: the numpydoc Parameters section of each analyser lists exactly its
    signature's parameters, in the signature's order (``*args`` / ``**kwargs`` with their
    stars): a parameter added, removed, renamed or moved without its documentation
    fails."""
    import importlib

    fn = getattr(importlib.import_module(module), name)
    sig = [("**" if p.kind == p.VAR_KEYWORD else "*" if p.kind == p.VAR_POSITIONAL else "")
           + p.name for p in inspect.signature(fn).parameters.values()]
    assert _documented_parameters(fn) == sig, name


def test_the_analyser_rules_catch_a_settings_parameter_and_an_undocumented_one():
    """Hypothesis: the two analyser rules above can fail: a function taking ``rtol``
    beside its system clashes with the System's settings, and one whose Parameters
    section skips a parameter or swaps two is not in signature order."""
    def bad(system, state0, *, rtol=1e-8):
        """Bad.

        Parameters
        ----------
        state0 : array_like
        system : System
        """

    assert {"rtol"} <= ({p for p in inspect.signature(bad).parameters}
                        & _system_settings())
    assert _documented_parameters(bad) != [p for p in inspect.signature(bad).parameters]


DOCS = PKG.parent / "docs" / "internals.rst"
#: the comment that introduces the layer table in ``docs/internals.rst``
TABLE_MARK = ".. The layer table"


def _table_rows(text):
    """The rows of the layer table in ``text`` (an rst page): the lines of the code block
    after the comment :data:`TABLE_MARK`, each as the tuple of its leading folders
    (``name/``) and modules (``name.py``), the words before its description."""
    lines = text[text.index(TABLE_MARK):].splitlines()
    at = next(i for i, line in enumerate(lines) if line.startswith(".. code-block::"))
    rows = []
    for line in lines[at + 1:]:
        if line and not line.startswith(" "):
            break
        names = []
        for word in line.split():
            if not (word.endswith("/") or word.endswith(".py")):
                break
            names.append(word)
        if names:
            rows.append(tuple(names))
    return rows


def _unit_of_entry(name):
    """The layer unit a table entry names: a folder ``sweeps/`` is ``sweeps``, a
    top-level module ``__main__.py`` is ``__main__``, the package root ``__init__.py``
    is ``""``."""
    stem = name[:-1] if name.endswith("/") else name[:-3]
    return "" if stem == "__init__" else stem


def _layer_table(text):
    """The layers, top to bottom, as tuples of units (:func:`_unit_of_entry`)."""
    return tuple(tuple(_unit_of_entry(n) for n in row) for row in _table_rows(text))


#: the package's layers, top to bottom, read from the table in ``docs/internals.rst``: a
#: module may import its own layer and those below.  A module's layer is that of its
#: top folder (a top-level module's its own, the package root's "": it imports no
#: vibimpact module, its public names are loaded lazily, by name, from the table
#: ``_EXPORTS``, and an import of one of them is charged to the module that defines it).
LAYERS = _layer_table(DOCS.read_text())


def _units_on_disk():
    """The units of the package's top level: every folder holding ``__init__.py`` by its
    name, every top-level module by its name, the package root as ""."""
    folders = {d.name for d in PKG.iterdir() if (d / "__init__.py").is_file()}
    modules = {"" if f.stem == "__init__" else f.stem for f in PKG.glob("*.py")}
    return folders | modules


def test_the_layer_table_of_the_docs_names_exactly_the_folders_of_the_package():
    """Hypothesis: the layer table of ``docs/internals.rst`` names every folder and
    top-level module of ``vibimpact/`` once and nothing else, so the folder tree and the
    page agree (a folder added, removed or renamed without the page fails), and the
    top level holds only packages besides ``__init__.py`` and ``__main__.py``."""
    named = [u for layer in LAYERS for u in layer]
    assert len(LAYERS) >= 10, LAYERS
    assert sorted(named) == sorted(set(named)), named
    assert set(named) == _units_on_disk(), (set(named) ^ _units_on_disk())
    assert sorted(f.name for f in PKG.glob("*.py")) == ["__init__.py", "__main__.py"]


def _unit(dotted):
    """The layer unit of a module: its top folder or top-level module name ("" for the
    package root)."""
    parts = dotted.split(".")
    return parts[1] if len(parts) > 1 else ""


def _layer(dotted):
    """The index in :data:`LAYERS` of the layer of module ``dotted`` (0 the top), or
    None."""
    unit = _unit(dotted)
    return next((i for i, units in enumerate(LAYERS) if unit in units), None)


def test_the_table_reader_takes_each_rows_leading_folders_only():
    """Hypothesis: the reader of the layer table keeps a row's folders and modules and
    stops at its description (which may name folders too), skips blank lines and ends
    with the block."""
    text = ("x\n\n.. The layer table\n\n.. code-block:: text\n\n"
            "   cli/ __main__.py   the command line, cli/common/ shared\n\n"
            "   io/                files\n"
            "   base/ __init__.py  vocabulary\n\nAfter the block: sweeps/\n")
    assert _layer_table(text) == (("cli", "__main__"), ("io",), ("base", ""))


def _exports():
    """The package root's lazy table: public name -> defining module (dotted)."""
    tree = _tree(PKG / "__init__.py")
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(
                getattr(t, "id", None) == "_EXPORTS" for t in node.targets):
            table = ast.literal_eval(node.value)
            return {k: f"vibimpact.{mod}" for k, (mod, _) in table.items()}
    raise AssertionError("vibimpact/__init__.py has no _EXPORTS table")


def _dependencies(path):
    """The vibimpact modules ``path`` uses: ``from x import y`` (y a module or a name of
    x), and for the package root the defining module of every name taken from it
    (``from vibimpact import sweep``, ``vi.sweep`` after ``import vibimpact as vi``)."""
    exports = _exports()
    aliases = set()
    for node in ast.walk(_tree(path)):
        if isinstance(node, ast.Import):
            for a in node.names:
                if a.name == "vibimpact":
                    aliases.add(a.asname or a.name)
                elif a.name.startswith("vibimpact."):
                    yield a.name
        elif isinstance(node, ast.ImportFrom):
            mod = _resolve(path, node)
            if not mod.startswith("vibimpact"):
                continue
            for a in node.names:
                sub = f"{mod}.{a.name}"
                if _is_module(sub):
                    yield sub
                elif mod == "vibimpact":
                    yield exports.get(a.name, "vibimpact")
                else:
                    yield mod
        elif isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) \
                and node.value.id in aliases:
            yield exports.get(node.attr, "vibimpact")
    if aliases:
        yield "vibimpact"


def test_every_module_is_in_exactly_one_layer():
    """Hypothesis: every module of the package -- top-level modules, the package root and
    every module of every folder -- belongs to exactly one layer of ``LAYERS``, by its top
    folder (a new folder must be placed in the table, none is let through for being in
    no layer)."""
    missing, twice = [], []
    for path in _modules():
        unit = _unit(_module_name(path))
        hits = [i for i, units in enumerate(LAYERS) if unit in units]
        if not hits:
            missing.append(str(path.relative_to(PKG)))
        elif len(hits) > 1:
            twice.append(str(path.relative_to(PKG)))
    assert not missing and not twice, (missing, twice)


def test_the_package_root_imports_no_module_of_the_package():
    """Hypothesis: ``vibimpact/__init__.py`` imports no vibimpact module by an import
    statement (its public names load lazily from ``_EXPORTS``), which is what puts the
    root in the bottom layer."""
    assert [m for m in _dependencies(PKG / "__init__.py") if m != "vibimpact"] == []


def test_packages_import_no_layer_above_their_own():
    """Hypothesis: every module uses only modules of its own layer or below (``LAYERS``,
    top to bottom: the CLI on the studies, they on the engine, it on the point pipeline,
    that on the analysers, they on simulate, simulate on System and its Solver, they on
    runs and models, models on the kernel), a name taken from the package root counting
    as its defining module; so no two packages import each other."""
    bad = []
    for path in _modules():
        own = _layer(_module_name(path))
        for dep in _dependencies(path):
            other = _layer(dep)
            if other is not None and other < own:
                bad.append(f"{path.relative_to(PKG)}: {dep}")
    assert not bad, bad


def test_the_layer_rule_catches_an_upward_import(tmp_path):
    """Hypothesis: the layer check fails for a module below the studies that imports
    ``vibimpact.sweeps`` directly, or takes ``sweep`` from the package root (``from
    vibimpact import sweep`` or ``vi.sweep``)."""
    for i, src in enumerate(("from vibimpact.sweeps import sweep\n",
                             "from vibimpact import sweep\n",
                             "import vibimpact as vi\nvi.sweep\n")):
        f = tmp_path / f"probe{i}.py"
        f.write_text(src)
        deps = list(_dependencies(f))
        assert any(_layer(d) is not None and _layer(d) < _layer("vibimpact.core.run")
                   for d in deps), (src, deps)


CLI = PKG / "cli"


def _commands():
    """The command modules of the command line: the modules directly in ``cli/`` other
    than its ``__init__.py`` (the registration table) and ``__main__.py``."""
    return sorted(p for p in CLI.glob("*.py") if p.stem not in ("__init__", "__main__"))


def _command_imports(path):
    """The command modules (dotted) that ``path`` uses, the registration package
    ``vibimpact.cli`` itself included (lazy imports inside functions count)."""
    commands = {_module_name(p) for p in _commands()}
    own = _module_name(path) if PKG in path.parents else None
    return sorted({d for d in _dependencies(path) if d in commands or d == "vibimpact.cli"}
                  - {own})


def test_no_command_imports_another_command():
    """Hypothesis: no command module of ``cli/`` imports another command module or the
    registration table ``vibimpact.cli`` (what two commands share is in ``cli/common/``,
    or in a layer below), and no module of ``cli/common/`` imports a command: ``plot``
    draws a map, a branch and a census without importing ``map``, ``continue`` or
    ``attractors``."""
    shared = sorted((CLI / "common").rglob("*.py"))
    bad = {str(p.relative_to(PKG)): _command_imports(p) for p in _commands() + shared}
    assert {k: v for k, v in bad.items() if v} == {}


def test_the_command_rule_catches_an_import_of_another_command(tmp_path):
    """Hypothesis: the command rule sees a command taken from another command's module,
    at module level or inside a function, and the registration table imported."""
    for i, src in enumerate(("from vibimpact.cli.map import parse_vary\n",
                             "def f():\n    from vibimpact.cli import continue_\n",
                             "from vibimpact.cli import build_parser\n")):
        f = tmp_path / f"probe{i}.py"
        f.write_text(src)
        assert _command_imports(f), src


def test_the_registration_table_names_every_command_module_once():
    """Hypothesis: ``vibimpact.cli.COMMANDS`` maps each command name to a command module
    of ``cli/``, every command module is in it exactly once, and each has the
    ``add_parser(sub, fmt)`` the parser is built with; the commands ``--help`` lists
    are the table's, in its order."""
    import argparse
    import importlib

    from vibimpact import cli

    assert sorted(cli.COMMANDS.values()) == [p.stem for p in _commands()]
    for module in cli.COMMANDS.values():
        add = importlib.import_module(f"vibimpact.cli.{module}").add_parser
        assert list(inspect.signature(add).parameters) == ["sub", "fmt"], module
    sub = next(a for a in cli.build_parser()._actions
               if isinstance(a, argparse._SubParsersAction))
    assert list(sub.choices) == list(cli.COMMANDS)


def test_help_of_the_program_and_of_every_command_imports_nothing_heavy(tmp_path):
    """Hypothesis: ``vibimpact --help`` and ``vibimpact COMMAND --help`` for every command
    of the registration table, run one after the other in one fresh process through the
    script's entry point (``vibimpact.__main__.run``), exit 0 and leave numba, numpy,
    xarray, SciPy and matplotlib unimported: building the parser imports every command
    module, and none of them imports a heavy library at module level."""
    import subprocess
    import sys

    code = ("import sys\nfrom vibimpact.__main__ import run\nfrom vibimpact.cli import "
            "COMMANDS\nfor argv in [[]] + [[c] for c in COMMANDS]:\n"
            "    sys.argv = ['vibimpact', *argv, '--help']\n    try:\n        run()\n"
            "    except SystemExit as e:\n        assert e.code == 0, (argv, e.code)\n"
            "heavy = [m for m in ('numba', 'numpy', 'xarray', 'scipy', 'matplotlib') "
            "if m in sys.modules]\nprint('HEAVY', heavy)\n")
    r = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True,
                       text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    assert r.stdout.splitlines()[-1] == "HEAVY []", r.stdout[-300:]
