"""The command and code blocks of README.md and of the documentation's pages, as a reader
pastes them (used by ``tests/test_doc_blocks.py``).

A *page* is ``README.md`` or a ``docs/**/*.rst`` page.  Its blocks, in order, are the
fenced Markdown blocks (```` ```bash ````, ```` ```console ````, ```` ```python ````) and the
reStructuredText ``.. code-block:: bash|console|python`` directives.  A shell block is a
list of *lines*: a command with its ``\\`` continuations joined, comments and blank lines
left out.  A line that ends in the comment ``# exits N`` (``N`` an exit status) is meant
to end with that status; every other line must end with 0.

Some lines are the set-up a reader runs once from the checkout (``pip install ...``, the
test command, the documentation build): CI runs exactly those lines (``.ci/run``), so
they are matched against it instead of being run again inside a test
(:func:`ci_commands`).
"""
from __future__ import annotations

import re
import shlex
import textwrap
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SHELL = ("bash", "console")
LANGUAGES = SHELL + ("python",)
#: the trailing comment that says a line fails on purpose
EXITS = re.compile(r"#\s*exits\s+(\d+)\b")
#: the options whose value is a file a command writes
OUTPUT_OPTIONS = ("-o", "--output", "--plot")
IMAGE = (".png", ".pdf", ".svg", ".jpg", ".jpeg")


@dataclass(frozen=True)
class Block:
    """One block: its page, its language, its first line in the page and its text."""

    page: Path
    language: str
    line: int
    text: str

    @property
    def where(self):
        return f"{self.page.relative_to(ROOT)}:{self.line}"


@dataclass(frozen=True)
class Line:
    """One shell command of a block: its text, the exit status it must end with and its
    block."""

    text: str
    expect: int
    block: Block


def pages(root=ROOT):
    """README.md and every reStructuredText page of the documentation (the generated
    gallery, API and build folders left out), in a fixed order."""
    skip = {"_build", "auto_examples", "generated", "_generated"}
    docs = sorted(p for p in (root / "docs").rglob("*.rst")
                  if not skip & set(p.relative_to(root / "docs").parts)
                  and p.name != "sg_execution_times.rst")
    return [root / "README.md", *docs]


def markdown_blocks(path):
    """``[Block, ...]`` of the fenced blocks of a Markdown page, every language (the
    language of a fence without one is ``""``)."""
    out, lines, i = [], path.read_text().splitlines(), 0
    while i < len(lines):
        m = re.match(r"^```\s*([\w+-]*)\s*$", lines[i])
        i += 1
        if not m:
            continue
        start, body = i, []
        while i < len(lines) and not lines[i].startswith("```"):
            body.append(lines[i])
            i += 1
        i += 1
        out.append(Block(path, m.group(1), start, "\n".join(body)))
    return out


def rst_blocks(path):
    """``[Block, ...]`` of the ``code-block``/``code`` directives and the ``::`` literal
    blocks (language ``""``) of a reStructuredText page."""
    out, lines, i = [], path.read_text().splitlines(), 0
    while i < len(lines):
        m = re.match(r"^(\s*)\.\. (?:code-block|code|sourcecode)::\s*(\S*)\s*$", lines[i])
        literal = not m and lines[i].rstrip().endswith("::") and \
            not lines[i].lstrip().startswith("..")
        i += 1
        if not (m or literal):
            continue
        indent = len(m.group(1)) if m else len(lines[i - 1]) - len(lines[i - 1].lstrip())
        while i < len(lines) and lines[i].strip().startswith(":") and m:
            i += 1  # directive options
        start, body = i, []
        while i < len(lines) and (not lines[i].strip() or
                                  len(lines[i]) - len(lines[i].lstrip()) > indent):
            body.append(lines[i])
            i += 1
        text = textwrap.dedent("\n".join(body)).strip("\n")
        if text:
            out.append(Block(path, m.group(2) if m else "", start + 1, text))
    return out


def blocks(path):
    """Every block of a page."""
    return markdown_blocks(path) if path.suffix == ".md" else rst_blocks(path)


def runnable(path):
    """The blocks of a page a reader pastes: shell and Python, in order."""
    return [b for b in blocks(path) if b.language in LANGUAGES]


