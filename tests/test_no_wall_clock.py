"""No test asserts on a wall clock (issue 32, part 2).

A test that says "refused before any work" or "ends without a hang" with ``assert
elapsed < 20`` passes on a fast machine and fails on a loaded one, and proves nothing
about the work: it is proved by what was computed or written (counters, files, progress
lines).  A hang is guarded by a bounded wait that fails the test (``timeout=`` of a
subprocess, a loop past a deadline that calls ``pytest.fail``), which is a guard, not a
claim, and is never an ``assert``.

The scan is a taint analysis of each test file:

* a *clock* is ``time.time``, ``time.perf_counter``, ``time.monotonic``,
  ``time.process_time``, ``time.thread_time`` (and their ``_ns`` forms), and
  ``datetime.now`` / ``utcnow`` / ``today`` and ``date.today``, however imported:
  ``import time as t``, ``from time import monotonic as m``, ``import datetime as dt``,
  ``from datetime import datetime as D``, anywhere in the file;
* a value is *tainted* when its expression mentions a clock (called or not) or a
  tainted name: through arithmetic, any call wrapping it (``float``, ``round``,
  ``min``, ``max``, a helper's arguments), subscripts, attributes, tuples; a name or
  attribute (``self.t0``) assigned a tainted value is tainted (at module level for the
  whole file, in a function for that function), and so is a call of a function of the
  file that returns a tainted value;
* every ``assert`` whose test involves a tainted value is reported, and so is every
  ``self.assert...(...)`` call with a tainted argument, and every ``if`` on a tainted
  value that fails the test (``pytest.fail``, ``raise``) outside a loop: a hang guard
  bounds a loop that waits for something; the same check after the work is a
  wall-clock assert written another way.

A time stamp handed to a checker inside an assert is reported too: a test takes its
stamp from the file system (a file's ``st_mtime``) instead of a clock.
"""
import ast
import re
from pathlib import Path

TESTS = Path(__file__).resolve().parent

#: the clock functions of the ``time`` module
TIME_CLOCKS = {"time", "perf_counter", "monotonic", "process_time", "thread_time",
               "time_ns", "perf_counter_ns", "monotonic_ns", "process_time_ns",
               "thread_time_ns"}
#: the clock methods of ``datetime.datetime`` and ``datetime.date``
DATETIME_CLOCKS = {"now", "utcnow", "today"}


class _Clocks:
    """The names that stand for the ``time`` module, the ``datetime`` module, its
    ``datetime``/``date`` classes and clock functions in one file, from its imports."""

    def __init__(self, tree):
        self.time_mods, self.dt_mods, self.dt_classes, self.funcs = set(), set(), set(), set()
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):
                for a in node.names:
                    if a.name == "time":
                        self.time_mods.add(a.asname or "time")
                    elif a.name == "datetime":
                        self.dt_mods.add(a.asname or "datetime")
            elif isinstance(node, ast.ImportFrom) and node.module in ("time", "datetime"):
                for a in node.names:
                    name = a.asname or a.name
                    if node.module == "time" and a.name in TIME_CLOCKS:
                        self.funcs.add(name)
                    elif node.module == "datetime" and a.name in ("datetime", "date"):
                        self.dt_classes.add(name)

    def is_clock(self, node):
        """Whether the expression ``node`` (a Name or an Attribute) names a clock."""
        if isinstance(node, ast.Name):
            return node.id in self.funcs
        if not isinstance(node, ast.Attribute):
            return False
        base = node.value
        if isinstance(base, ast.Name) and base.id in self.time_mods:
            return node.attr in TIME_CLOCKS
        if node.attr not in DATETIME_CLOCKS:
            return False
        if isinstance(base, ast.Name):
            return base.id in self.dt_classes
        return (isinstance(base, ast.Attribute) and base.attr in ("datetime", "date")
                and isinstance(base.value, ast.Name) and base.value.id in self.dt_mods)


def _key(node):
    """``"x"`` or ``"self.t0"``: how an assigned name or attribute is remembered."""
    if isinstance(node, (ast.Name, ast.Attribute)):
        return ast.unparse(node)
    return None


#: the taint of a whole value (a name's, a function's return): every part of it
WHOLE = "whole"


