"""Every command and code block of README.md and of the documentation runs as pasted.

The slow test (:func:`test_a_page_runs_as_pasted`) runs each page's shell and Python
blocks in order in a fresh empty folder, every shell line on its own, and checks each
line's exit status: 0, or ``N`` where the page marks the line ``# exits N``.  The fast
tests check what can be checked without running anything: every command and option
exists, no page writes a file twice or resumes a finished one, Python blocks parse and
name what exists, grids come from ``vi.grid``, set-up lines are the ones CI runs, and
the prose neither retypes measured numbers nor restates the reproducibility promise
away from its one page.  How blocks are read: ``tests/doc_blocks.py``.
"""
import argparse
import ast
import importlib
import os
import re
import shutil
import subprocess
import sys

import pytest

import doc_blocks as db

ROOT = db.ROOT
PAGES = db.pages()
SHELL_BUILTINS = {"export", "cd", "kill", "wait", "sleep", "true", "test", "echo", "unset",
                  "set", "ls", "cat", "rm", "mkdir"}


def _subparsers():
    from vibimpact.cli import build_parser

    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    top = {o for a in parser._actions for o in a.option_strings}
    return top, {name: {o for a in p._actions for o in a.option_strings}
                 for name, p in sub.choices.items()}


def _lines(page):
    return [ln for b in db.runnable(page) if b.language in db.SHELL
            for ln in db.shell_lines(b)]


def _rel(page):
    return str(page.relative_to(ROOT))


def test_pages_are_found_and_readme_blocks_are_read():
    """Hypothesis: the block reader finds README.md and the user guide's pages, and reads
    shell and Python blocks from both kinds of page (a reader that finds nothing would
    let every other test here pass)."""
    names = {_rel(p) for p in PAGES}
    assert {"README.md", "docs/user_guide/sweeps.rst", "docs/index.rst"} <= names
    readme = db.runnable(ROOT / "README.md")
    assert {b.language for b in readme} >= {"bash", "python"}
    assert any(b.language == "bash" for b in db.runnable(ROOT / "docs/user_guide/ring.rst"))
    assert db.shell_lines(db.Block(ROOT, "bash", 1, "a \\\n  b  # exits 2\n# c\n"))[0] \
        == db.Line("a b  # exits 2", 2, db.Block(ROOT, "bash", 1, "a \\\n  b  # exits 2\n# c\n"))


def test_every_shell_command_and_option_of_the_docs_exists():
    """Hypothesis: every command a page's shell blocks run is a ``vibimpact`` command
    with options its ``--help`` lists, a set-up line CI runs, or a program on PATH (a
    renamed option or command fails here, before the slow run)."""
    top, subs = _subparsers()
    ci = db.ci_commands()
    bad = []
    for page in PAGES:
        for line in _lines(page):
            words = db.command(line)
            if words is None:
                bad.append((line.block.where, line.text, "unparsable"))
                continue
            for seg in db.segments(words):
                seg = [w for w in seg if not re.match(r"^\w+=", w)] or seg  # VAR=x cmd
                if db.is_setup(seg):
                    if db.normal(seg) not in ci:
                        bad.append((line.block.where, " ".join(seg), "set-up CI does not run"))
                    continue
                if seg[0] == "vibimpact":
                    name = next((w for w in seg[1:] if not w.startswith("-")), None)
                    if name is None:
                        known = top
                    elif name not in subs:
                        bad.append((line.block.where, line.text, f"no command {name}"))
                        continue
                    else:
                        known = subs[name] | {"-v", "--verbose"}
                    for w in seg[1:]:
                        opt = w.split("=", 1)[0]
                        if opt.startswith("-") and not re.match(r"^-\d", opt) \
                                and opt not in known:
                            bad.append((line.block.where, line.text, f"no option {opt}"))
                elif seg[0] not in SHELL_BUILTINS and shutil.which(seg[0]) is None:
                    bad.append((line.block.where, line.text, f"no program {seg[0]}"))
    assert bad == []


