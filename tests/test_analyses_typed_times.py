"""No run time or compile time is typed by hand into the analyses scripts' text.

A time that a script's docstring or comment states ("about 5 minutes on 2 cores", "the
JIT compiles for 10-15 s") is a measurement retyped from some run: it drifts from what the
scripts measure now (issue 32: 10 against 5 minutes, 10-15 against 10-20 s while 17-19 s
were measured).  Measured times belong in the reports and sections the scripts write; the
scripts' text may state a *target* (a requirement, not a measurement) and a zero.
"""
import ast
import io
import re
import tokenize
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: a time with its unit (a range "10-15 s" counts once)
TIME = re.compile(r"(?<![\w.-])(\d+(?:[.,]\d+)*)\s*(?:(?:-|–|to)\s*\d+(?:\.\d+)?\s*)?"
                  r"(?:ns|µs|us|ms|s|sec|seconds?|min|minutes?|h|hours?)\b(?![-/])")


def _texts(src):
    """``(line, text)`` of every docstring and comment of the Python source ``src``."""
    for node in ast.walk(ast.parse(src)):
        if isinstance(node, (ast.Module, ast.FunctionDef, ast.AsyncFunctionDef,
                             ast.ClassDef)):
            doc = ast.get_docstring(node, clean=False)
            if doc:
                yield getattr(node, "lineno", 1), doc
    for tok in tokenize.generate_tokens(io.StringIO(src).readline):
        if tok.type == tokenize.COMMENT:
            yield tok.start[0], tok.string


def typed_times(src):
    """The hand-typed times of ``src``: nonzero times in a sentence that states no
    target."""
    out = []
    for line, text in _texts(src):
        for sentence in re.split(r"(?<=[.;])\s+", text):
            if "target" in sentence.lower():
                continue
            for m in TIME.finditer(sentence):
                if float(m.group(1).replace(",", "")) > 0:
                    out.append((line, m.group(0)))
    return out


def test_no_analyses_script_types_a_run_time():
    """Hypothesis: no docstring or comment of a script under analyses/ states a nonzero
    run or compile time other than a target."""
    bad = [(str(p.relative_to(ROOT)), line, t)
           for p in sorted((ROOT / "analyses").rglob("*.py"))
           for line, t in typed_times(p.read_text())]
    assert bad == []


def test_the_check_catches_retyped_times_and_lets_targets_and_zeros_pass():
    """Hypothesis: the check flags a script run time and a compile-time range typed in a
    docstring or a comment, and passes a target and a zero."""
    src = ('"""Run as x.py (about 5 minutes on 2 cores).  The JIT compiles for 10–15 s.\n\n'
           'Target: at most 5 s on 2 cores.  Read from the cache: 0 s.\n"""\n'
           "x = 1  # takes ~10-20 s\n")
    assert [t for _, t in typed_times(src)] == ["5 minutes", "10–15 s", "10-20 s"]