def _mask(node, clocks, names, funcs):
    """The taint of ``node`` itself, not of its parts: None (none), :data:`WHOLE`, or the
    tainted positions of a tuple-valued name or of a call returning a tuple."""
    if clocks.is_clock(node):
        return WHOLE
    key = _key(node)
    if key is not None and key in names:
        return names[key]
    if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and \
            node.func.id in funcs:
        return funcs[node.func.id]
    return None


def _tainted(node, clocks, names, funcs):
    """Whether expression ``node`` involves a clock, a tainted name or attribute, or a
    call of a function that returns a tainted value; ``x[i]`` of a tuple-valued ``x``
    is tainted only for a tainted position ``i``, any other use of ``x`` always."""
    if isinstance(node, ast.Subscript):
        mask = _mask(node.value, clocks, names, funcs)
        sl = node.slice
        if isinstance(mask, frozenset) and isinstance(sl, ast.Constant) and \
                isinstance(sl.value, int):
            return sl.value in mask
    if _mask(node, clocks, names, funcs) is not None:
        return True
    return any(_tainted(c, clocks, names, funcs) for c in ast.iter_child_nodes(node))


def _value_taint(value, clocks, names, funcs):
    """The taint an assignment of ``value`` passes on: None, :data:`WHOLE`, or the
    tainted positions of a tuple (a literal tuple, or a tuple-valued name or call)."""
    if isinstance(value, ast.Tuple):
        pos = frozenset(i for i, e in enumerate(value.elts)
                        if _tainted(e, clocks, names, funcs))
        return pos or None
    mask = _mask(value, clocks, names, funcs)
    if mask is not None:
        return mask
    return WHOLE if _tainted(value, clocks, names, funcs) else None


def _assigned(node):
    """``[(target, value)]`` of an assignment, a ``for`` loop, a ``with ... as`` and a
    walrus."""
    if isinstance(node, ast.Assign):
        return [(t, node.value) for t in node.targets]
    if isinstance(node, (ast.AugAssign, ast.AnnAssign, ast.NamedExpr)) and \
            node.value is not None:
        return [(node.target, node.value)]
    if isinstance(node, (ast.For, ast.AsyncFor)):
        return [(node.target, node.iter)]
    if isinstance(node, ast.withitem) and node.optional_vars is not None:
        return [(node.optional_vars, node.context_expr)]
    return []


def _bind(target, taint, names):
    """Give ``target`` (a name, an attribute, a tuple of them) the taint ``taint``;
    whether ``names`` changed."""
    changed = False
    if isinstance(target, (ast.Tuple, ast.List)):
        for i, t in enumerate(target.elts):
            sub = taint if taint == WHOLE else (WHOLE if i in taint else None)
            if sub is not None:
                changed |= _bind(t, sub, names)
        return changed
    if isinstance(target, ast.Starred):
        return _bind(target.value, WHOLE, names)
    key = _key(target)
    if key is None or names.get(key) == WHOLE or names.get(key) == taint:
        return False
    names[key] = WHOLE if key in names else taint  # two different taints: all of it
    return True


def _fails(body):
    """Whether the statements ``body`` fail the test: a ``raise`` or a call of a
    function named ``fail`` (``pytest.fail``)."""
    for n in (m for stmt in body for m in ast.walk(stmt)):
        if isinstance(n, ast.Raise):
            return True
        if isinstance(n, ast.Call) and (getattr(n.func, "attr", None) == "fail"
                                        or getattr(n.func, "id", None) == "fail"):
            return True
    return False


def _walk_scope(node):
    """The nodes of ``node``'s own scope: nested functions and classes are not entered."""
    todo = list(ast.iter_child_nodes(node))
    while todo:
        n = todo.pop()
        yield n
        if not isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef,
                              ast.Lambda)):
            todo.extend(ast.iter_child_nodes(n))


def _mutated(node):
    """``[(container, value)]`` of a statement that puts a value into a container:
    ``x.append(v)`` (any method call on a name or attribute with arguments) and
    ``x[k] = v``."""
    if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and \
            _key(node.func.value) is not None:
        return [(node.func.value, a) for a in [*node.args,
                                               *(k.value for k in node.keywords)]]
    if isinstance(node, (ast.Assign, ast.AugAssign)):
        targets = node.targets if isinstance(node, ast.Assign) else [node.target]
        return [(t.value, node.value) for t in targets if isinstance(t, ast.Subscript)]
    return []