def _rewrites(lines):
    """``[(where, line, why), ...]``: the lines of one page (in order) that write a file
    an earlier line wrote without ``--overwrite``, or ``--resume`` a run an earlier line
    finished without ``--keep-checkpoint``; lines marked ``# exits N`` are left alone."""
    bad, written, kept = [], set(), set()
    for line in lines:
        for seg in db.segments(db.command(line) or []):
            if seg[:1] != ["vibimpact"] or line.expect != 0:
                continue
            outs = db.outputs(seg)
            if "--resume" in seg and any(o in written - kept for o in outs):
                bad.append((line.block.where, line.text, "resumes a finished run"))
            elif "--overwrite" not in seg and "--resume" not in seg:
                again = [o for o in outs if o in written]
                if again:
                    bad.append((line.block.where, line.text, f"writes {again} again"))
            written.update(outs)
            if "--keep-checkpoint" in seg:
                kept.update(outs)
    return bad


def test_no_page_writes_a_file_twice_or_resumes_a_finished_run():
    """Hypothesis: pasted in order, no shell line of a page writes a file an earlier line
    of the page wrote (it would stop at 'exists') unless it says ``--overwrite``, and no
    ``--resume`` line names an output an earlier line finished without
    ``--keep-checkpoint`` (there is no checkpoint left to resume), unless the page marks
    the line ``# exits N``."""
    assert [bad for page in PAGES for bad in _rewrites(_lines(page))] == []


def test_rewrite_check_flags_the_old_usage_block():
    """Hypothesis: the check above flags both faults of the README Usage block of issue
    32 (a ``--resume`` of a finished file, ``run.nc`` written twice), and passes the same
    lines once the first run keeps its checkpoint and the second run names another file
    -- it is neither vacuous nor blind to the fix."""
    def lines(text):
        return db.shell_lines(db.Block(ROOT, "bash", 1, text))

    old = ("vibimpact classify --eta 1.1:1.3:0.002 -o fig10.nc\n"
           "vibimpact classify --eta 1.1:1.3:0.002 -o fig10.nc --resume\n"
           "vibimpact simulate --eta 1.0 -o run.nc --plot xy.png\n"
           "vibimpact simulate --eta 1.06 -o run.nc\n")
    assert [why for *_, why in _rewrites(lines(old))] == ["resumes a finished run",
                                                          "writes ['run.nc'] again"]
    fixed = old.replace("fig10.nc\n", "fig10.nc --keep-checkpoint\n", 1).replace(
        "-o run.nc\n", "-o run2.nc\n")
    assert _rewrites(lines(fixed)) == []


def _dotted(node):
    parts = []
    while isinstance(node, ast.Attribute):
        parts.append(node.attr)
        node = node.value
    if isinstance(node, ast.Name):
        return [node.id, *reversed(parts)]
    return None


def _resolve(name):
    parts = name.split(".")
    for i in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:i]))
        except ImportError:
            continue
        for attr in parts[i:]:
            if not hasattr(obj, attr):
                return False
            obj = getattr(obj, attr)
        return True
    return False


def test_python_blocks_parse_and_every_vibimpact_name_exists():
    """Hypothesis: every Python block of every page is valid Python, its imports from
    vibimpact resolve, and every ``vi.a.b`` chain it uses names something that exists."""
    bad = []
    for page in PAGES:
        for b in db.runnable(page):
            if b.language != "python":
                continue
            try:
                tree = ast.parse(b.text)
            except SyntaxError as exc:
                bad.append((b.where, f"syntax: {exc}"))
                continue
            for node in ast.walk(tree):
                if isinstance(node, ast.ImportFrom) and (node.module or "").startswith(
                        "vibimpact"):
                    for a in node.names:
                        if not _resolve(f"{node.module}.{a.name}"):
                            bad.append((b.where, f"{node.module}.{a.name}"))
                elif isinstance(node, ast.Attribute):
                    chain = _dotted(node)
                    if chain and chain[0] in ("vi", "vibimpact") and len(chain) > 1:
                        name = "vibimpact." + ".".join(chain[1:])
                        if not _resolve(name):
                            bad.append((b.where, name))
    assert bad == []


