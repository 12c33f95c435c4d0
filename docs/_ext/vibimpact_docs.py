"""Build-time content of the vibimpact documentation.

Numbers on the documentation pages are never typed by hand.  When the builder starts,
this extension writes reStructuredText includes into ``docs/_generated/``:

``presets.rst``
    the table of the presets, from :mod:`vibimpact.models.presets` (every :class:`~vibimpact.Params`
    field of every preset and what the paper shows for it);
``defaults.rst``
    the calibrated defaults ``B`` and ``Ec`` from :mod:`vibimpact.builtin_models.rotor`, with the
    calibration report (``reports/calibration.md``) and the README's summary quoted;

It also provides :func:`figure_scraper`, a sphinx-gallery image scraper for the
matplotlib figures that :mod:`vibimpact.plotting` draws with the object API (they are not
registered with pyplot, so the stock scraper does not see them).
"""
from __future__ import annotations

import json
import re
from pathlib import Path

DOCS = Path(__file__).resolve().parents[1]
ROOT = DOCS.parent
GENERATED = DOCS / "_generated"


# -- Markdown (of the reports) to reStructuredText, inline only ----------------------------

_INLINE = re.compile(r"(`[^`]+`)|(\*\*[^*]+\*\*)|(\[([^\]]+)\]\(([^)]+)\))|"
                     r"(?<![\w*])(\*[^*\s][^*]*\*)(?![\w*])")


def _escape(text):
    return re.sub(r"([\\*_|`<>])", r"\\\1", text)


def md_inline(text):
    """One paragraph of Markdown as reStructuredText: code, bold and links kept, anything
    else that reStructuredText would read as markup escaped."""
    out, pos = [], 0
    for m in _INLINE.finditer(text):
        before = text[pos:m.start()]
        out.append(_escape(before))
        if (before or (out and out[-1]))[-1:].isalnum():
            out.append("\\ ")  # reStructuredText needs a boundary before markup
        if m.group(1):
            out.append(f"``{m.group(1)[1:-1]}``")
        elif m.group(2):
            out.append(f"**{_escape(m.group(2)[2:-2])}**")
        elif m.group(6):
            out.append(f"*{_escape(m.group(6)[1:-1])}*")
        else:
            label, target = m.group(4), m.group(5)
            if target.startswith(("http://", "https://")):
                out.append(f"`{_escape(label)} <{target}>`__")
            elif label.strip("`") == target:
                out.append(f"``{target}``")
            else:
                out.append(f"{_escape(label)} (``{target}``)")
        pos = m.end()
        if text[pos:pos + 1].isalnum():
            out.append("\\ ")  # and after it
    out.append(_escape(text[pos:]))
    return "".join(out)


def _paragraphs(markdown):
    """Paragraphs of a Markdown text (blank-line separated), code blocks dropped."""
    paras, cur, fence = [], [], False
    for line in markdown.splitlines():
        if line.startswith("```"):
            fence = not fence
            continue
        if fence:
            continue
        if line.strip():
            cur.append(line.strip())
        elif cur:
            paras.append(" ".join(cur))
            cur = []
    if cur:
        paras.append(" ".join(cur))
    return paras


def _quote(paragraphs):
    lines = []
    for para in paragraphs:
        lines += ["   " + md_inline(para), ""]
    return lines


# -- the generated pages ---------------------------------------------------------------

def _fmt(value):
    return f"{value:g}"


def presets_rst():
    """The presets table (a list-table) from :mod:`vibimpact.models.presets`."""
    from vibimpact import presets
    from vibimpact.builtin_models import rotor

    names = rotor.paper_names()
    fields = list(presets.get(names[0]).as_dict())
    lines = [".. list-table:: The presets (``vibimpact.models.presets.get(name)``), generated from "
             "``vibimpact.models.presets``",
             "   :header-rows: 1",
             "   :class: presets-table",
             "",
             "   * - preset"]
    lines += [f"     - ``{f}``" for f in fields]
    lines.append("     - what the paper shows")
    for name in names:
        p = presets.get(name).as_dict()
        default = " (default)" if name == presets.DEFAULT else ""
        lines.append(f"   * - ``{name}``{default}")
        lines += [f"     - {_fmt(p[f])}" for f in fields]
        lines.append(f"     - {md_inline(presets.describe(name))}")
    lines.append("")
    return "\n".join(lines)


def _calibration():
    """The winner's JSON record and the paragraphs of ``reports/calibration.md``."""
    path = ROOT / "reports" / "calibration.md"
    text = path.read_text(encoding="utf-8")
    m = re.search(r"```json\n(.*?)\n```", text, re.S)
    record = json.loads(m.group(1)) if m else {}
    body = text.split("\n## ", 1)[0]
    paras = [p for p in _paragraphs(body) if not p.startswith(("#", "!["))]
    return record, paras


