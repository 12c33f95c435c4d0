"""The hand-written reading of ``reports/paper.md``, tied to the report's data.

``paper_notes.md`` is prose written by a person, but every statement in it about a result
is bound to the data that ``paper.py`` stores in ``reports/paper.json``:

``{{ EXPR }}`` or ``{{ EXPR | FORMAT }}``
    A value filled in from the data when the report is rendered (a verdict, a number):
    the prose cannot state another one.
``<!-- check: EXPR -->``
    An assertion next to the sentence it backs; rendering fails when it is false, so a
    sentence whose data changed is rewritten, not left to contradict the table.

Every paragraph and every bullet of the notes carries at least one of the two (else the
render fails: a statement nothing checks is refused).  ``EXPR`` is a Python expression
over the names of :func:`namespace` (the JSON as ``P`` and a few shorthands).
``tests/test_paper_notes.py`` renders the notes again from ``reports/paper.json``,
compares with the section in ``reports/paper.md`` and checks that a contradicting
statement fails.
"""
from __future__ import annotations

import re
from pathlib import Path

NOTES = Path(__file__).resolve().parent / "paper_notes.md"
#: markers of the notes' section in reports/paper.md
BEGIN, END = "<!-- paper-notes -->", "<!-- /paper-notes -->"
_FILL = re.compile(r"\{\{(.+?)\}\}", re.S)
_CHECK = re.compile(r"<!--\s*check:(.+?)-->", re.S)


class NotesDrift(ValueError):
    """A statement of the notes contradicts the report's data, or is checked by nothing."""


def namespace(summary):
    """The names an expression of the notes may use.

    ``P``: the whole summary (``reports/paper.json``); ``V``: claim key -> verdict;
    ``VP``: the same at the previous defaults; ``O``: claim key -> census outcome;
    ``cmp(prefix)``: the measured values of the one comparative row whose key starts with
    ``prefix`` (e.g. ``"fig9:"``), with its ``verdict``; ``census(key)``: the census
    summary of one claim; ``sets(preset)``: the census's parameter sets of one figure.
    """
    def one(prefix):
        keys = [k for k in summary["comparative"] if k.startswith(prefix)]
        if len(keys) != 1:
            raise NotesDrift(f"cmp({prefix!r}) names {len(keys)} comparative rows: {keys}")
        return keys[0]

    def cmp(prefix):
        k = one(prefix)
        return {**summary["comparative_values"][k], "verdict": summary["comparative"][k]}

    census = summary.get("census_claims", {})
    return dict(P=summary, V=summary["verdicts"], VP=summary["verdicts_previous"],
                O=summary.get("census_outcomes", {}), cmp=cmp,
                census=lambda key: next(c for c in census["claims"] if c["key"] == key),
                sets=lambda preset: census["sets"][preset],
                abs=abs, min=min, max=max, len=len, all=all, any=any, sorted=sorted,
                round=round)


def _eval(expr, ns, where):
    try:
        # the names as globals: comprehensions in an expression see them too
        return eval(expr, {"__builtins__": {}, **ns})  # noqa: S307 (our own file)
    except NotesDrift:
        raise
    except Exception as exc:
        raise NotesDrift(f"{where}: {expr.strip()!r} cannot be evaluated: "
                         f"{type(exc).__name__}: {exc}") from None


def _fill(match, ns, where):
    expr, _, fmt = match.group(1).partition("|")
    return format(_eval(expr, ns, where), fmt.strip())


def blocks(text):
    """The paragraphs and bullets of ``text`` (headings left out), with line numbers."""
    out, cur, start = [], [], 0
    for i, line in enumerate(text.splitlines() + [""], 1):
        new_item = line.lstrip().startswith(("* ", "- ")) or not line.strip()
        if new_item and cur:
            out.append((start, "\n".join(cur)))
            cur = []
        if line.strip() and not line.startswith("#"):
            if not cur:
                start = i
            cur.append(line)
    return out


def render(summary, text=None):
    """The notes with every value filled in, after every check passed.

    Parameters
    ----------
    summary : dict
        The report's data (what ``paper.py`` writes to ``reports/paper.json``).
    text : str, optional
        The notes (default: ``paper_notes.md``).

    Returns
    -------
    str
        The section, between :data:`BEGIN` and :data:`END`.

    Raises
    ------
    NotesDrift
        Naming every failed check, every expression that cannot be evaluated and every
        paragraph or bullet that nothing checks.
    """
    text = NOTES.read_text() if text is None else text
    ns = namespace(summary)
    errors = []
    for line, block in blocks(text):
        if not (_FILL.search(block) or _CHECK.search(block)):
            errors.append(f"line {line}: a statement no value or check backs: "
                          f"{block[:80]!r}")
        for m in _CHECK.finditer(block):
            try:
                if not _eval(m.group(1), ns, f"line {line}"):
                    errors.append(f"line {line}: check fails: {m.group(1).strip()}")
            except NotesDrift as exc:
                errors.append(str(exc))
    if errors:
        raise NotesDrift("paper_notes.md contradicts reports/paper.json:\n  "
                         + "\n  ".join(errors))
    body = _FILL.sub(lambda m: _fill(m, ns, "paper_notes.md"), text.strip())
    return "\n".join([BEGIN, body, END])


def section_of(report_text):
    """The notes' section of a rendered ``reports/paper.md`` (markers included)."""
    a, b = report_text.index(BEGIN), report_text.index(END) + len(END)
    return report_text[a:b]