def test_every_vibimpact_name_the_pages_cite_exists():
    """Hypothesis: each dotted name ``vibimpact.x.y`` that a page's prose cites (as code,
    or in a Sphinx role) resolves to a module or an attribute of one, so that a name moved
    by a refactoring cannot linger in the docs."""
    bad = sorted({(_rel(p), n) for p in PAGES for para in _prose(p)
                  for n in re.findall(r"[`~](vibimpact(?:\.[A-Za-z_]\w*)+)", para)
                  if not _resolve(n)})
    assert bad == []


def test_grids_in_the_docs_come_from_vi_grid():
    """Hypothesis: no Python block of a page and no gallery script builds a grid with
    ``np.arange`` or ``np.linspace`` (their last bits differ from the command line's
    grid, and a continuation can land elsewhere); ``vi.grid`` is the one helper."""
    sources = [(b.where, b.text) for p in PAGES for b in db.runnable(p)
               if b.language == "python"]
    sources += [(str(p.relative_to(ROOT)), p.read_text())
                for p in sorted((ROOT / "docs" / "examples").glob("*.py"))]
    bad = [(w, m.group(0)) for w, t in sources
           for m in re.finditer(r"np\.(arange|linspace)\(", t)]
    assert bad == []


def test_no_command_hides_in_a_block_that_is_not_run():
    """Hypothesis: every block whose lines are ``vibimpact`` commands, installs or
    Python statements is a bash, console or python block, so that the slow test runs it
    (a command shown as plain text would escape it)."""
    _, subs = _subparsers()
    looks = re.compile(r"^(\$ )?(vibimpact (%s)\b|pip install|python -m|import vibimpact"
                       r"|>>> )" % "|".join(map(re.escape, subs)))
    bad = [(b.where, b.language) for p in PAGES for b in db.blocks(p)
           if b.language not in db.LANGUAGES
           and any(looks.match(s.strip()) for s in b.text.splitlines())]
    assert bad == []


def test_readme_has_two_setup_commands_and_ci_runs_both():
    """Hypothesis: the README's first two shell lines are the set-up a newcomer copies:
    install and run the main job (``vibimpact classify``), install the test extra and
    run ``python -m pytest -q -n 2``; ``.ci/run`` runs both installs and that test command,
    and no other README line installs anything but the documentation's extra."""
    lines = _lines(ROOT / "README.md")
    first, second = (db.segments(db.command(ln)) for ln in lines[:2])
    ci = db.ci_commands()
    assert db.normal(first[0]) == "pip install -e ." and first[1][:2] == ["vibimpact",
                                                                         "classify"]
    assert [db.normal(s) for s in second] == ['pip install -e .[test]',
                                              "python -m pytest -q -n 2"]
    assert {db.normal(first[0]), *map(db.normal, second)} <= ci
    later = [db.normal(s) for ln in lines[2:] for s in db.segments(db.command(ln))
             if db.is_setup(s) and db.normal(s).startswith("pip")]
    assert later == ["pip install -e .[docs]"]


def _prose(page, literals=True):
    """The page's text without code blocks and without script-written sections, as
    paragraphs; without inline code too where ``literals`` is false."""
    text = page.read_text()
    text = re.sub(r"<!-- section:(\S+) -->.*?<!-- /section:\1 -->", "", text, flags=re.S)
    for b in db.blocks(page):
        text = text.replace(b.text, "")
    if page.suffix == ".rst":
        text = "\n".join(ln for ln in text.splitlines() if not ln.startswith("   "))
    if not literals:  # inline code: formulas, names
        text = re.sub(r"``.*?``|(?<!:)`[^`]*`", "", text, flags=re.S)
    return [p for p in re.split(r"\n\s*\n", text) if p.strip()]


MEASURED = re.compile(
    r"(?<![\w.-])\d+(?:[.,]\d+)*\s*(?:(?:-|–|to)\s*\d+(?:\.\d+)?\s*)?"
    r"(?:ns|µs|us|ms|s|sec|seconds?|min|minutes?|h|hours?)\b(?![-/])"
    r"|(?<![\w.])\d+(?:\.\d+)?\s*(?:×|x)(?=[\s,.;)])"
    r"|(?<![\w.])\d+(?:\.\d+)?\s*%")


