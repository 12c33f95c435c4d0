"""``vibimpact presets``: every built-in model's parameter sets, each model's as it declares
them (:attr:`vibimpact.models.PlotSpec.preset_columns`)."""

_PRESETS_EPILOG = """\
example:
  vibimpact presets

A model's table shows the parameters it declares as columns; columns marked * are
explained under the table.  The presets of a model that declares no columns are listed
with all their values.  The last lines say what the commands do with each model when
not told: the frequencies a sweep and a map cover, where a census and a basin image look.
"""


def _table(model):
    """The lines of ``model``'s table of presets (its declared columns)."""
    from ..models import presets

    spec = model.plot
    cols = spec.preset_columns
    header = ("name",) + tuple(c + "*" if c in spec.preset_marked else c for c in cols)
    rows = []
    for name in model.presets:
        p = presets.get(name).as_dict()
        mark = " (default)" if name == presets.DEFAULT else ""
        rows.append((name,) + tuple(f"{p[c]:g}" for c in cols)
                    + (presets.describe(name) + mark,))
    widths = [max(len(r[i]) for r in rows + [header]) for i in range(len(header))]
    lines = ["  ".join(h.ljust(w) for h, w in zip(header, widths)) + "  description"]
    lines += ["  ".join(c.ljust(w) for c, w in zip(r, widths)) + "  " + r[-1] for r in rows]
    if spec.preset_note:
        lines.append(f"\n* {spec.preset_note}")
    return lines


def _cmd_presets(args):
    from .. import models
    from ..models import presets

    tabled = [m for m in map(models.get, models.names())
              if m.plot is not None and m.plot.preset_columns and m.presets]
    for k, model in enumerate(tabled):
        if k:
            print(f"\nPresets of the {model.name} model:")
        print("\n".join(_table(model)))
    shown = {name for m in tabled for name in m.presets}
    others = [n for n in presets.names() if n not in shown]
    if others:
        print("\nPresets of the other built-in models:")
        for name in others:
            values = ", ".join(f"{k}={v:g}" for k, v in presets.get(name).as_dict().items())
            mark = " (default)" if name == presets.DEFAULT else ""
            print(f"  {name}  ({type(presets.get(name)).__name__}: {values})  "
                  f"{presets.describe(name)}{mark}")
    print("\nWithout --eta (and --preset for attractors and basins), each model's:")
    for name in models.names():
        if models.get(name).presets:
            print("  " + _defaults_line(models.get(name)))
    return 0


def _defaults_line(model):
    """One line of what the commands do with ``model`` when not told
    (:func:`vibimpact.models.presets.command_default` of its first preset)."""
    from ..models.presets import command_default

    first = next(iter(model.presets))
    sweep = command_default("frequencies", first)
    where = str(command_default("census_preset", first))
    freq = command_default("census_frequency", where)
    sweeps = (f"sweeps {sweep}, maps {command_default('map_frequencies', first)}"
              if sweep is not None else "sweeps and maps need --eta")
    return f"{model.name}: {sweeps}; attractors and basins {where} at {freq:g}"


def add_parser(sub, fmt):
    """Add ``presets`` to the subparsers ``sub``."""
    p = sub.add_parser("presets", help="list the built-in models' parameter sets",
                       description="List the presets of the built-in models (the paper's: "
                                   "one per figure) with their parameters.",
                       epilog=_PRESETS_EPILOG, formatter_class=fmt)
    p.set_defaults(func=_cmd_presets)
