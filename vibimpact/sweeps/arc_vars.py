"""The loaded arcs of every sweep point as dataset variables (start, end, width, loaded).

A point's arcs (:func:`vibimpact.analysis.contact_arcs` of its record: each contact from
entry to exit, sliding included) travel in its result as ``arc_table``, one row
``(start, end, width, loaded)`` per arc.  :func:`add_arc_variables` stores them on a
dimension ``arc`` of :data:`MAX_STORED_ARCS` slots, NaN where a point has fewer arcs
(``n_arcs`` counts them all).
"""
from __future__ import annotations

import numpy as np

#: arcs stored per point; a point with more keeps the most loaded ones (in order of start)
MAX_STORED_ARCS = 8

_WHERE = "{angle}; each arc runs towards increasing angle from its start to its end"
#: ``name: (column of arc_table, units, long_name with the model's words in its
#: ``{fields}``, :func:`vibimpact.models.words.file_words`)``
ARC_VARIABLES = {
    "arc_start": (0, "degree", f"start of each loaded arc of the {{obstacle}} ({_WHERE})"),
    "arc_end": (1, "degree", f"end of each loaded arc of the {{obstacle}} ({_WHERE})"),
    "arc_width": (2, "degree", "angular extent of each loaded arc: the angles its contacts "
                               "cover from entry to exit, sliding included"),
    "arc_loaded": (3, "1", "loaded share of each arc: fraction of the recorded time the "
                           "body is in contact on it"),
}


def kept(table):
    """The rows of an ``(k, 4)`` arc table that are stored: all of them up to
    :data:`MAX_STORED_ARCS`, else that many of the most loaded, in order of start."""
    table = np.asarray(table, dtype=np.float64).reshape(-1, 4)
    if table.shape[0] <= MAX_STORED_ARCS:
        return table
    top = np.sort(np.argsort(-np.nan_to_num(table[:, 3], nan=-1.0),
                             kind="stable")[:MAX_STORED_ARCS])
    return table[top]


def add_arc_variables(ds, results, dirs, n, dims, words):
    """Add ``arc_start``, ``arc_end``, ``arc_width`` and ``arc_loaded`` on ``dims +
    ("arc",)`` to the sweep dataset ``ds`` of a model with a contact
    (``results[direction]``: result dicts in sweep order, None where not computed).  A
    point whose result carries no arc table (not computed, or a result saved before arcs
    were stored) has NaN in every slot, as every not-computed value; so a map's template
    and its filled rows, and a sweep and a map, have the same variables.  ``words``: the
    model's (:func:`vibimpact.models.words.file_words`).  Returns ``ds``."""
    table = np.full((len(dirs), n, MAX_STORED_ARCS, 4), np.nan)
    for a, d in enumerate(dirs):
        order = np.arange(n) if d == "up" else np.arange(n)[::-1]
        for i, r in enumerate(results[d]):
            if r is None or r.get("arc_table") is None:
                continue
            rows = kept(r["arc_table"])
            table[a, order[i], :rows.shape[0]] = rows
    for name, (col, units, long_name) in ARC_VARIABLES.items():
        ds[name] = (tuple(dims) + ("arc",), table[..., col],
                    dict(units=units, long_name=long_name.format(**words)))
    return ds
