"""Reading cProfile statistics of the package's runs.

The integration loop is called through its compiled entry point once numba has typed it
(:meth:`vibimpact._kernel.precompiled.Routine.call_keyed`); cProfile records that call
as a built-in, ``<built-in method vibimpact._kernel.driver.integrate>`` in file ``~``.
:func:`as_source` names it as its Python source, ``.../vibimpact/_kernel/driver.py``,
``integrate``, as a call through numba's dispatcher is named, so that every script that
attributes profile time to the kernel counts both.
"""
from __future__ import annotations

import re

_BUILTIN = re.compile(r"<built-in method (vibimpact(?:\.\w+)*)\.(\w+)>")


def as_source(key):
    """A profile key ``(file, line, function)``, a compiled kernel entry point's (a
    built-in of module ``vibimpact.X.Y``) as its Python source's ``vibimpact/X/Y.py``."""
    fname, line, fn = key
    m = _BUILTIN.fullmatch(fn) if fname == "~" else None
    if m is None:
        return key
    return m.group(1).replace(".", "/") + ".py", line, m.group(2)


def by_source(stats):
    """``stats`` (:attr:`pstats.Stats.stats`) with every key :func:`as_source`'s; the
    entries of one source summed (calls, primitive calls, tottime, cumtime)."""
    out = {}
    for key, value in stats.items():
        k = as_source(key)
        if k in out:
            old = out[k]
            value = (old[0] + value[0], old[1] + value[1], old[2] + value[2],
                     old[3] + value[3], {})
        out[k] = value
    return out
