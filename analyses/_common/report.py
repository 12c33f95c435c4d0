"""Helpers of the analyses scripts: timing, and one marked section of a Markdown report."""
import os
import re
import time

START = "<!-- section:{name} -->"
END = "<!-- /section:{name} -->"


def write_section(path, name, text):
    """Replace (or append) the section ``name`` of ``path`` atomically."""
    start, end = START.format(name=name), END.format(name=name)
    block = f"{start}\n{text.rstrip()}\n{end}\n"
    old = path.read_text() if path.exists() else ""
    pat = re.compile(re.escape(start) + r".*?" + re.escape(end) + r"\n?", re.S)
    new = pat.sub(lambda m: block, old) if pat.search(old) else (
        old + ("\n" if old and not old.endswith("\n") else "") + block)
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text(new)
    os.replace(tmp, path)


def best_time(fn, repeats=3):
    """Best wall time of ``repeats`` calls (after the caller's warm-up) and the last result."""
    best, out = float("inf"), None
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out