def test_no_measured_number_is_typed_in_the_prose():
    """Hypothesis: no page's prose types a run time, a speed-up or a percentage by hand
    (they drift from what the scripts measure); such numbers live in the reports and in
    the sections the scripts write, and the prose refers to them."""
    bad = [(_rel(p), m.group(0).strip()) for p in PAGES for para in _prose(p, False)
           for m in MEASURED.finditer(para)]
    assert bad == []


def test_measured_number_check_catches_retyped_figures():
    """Hypothesis: the check above flags the retyped figures of issue 32 (a compile-time
    range, a script's run time in minutes, a ratio, a percentage)."""
    text = ("it compiles for 10–15 s; the script runs about 10 minutes; 1.05x eq. (5)'s; "
            "33 % of labels; 118 ns with them")
    assert len(MEASURED.findall(text)) == 5


SAMENESS = re.compile(r"bit-identical|same numbers|same result|every machine|any machine|"
                      r"all machines|identical to (?:a|an|the) (?:serial|uninterrupted)",
                      re.I)


def test_python_outputs_are_the_file_names_a_block_passes_to_calls():
    """Hypothesis: the files the slow run checks after a Python block are the relative
    paths with a data or image extension passed to a call, positionally or by keyword
    (a figure's savefig, a plot's path=, write_netcdf, a read), and no other string."""
    text = ('fig.savefig("a/b.png", dpi=80)\nplot_bifurcation(ds, states="Vr", '
            'path="ring_vr_api.png")\nvi.io.write_netcdf(ds, "c.nc")\n'
            'print("done.png is a word here")\nx = "d.nc"\nf(label="P1")\n')
    assert db.python_outputs(text) == ["a/b.png", "ring_vr_api.png", "c.nc"]


def test_the_ring_page_names_the_figure_its_python_block_writes():
    """Hypothesis: the pages' Python blocks name the files they write in a form the slow
    run checks: the ring guide's plot_bifurcation(..., path="ring_vr_api.png") is found
    (the check the deleted ring-guide test made)."""
    found = {o for page in db.pages() for b in db.runnable(page)
             if b.language == "python" for o in db.python_outputs(b.text)}
    assert "ring_vr_api.png" in found


def test_the_reproducibility_promise_is_stated_on_one_page():
    """Hypothesis: a paragraph that promises the same numbers (serial or parallel,
    resumed, another machine) outside the reproducibility page refers to that page,
    where the conditions (one CPU type, the same versions) are stated once; nowhere does
    a page promise the same numbers on every machine."""
    home = ROOT / "docs" / "user_guide" / "reproducibility.rst"
    assert home.exists()
    bad = []
    for page in PAGES:
        if page == home:
            continue
        for para in _prose(page):
            if re.search(r"every machine|any machine|all machines", para, re.I):
                bad.append((_rel(page), para[:80]))
            elif SAMENESS.search(para) and "reproducibility" not in para.lower():
                bad.append((_rel(page), para[:80]))
    assert bad == []
    text = home.read_text()
    assert "CPU" in text and "version" in text


def test_continuation_is_described_with_its_blocks():
    """Hypothesis: every paragraph of a page or a gallery script that says a sweep's
    point starts from the previous point's final state also says that the grid is cut into blocks (the default 16
    blocks are seeded, so 'each eta starts from the previous one' alone is untrue)."""
    claim = re.compile(r"previous (?:point|η|eta)(?:'s)?\W+(?:\w+\W+)?final state", re.I)
    paras = [(_rel(p), para) for p in PAGES for para in _prose(p)]
    paras += [(str(p.relative_to(ROOT)), para)
              for p in sorted((ROOT / "docs" / "examples").glob("*.py"))
              for para in re.split(r"\n\s*\n", p.read_text())]
    bad = [(where, para[:80]) for where, para in paras
           if claim.search(para) and "block" not in para.lower()]
    assert bad == []


# ---------------------------------------------------------------- the slow run

DRIVER = r'''
import os, sys, traceback
proto = os.fdopen(os.dup(1), "w", buffering=1)
os.dup2(2, 1)
sys.stdout = sys.stderr
ns = {"__name__": "__main__"}
if __name__ == "__main__":
    for path in sys.stdin:
        path = path.strip()
        try:
            exec(compile(open(path).read(), path, "exec"), ns)
            proto.write("@@ok\n")
        except BaseException:
            traceback.print_exc()
            sys.stderr.flush()
            proto.write("@@fail\n")
'''