def _readme_summary():
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    m = re.search(r"<!-- section:summary -->\n(.*?)<!-- /section:summary -->", text, re.S)
    if not m:
        return []
    return [line[2:].strip() for line in m.group(1).splitlines() if line.startswith("* ")]


def defaults_rst():
    """The calibrated defaults of ``B`` and ``Ec`` and where they come from."""
    from vibimpact.models import params
    from vibimpact import presets

    record, paras = _calibration()
    lines = [
        f"The presets use ``B = {_fmt(params.DEFAULT_B)}`` "
        f"(:data:`vibimpact.builtin_models.rotor.DEFAULT_B`) and "
        f"``Ec = {_fmt(params.DEFAULT_EC)}`` "
        f"(:data:`vibimpact.builtin_models.rotor.DEFAULT_EC`).",
        "",
    ]
    if record:
        agree = "agree with" if (record.get("B") == params.DEFAULT_B
                            and record.get("Ec") == params.DEFAULT_EC) else "DIFFER FROM"
        lines += [
            f"These values {agree} the optimum of the last calibration run recorded in "
            f"``reports/calibration.md``: reading ({record.get('reading')}) — "
            f"{md_inline(str(record.get('text')))} — at ``B = {_fmt(record['B'])}``, "
            f"``Ec = {_fmt(record['Ec'])}``, objective {record['objective']:.3f}, "
            f"{record['agree_count']} of {record['claims']} fitted claims agree "
            f"(interior optimum: {'yes' if record.get('interior') else 'no'}; converged: "
            f"{'yes' if record.get('converged') else 'no'}).",
            "",
        ]
        presets_used = record.get("presets", {})
        if presets_used:
            lines += ["The contact dampings of that reading, per figure:", ""]
            for fig, vals in presets_used.items():
                got = presets.get(fig).as_dict() if fig in presets.names() else {}
                same = all(got.get(k) == v for k, v in vals.items())
                vals_txt = ", ".join(f"``{k} = {_fmt(v)}``" for k, v in vals.items())
                lines.append(f"* ``{fig}``: {vals_txt}"
                             + ("" if same else " (**the preset differs**)"))
            lines.append("")
    if paras:
        lines += ["From the calibration report (``reports/calibration.md``, generated by "
                  "``python analyses/paper/calibrate.py``):", ""]
        lines += _quote(paras)
    summary = _readme_summary()
    if summary:
        lines += ["The README's summary of the reports (written by "
                  "``analyses/paper/readme_summary.py``):", ""]
        lines += _quote(summary)
    return "\n".join(lines)


PAGES = {"presets.rst": presets_rst, "defaults.rst": defaults_rst}


def write_generated(app=None):
    """Write every generated include, touching only those whose text changed."""
    GENERATED.mkdir(exist_ok=True)
    for name, make in PAGES.items():
        text = ".. This file is generated by docs/_ext/vibimpact_docs.py; do not edit.\n\n" \
            + make() + "\n"
        path = GENERATED / name
        if not path.exists() or path.read_text(encoding="utf-8") != text:
            path.write_text(text, encoding="utf-8")


# -- sphinx-gallery: figures drawn with matplotlib's object API ----------------------------

def figure_scraper(block, block_vars, gallery_conf):
    """Save every matplotlib figure an example holds in a global variable (a ``Figure``,
    or ``Axes`` of one) that pyplot does not manage and that was not shown before."""
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
    from sphinx_gallery.scrapers import figure_rst

    figs = []
    for value in list(block_vars["example_globals"].values()):
        items = value if isinstance(value, (list, tuple)) else [value]
        for item in items:
            if isinstance(item, Axes):
                fig = item.figure
            elif isinstance(item, Figure):
                fig = item
            else:
                continue
            if hasattr(fig, "get_figure"):
                fig = fig.get_figure(root=True)
            if getattr(fig.canvas, "manager", None) is not None:
                # a pyplot figure: the matplotlib scraper (after this one) saves it
                fig._vibimpact_scraped = True
                continue
            if getattr(fig, "_vibimpact_scraped", False) or any(fig is f for f in figs):
                continue
            figs.append(fig)
    paths = []
    for fig, path in zip(figs, block_vars["image_path_iterator"]):
        fig.savefig(path, dpi=100)
        fig._vibimpact_scraped = True
        paths.append(path)
    return figure_rst(paths, gallery_conf["src_dir"])


def setup(app):
    app.connect("builder-inited", write_generated)
    return {"parallel_read_safe": True, "parallel_write_safe": True, "version": "1"}