def _taint(nodes, clocks, names, funcs):
    """A copy of ``names`` grown, to a fixed point, by the targets assigned a tainted
    value and the containers a tainted value is put into."""
    names = dict(names)
    changed = True
    while changed:
        changed = False
        for node in nodes:
            for target, value in _assigned(node):
                taint = _value_taint(value, clocks, names, funcs)
                if taint is not None:
                    changed |= _bind(target, taint, names)
            for container, value in _mutated(node):
                if _tainted(value, clocks, names, funcs):
                    changed |= _bind(container, WHOLE, names)
    return names


def wall_clock_asserts(source, filename="<test>"):
    """``[(line, text)]`` of the asserts of ``source`` that involve a clock reading (a
    source that imports neither ``time`` nor ``datetime`` has none: it is not parsed)."""
    if not re.search(r"^\s*(?:import|from)\s+(?:time|datetime)\b|import.*\b(?:time|datetime)\b",
                     source, re.M):
        return []
    tree = ast.parse(source, filename)
    clocks = _Clocks(tree)
    if not (clocks.time_mods or clocks.dt_mods or clocks.dt_classes or clocks.funcs):
        return []
    defs = [n for n in ast.walk(tree) if isinstance(n, (ast.FunctionDef,
                                                        ast.AsyncFunctionDef))]
    scopes = {d: list(_walk_scope(d)) for d in defs}
    top = list(_walk_scope(tree))
    funcs, module = {}, {}

    def names_of(d):
        """The tainted names of function ``d``: the module's, its parameters named after
        a function returning a clock value (a pytest fixture), its own assignments."""
        args = d.args.posonlyargs + d.args.args + d.args.kwonlyargs
        given = {a.arg: funcs[a.arg] for a in args if a.arg in funcs}
        return _taint(scopes[d], clocks, {**module, **given}, funcs)

    changed = True
    while changed:  # module names and functions returning clock values, to a fixed point
        changed = False
        module = _taint(top, clocks, module, funcs)
        for d, nodes in scopes.items():
            names = names_of(d)
            for n in nodes:
                if isinstance(n, (ast.Return, ast.Yield)) and n.value is not None:
                    taint = _value_taint(n.value, clocks, names, funcs)
                    if taint is not None and funcs.get(d.name) != WHOLE and \
                            funcs.get(d.name) != taint:
                        funcs[d.name] = WHOLE if d.name in funcs else taint
                        changed = True
    out = []
    for nodes, names in [(top, module)] + [(scopes[d], names_of(d)) for d in defs]:
        loops = [n for n in nodes if isinstance(n, (ast.While, ast.For, ast.AsyncFor))]
        in_loop = {id(m) for lp in loops for m in ast.walk(lp)}
        for node in nodes:
            if isinstance(node, ast.If) and id(node) not in in_loop and \
                    _tainted(node.test, clocks, names, funcs) and _fails(node.body):
                out.append((node.lineno, ast.get_source_segment(source, node) or ""))
            hit = (isinstance(node, ast.Assert)
                   and _tainted(node.test, clocks, names, funcs)) or (
                isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute)
                and node.func.attr.startswith("assert")
                and any(_tainted(a, clocks, names, funcs) for a in node.args))
            if hit:
                out.append((node.lineno, ast.get_source_segment(source, node) or ""))
    return sorted(set(out))