def _environment(tmp):
    """PATH with ``vibimpact`` and ``python`` of this interpreter first, the repository
    on PYTHONPATH, a non-interactive matplotlib."""
    bindir = tmp / ".bin"
    bindir.mkdir()
    (bindir / "vibimpact").write_text(f'#!/bin/sh\nexec "{sys.executable}" -m vibimpact "$@"\n')
    (bindir / "vibimpact").chmod(0o755)
    (bindir / "python").symlink_to(sys.executable)
    return dict(os.environ, MPLBACKEND="Agg",
                PATH=os.pathsep.join([str(bindir), os.environ.get("PATH", "")]),
                PYTHONPATH=os.pathsep.join([str(ROOT), *filter(
                    None, [os.environ.get("PYTHONPATH")])]))


def _shell_script(lines, ci, status):
    """One bash script running ``lines`` in order, printing each one's exit status; a
    line with a set-up command CI runs (an install, the test command, the documentation
    build) runs its other commands only, joined by ``&&``."""
    import shlex

    out = ["set +e"]
    for i, line in enumerate(lines):
        text = line.text
        segs = db.segments(db.command(line) or [])
        if any(db.is_setup(s) and db.normal(s) in ci for s in segs):
            text = " && ".join(["true"] + [shlex.join(s) for s in segs
                                           if not (db.is_setup(s) and db.normal(s) in ci)])
        out += [text, f'echo "@@rc {i} $?" >> "{status}"']
    return "\n".join(out) + "\n"


RUN_PAGES = [p for p in PAGES if db.runnable(p)]


@pytest.mark.slow
@pytest.mark.parametrize("page", RUN_PAGES, ids=_rel)
def test_a_page_runs_as_pasted(page, tmp_path):
    """Hypothesis: pasted in order into a shell and one Python interpreter in an empty
    folder, every shell line of the page ends with status 0 (or the N of its
    ``# exits N``), every Python block runs without an exception, and every file a
    command names as its output, and every file a Python block names in a call
    (``savefig``, a plot's ``path=``, ``write_netcdf``), is there afterwards."""
    env = _environment(tmp_path)
    ci = db.ci_commands()
    driver = tmp_path / ".driver.py"
    driver.write_text(DRIVER)
    log = open(tmp_path / ".python.log", "w")
    py = subprocess.Popen([sys.executable, str(driver)], cwd=tmp_path, env=env,
                          stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=log,
                          text=True)
    failures, outputs = [], []
    try:
        for k, b in enumerate(db.runnable(page)):
            if b.language == "python":
                src = tmp_path / f".block{k}.py"
                src.write_text(b.text + "\n")
                py.stdin.write(f"{src}\n")
                py.stdin.flush()
                answer = py.stdout.readline().strip()
                if answer != "@@ok":
                    log.flush()
                    failures.append((b.where, b.text[:200],
                                     (tmp_path / ".python.log").read_text()[-2000:]))
                    break
                outputs += db.python_outputs(b.text)
                continue
            lines = db.shell_lines(b)
            script = tmp_path / f".block{k}.sh"
            status = tmp_path / f".block{k}.status"
            script.write_text(_shell_script(lines, ci, status))
            proc = subprocess.run(["bash", str(script)], cwd=tmp_path, env=env,
                                  stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                  text=True, timeout=1800)
            out = proc.stdout
            codes = dict(map(int, m.groups()) for m in re.finditer(
                r"@@rc (\d+) (\d+)", status.read_text() if status.exists() else ""))
            for i, line in enumerate(lines):
                if codes.get(i) != line.expect:
                    failures.append((b.where, line.text, codes.get(i), out[-2000:]))
                elif line.expect == 0:
                    for seg in db.segments(db.command(line) or []):
                        if seg[:1] == ["vibimpact"]:
                            outputs += db.outputs(seg)
            if failures:
                break
    finally:
        py.stdin.close()
        py.wait(timeout=600)
        log.close()
    assert failures == []
    missing = [o for o in outputs if not (tmp_path / o).exists()]
    assert missing == []
