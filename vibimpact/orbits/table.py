"""The text table of a hunt's orbits (what ``vibimpact orbits`` prints)."""
from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:  # names of the annotations only
    from .found import OrbitHunt

__all__ = ["orbit_table", "interval_text"]


def interval_text(pairs):
    """``"1.05-1.062, 1.07-1.08"``; ``"-"`` for none."""
    return ", ".join(f"{a:.5g}-{b:.5g}" for a, b in pairs) or "-"


def orbit_table(hunt: OrbitHunt) -> list[str]:
    """One header and one line per orbit: label, arcs, ``|mu|max``, existence and
    stability intervals (when continued), and a last line with the counts."""
    p = hunt.param
    head = ("#", "orbit", "arcs", "|mu|max", f"exists in {p}", f"stable in {p}",
            "ends (low / high)")
    rows = []
    for i, o in enumerate(hunt.orbits):
        e = o.extent
        rows.append((str(i), o.label, o.arcs or "-", f"{o.abs_max:.4g}",
                     "-" if e is None else interval_text([(e.lo, e.hi)]),
                     "-" if e is None else interval_text(e.stable),
                     "-" if e is None else f"{e.lo_reason} / {e.hi_reason}"))
    widths = [max(len(r[j]) for r in rows + [head]) for j in range(len(head))]
    fmt = "  ".join(f"{{:{w}s}}" for w in widths)
    lines = [fmt.format(*head).rstrip()] + [fmt.format(*r).rstrip() for r in rows]
    c = hunt.counts
    lines.append(f"{len(hunt.orbits)} orbits at {p} = {hunt.value:g} from "
                 f"{hunt.seeds.shape[0]} seeds ({hunt.n_user} given, "
                 f"{hunt.seeds.shape[0] - hunt.n_user} random, seed {hunt.random_seed}); "
                 f"{c['shots']} Newton runs, {c['converged']} converged, "
                 f"{c['known']} starts next to known orbits skipped")
    return lines