#: one test per form of a wall-clock assert; each marks its assert's line with "# <-"
EVASIONS = """
import time
import time as t
import datetime as dt
from time import perf_counter, monotonic as m
from datetime import datetime as D
T0 = time.time()
def test_difference():
    t0 = time.monotonic()
    assert time.monotonic() - t0 < 10  # <-
def test_name():
    start = time.perf_counter()
    elapsed = time.perf_counter() - start
    assert status == 0 and elapsed < 5  # <-
def test_deadline():
    deadline = time.time() + 5
    assert time.time() < deadline  # <-
def test_from_import():
    s = perf_counter()
    assert perf_counter() - s < 1  # <-
def test_datetime_module():
    assert (dt.datetime.now() - x).seconds < 3  # <-
def test_float():
    elapsed = time.monotonic() - T0
    assert float(elapsed) < 5  # <-
def test_round():
    t0 = time.monotonic()
    assert round(time.monotonic() - t0) < 5  # <-
def test_min():
    elapsed = time.monotonic() - T0
    assert min(elapsed, 99) < 5  # <-
def test_module_alias():
    s = t.monotonic()
    assert t.monotonic() - s < 5  # <-
def test_function_alias():
    s = m()
    assert m() - s < 5  # <-
def test_datetime_class_alias():
    assert D.now() > limit  # <-
def test_clock_reference():
    clock = time.monotonic
    assert clock() - T0 < 5  # <-
def test_module_level_name():
    assert time.time() - T0 < 5  # <-
def took():
    return time.perf_counter() - T0
def test_helper():
    assert took() < 5  # <-
def test_list():
    times = []
    times.append(time.perf_counter())
    assert max(times) - T0 < 5  # <-
def test_attribute(self):
    self.t0 = time.time()
    self.assertLess(time.time() - self.t0, 5)  # <-
def test_walrus():
    assert (e := time.monotonic() - T0) < 5  # <-
def test_bare_truth():
    ok = time.monotonic() - T0 < 5
    assert ok  # <-
def timed():
    s = time.monotonic()
    return 1, time.monotonic() - s
def test_fixture(timed):
    value, secs = timed
    assert value == 1
    assert secs < 5  # <-
def test_fixture_index(timed):
    assert timed[1] < 5  # <-
def test_fail_after_the_work():
    t0 = time.monotonic()
    work()
    if time.monotonic() - t0 > 5:  # <-
        pytest.fail("too slow")
def test_raise_after_the_work():
    elapsed = time.monotonic() - T0
    if elapsed > 5:  # <-
        raise AssertionError(elapsed)
"""

#: tests without one: a subprocess timeout, a sleep, a hang guard that fails the test
#: with pytest.fail past a deadline, a time stamp from the file system, and the
#: untainted part of a fixture that also returns a duration
CLEAN = """
import datetime, subprocess, time, pytest
def test_ok():
    r = subprocess.run(["x"], timeout=60)
    time.sleep(0.1)
    assert r.returncode == 0
def test_guard():
    victim, deadline = None, time.monotonic() + 60
    while victim is None:
        if time.monotonic() > deadline:
            pytest.fail("no victim")
        victim = find()
    assert victim is not None
def test_stamp(tmp_path):
    start = datetime.datetime.fromtimestamp(tmp_path.stat().st_mtime)
    assert problems(path, since=start) == []
def timed():
    s = time.monotonic()
    return 1, time.monotonic() - s
def test_value(timed):
    value, _ = timed
    assert value == 1 and timed[0] == 1
"""


def test_the_scan_finds_each_form_of_a_wall_clock_assert():
    """Hypothesis: the taint analysis reports an assert on a clock value in each form a
    test can write it (a difference of readings, an assigned name, a deadline, a
    from-import, datetime.now through the module, a value wrapped in float, round or min,
    ``import time as t``, ``from time import monotonic as m``, ``from datetime import
    datetime as D``, a clock held in a name, a module-level reading, a helper returning a
    duration, a list appended to, an attribute with ``self.assertLess``, a walrus, a
    boolean computed first, a fixture's tuple unpacked and indexed, an ``if`` after the
    work that calls pytest.fail or raises): exactly the lines marked."""
    marked = [i for i, line in enumerate(EVASIONS.splitlines(), 1) if "# <-" in line]
    assert len(marked) == 22
    assert [line for line, _ in wall_clock_asserts(EVASIONS)] == marked


def test_the_scan_passes_guards_stamps_and_untainted_values():
    """Hypothesis: the scan reports nothing in tests whose clock readings only bound a
    wait (a subprocess timeout, a loop that calls pytest.fail past a deadline), whose
    time stamp comes from the file system, or that assert on the untainted part of a
    fixture that also returns a duration (so its silence on tests/ means something)."""
    assert wall_clock_asserts(CLEAN) == []


def test_no_test_asserts_on_a_wall_clock():
    """Hypothesis: no test in tests/ asserts on a wall-clock reading; each claim of
    speed or of 'before any work' is proved by what was done."""
    found = []
    for path in sorted(TESTS.rglob("*.py")):
        source = path.read_text(encoding="utf-8")
        found += [f"{path.relative_to(TESTS)}:{line}: {text.splitlines()[0]}"
                  for line, text in wall_clock_asserts(source, str(path))]
    assert not found, "\n".join(found)
