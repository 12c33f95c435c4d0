"""No test asserts on a wall clock (issue 32, part 2).

A test that says "refused before any work" or "ends without a hang" with ``assert
elapsed < 20`` passes on a fast machine and fails on a loaded one, and proves nothing
about the work: it is proved by what was computed or written (counters, files, progress
lines).  A hang is guarded by a bounded wait that fails the test (``timeout=`` of a
subprocess, ``pytest.fail`` past a deadline), which is a guard, not a claim.

The scan: every ``assert`` in a test function of ``tests/`` that compares a clock
reading (``time.time``, ``time.perf_counter``, ``time.monotonic``, their ``_ns`` forms,
``datetime.now``), either directly or through a name assigned from one (``elapsed =
time.monotonic() - t0``, ``t0 = time.perf_counter()``), is reported.  A time stamp
passed to a checker (``problems(path, since=start)``) is data, not a duration, and is
not.
"""
import ast
from pathlib import Path

TESTS = Path(__file__).resolve().parent

#: the clock readings a test must not assert on
CLOCKS = {"time", "perf_counter", "monotonic", "time_ns", "perf_counter_ns",
          "monotonic_ns", "now", "utcnow"}


def _is_clock(call):
    """Whether ``call`` (an ast.Call) reads a clock."""
    func = call.func
    if isinstance(func, ast.Attribute):
        base = func.value
        base_name = getattr(base, "id", getattr(base, "attr", ""))
        return func.attr in CLOCKS and base_name in ("time", "datetime", "dt")
    return getattr(func, "id", "") in ("perf_counter", "monotonic", "perf_counter_ns",
                                       "monotonic_ns")  # from time import perf_counter


def _reads_clock(node, tainted):
    """Whether the value of expression ``node`` is (or is computed from) a clock reading
    or a name assigned from one; the arguments of other calls do not count (a time
    stamp passed to a checker is data, not a duration asserted on)."""
    if isinstance(node, ast.Call):
        return _is_clock(node) or (isinstance(node.func, ast.Attribute) and
                                   _reads_clock(node.func.value, tainted))
    if isinstance(node, ast.Name):
        return node.id in tainted
    return any(_reads_clock(child, tainted) for child in ast.iter_child_nodes(node))


def _assigned(node):
    """``[(target, value)]`` of an assignment, a tuple assigned from a tuple paired."""
    targets = node.targets if isinstance(node, ast.Assign) else [node.target]
    out = []
    for t in targets:
        if isinstance(t, ast.Tuple) and isinstance(node.value, ast.Tuple) and \
                len(t.elts) == len(node.value.elts):
            out += list(zip(t.elts, node.value.elts))
        else:
            out.append((t, node.value))
    return out


def _compares_clock(test, tainted):
    """Whether an assert's test compares a clock reading (a Compare with one)."""
    return any(isinstance(n, ast.Compare) and
               any(_reads_clock(op, tainted) for op in [n.left, *n.comparators])
               for n in ast.walk(test))


def wall_clock_asserts(source, filename="<test>"):
    """``[(line, text)]`` of the asserts of ``source`` that compare a clock reading."""
    tree = ast.parse(source, filename)
    out = []
    for scope in ast.walk(tree):
        if not isinstance(scope, (ast.FunctionDef, ast.AsyncFunctionDef)):
            continue
        tainted = set()
        changed = True
        while changed:  # names assigned from clock readings, transitively
            changed = False
            for node in ast.walk(scope):
                if not isinstance(node, (ast.Assign, ast.AugAssign, ast.AnnAssign)) or \
                        node.value is None:
                    continue
                for target, value in _assigned(node):
                    if not _reads_clock(value, tainted):
                        continue
                    for n in ast.walk(target):
                        if isinstance(n, ast.Name) and n.id not in tainted:
                            tainted.add(n.id)
                            changed = True
        for node in ast.walk(scope):
            if isinstance(node, ast.Assert) and _compares_clock(node.test, tainted):
                out.append((node.lineno, ast.get_source_segment(source, node) or ""))
    return sorted(set(out))


def test_the_scan_finds_each_form_of_a_wall_clock_assert():
    """Hypothesis: the scan reports an assert on a clock reading in each form a test
    writes it (a difference of readings, a name assigned from one, a deadline, a bare
    import, datetime.now) and nothing in a test without one (so its silence on tests/
    means something)."""
    bad = '''
import time
from time import perf_counter
def test_a():
    t0 = time.monotonic()
    work()
    assert time.monotonic() - t0 < 10
def test_b():
    start = time.perf_counter()
    elapsed = time.perf_counter() - start
    assert status == 0 and elapsed < 5
def test_c():
    deadline = time.time() + 5
    assert time.time() < deadline
def test_d():
    s = perf_counter()
    assert perf_counter() - s < 1
def test_e():
    import datetime
    assert (datetime.datetime.now() - t).seconds < 3
'''
    assert [line for line, _ in wall_clock_asserts(bad)] == [7, 11, 14, 17, 20]
    good = '''
import datetime, subprocess, time
def test_ok():
    r = subprocess.run(["x"], timeout=60)
    time.sleep(0.1)
    assert r.returncode == 0
    assert not started and listing == before
def test_stamp():
    start = datetime.datetime.now()
    victim, deadline = None, time.monotonic() + 60
    while victim is None and time.monotonic() < deadline:
        victim = find()
    assert victim is not None
    assert problems(path, since=start) == []
'''
    assert wall_clock_asserts(good) == []


def test_no_test_asserts_on_a_wall_clock():
    """Hypothesis: no test in tests/ asserts on a wall-clock reading; each claim of
    speed or of 'before any work' is proved by what was done."""
    found = []
    for path in sorted(TESTS.rglob("*.py")):
        source = path.read_text(encoding="utf-8")
        found += [f"{path.relative_to(TESTS)}:{line}: {text.splitlines()[0]}"
                  for line, text in wall_clock_asserts(source, str(path))]
    assert not found, "\n".join(found)
