"""``vibimpact presets``: the paper's parameter sets and the other built-in models'."""
_PRESET_COLUMNS = ("kh", "G", "Bh", "BT", "f", "Rr", "B", "Ec")

_PRESETS_EPILOG = """\
example:
  vibimpact presets

B (support damping) and Ec (unbalance eccentricity) are not given in the paper; every
preset uses our documented defaults for them.
"""


def _cmd_presets(args):
    from ..models import presets

    header = ("name",) + tuple(c + "*" if c in ("B", "Ec") else c for c in _PRESET_COLUMNS)
    rows = []
    for name in presets.paper_names():
        p = presets.get(name).as_dict()
        rows.append((name,) + tuple(f"{p[c]:g}" for c in _PRESET_COLUMNS)
                    + (presets.describe(name),))
    widths = [max(len(r[i]) for r in rows + [header]) for i in range(len(header))]
    print("  ".join(h.ljust(w) for h, w in zip(header, widths)) + "  description")
    for r in rows:
        print("  ".join(c.ljust(w) for c, w in zip(r, widths)) + "  " + r[-1])
    print("\n* B and Ec are our defaults, not values from the paper; all the paper's presets have "
          "k3 = -0.002 and eta is set per run (--eta).")
    others = [n for n in presets.names() if n not in presets.paper_names()]
    if others:
        print("\nPresets of the other built-in models:")
        for name in others:
            values = ", ".join(f"{k}={v:g}" for k, v in presets.get(name).as_dict().items())
            print(f"  {name}  ({type(presets.get(name)).__name__}: {values})  "
                  f"{presets.describe(name)}")
    return 0


def add_parser(sub, fmt):
    """Add ``presets`` to the subparsers ``sub``."""
    p = sub.add_parser("presets", help="list the paper's parameter sets",
                       description="List the presets (one per figure of the paper) with "
                                   "their parameters.", epilog=_PRESETS_EPILOG,
                       formatter_class=fmt)
    p.set_defaults(func=_cmd_presets)