def shell_lines(block):
    """``[Line, ...]`` of a shell block: continuations joined, comments and blank lines
    left out, a ``$ `` prompt removed."""
    out, pending = [], ""
    for raw in block.text.splitlines():
        s = raw.strip()
        if s.startswith("$ "):
            s = s[2:]
        if not pending and (not s or s.startswith("#")):
            continue
        if s.endswith("\\"):
            pending += s[:-1].rstrip() + " "
            continue
        s, pending = pending + s, ""
        m = EXITS.search(s)
        out.append(Line(s, int(m.group(1)) if m else 0, block))
    return out


def command(line):
    """The words of a line without its trailing comment (``shlex``), or None where the
    shell syntax cannot be split."""
    try:
        return shlex.split(line.text, comments=True)
    except ValueError:
        return None


def segments(words):
    """The simple commands of ``words`` split at ``&&``, ``||``, ``;`` and a trailing
    ``&``."""
    out, cur = [], []
    for w in words:
        if w in ("&&", "||", ";", "&"):
            if cur:
                out.append(cur)
            cur = []
        else:
            cur.append(w)
    if cur:
        out.append(cur)
    return out


def normal(words):
    """A set-up command written the way CI and a reader may differ (``python -m pip`` for
    ``pip``, pip's ``-v``), as one string."""
    w = list(words)
    if w[:3] == ["python", "-m", "pip"]:
        w = ["pip", *w[3:]]
    if w[:1] == ["pip"]:
        w = [x for x in w if x != "-v"]
    return " ".join(w)


def is_setup(words):
    """Whether a simple command is set-up that only CI runs: an install, the test
    command, the documentation build."""
    w = normal(words).split()
    return w[:2] == ["pip", "install"] or w[:3] in (["python", "-m", "pytest"],
                                                   ["python", "-m", "sphinx"])


def ci_commands(root=ROOT):
    """The set-up commands ``.ci/run`` runs, normalised (:func:`normal`); its
    ``install ARGS`` helper is ``pip install ARGS``."""
    out = set()
    for raw in (root / ".ci" / "run").read_text().splitlines():
        s = raw.strip()
        if not s or s.startswith("#"):
            continue
        try:
            words = shlex.split(s, comments=True)
        except ValueError:
            continue
        for seg in segments(words):
            if seg[:1] == ["install"]:
                seg = ["pip", "install", *seg[1:]]
            out.add(normal(seg))
    return out


def outputs(words):
    """The files a ``vibimpact`` command writes (``-o``, ``--output``, ``--plot``; the
    ``.nc`` beside a ``bifurcation`` image)."""
    out = []
    for i, w in enumerate(words):
        value = None
        if w in OUTPUT_OPTIONS and i + 1 < len(words):
            value = words[i + 1]
        elif w.startswith("--output=") or w.startswith("--plot="):
            value = w.split("=", 1)[1]
        if value:
            out.append(value)
            if words[1:2] == ["bifurcation"] and value.lower().endswith(IMAGE):
                out.append(str(Path(value).with_suffix(".nc")))
    return out


#: what a file a Python block names looks like: a relative path with a data or image
#: extension
FILE_ARGUMENT = re.compile(r"[\w.-]+(?:/[\w.-]+)*\.(?:png|pdf|svg|jpe?g|nc|zarr|csv|json|txt|"
                           r"npz|npy|h5)", re.I)


def python_outputs(text):
    """The files a Python block writes or reads by name: every string literal, passed to
    a call (positionally or by keyword: ``fig.savefig("a.png")``,
    ``plot_bifurcation(ds, path="b.png")``, ``write_netcdf(ds, "c.nc")``), that is a
    relative path with a data or image extension.  After the page ran, each is there (a
    block that ran without an exception wrote or read it)."""
    import ast

    out = []
    for node in ast.walk(ast.parse(text)):
        if isinstance(node, ast.Call):
            for arg in [*node.args, *(k.value for k in node.keywords)]:
                if isinstance(arg, ast.Constant) and isinstance(arg.value, str) and \
                        FILE_ARGUMENT.fullmatch(arg.value):
                    out.append(arg.value)
    return out
