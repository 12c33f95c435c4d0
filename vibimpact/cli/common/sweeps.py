"""What the sweep commands (``classify``, ``bifurcation``) share: their options (the eta
grid, the preset, ``--set``, direction, workers, blocks), the grid and parameters read
from them, and the command line recorded in the file."""
import os

from .args import (DEFAULT_PRESET, DEFAULT_PRESET_HELP, SWEEP_FREQUENCIES, swept,
                   parse_sets, positive_int,
                   preset_name, with_sets, MAX_WORKERS)
from .errors import error_text, UsageError
from ...base._limits import MAX_POINTS

def default_workers():
    """Worker processes of a sweep by default: two, or one on a single CPU."""
    return min(2, os.cpu_count() or 1)


def sweep_inputs(args):
    """Grid, parameters from the parsed arguments; UsageError for bad input."""
    from ...models import presets
    from ...sweeps import parse_range

    try:
        etas = parse_range(swept(args))
    except ValueError as exc:
        raise UsageError(f"--eta: {exc}") from None
    try:
        base = presets.get(args.preset)
    except ValueError as exc:
        raise UsageError(error_text(exc)) from None
    return etas, with_sets(base, parse_sets(args.set))


def command_line(args):
    """The command line as the file records it: ``vibimpact ARGS``, quoted for a shell."""
    import shlex

    return shlex.join(["vibimpact"] + list(args.argv))


def add_sweep_options(s, direction):
    """Add the options every sweep command takes to its parser ``s`` (``direction``: the
    default of --direction)."""
    s.add_argument("--eta", default=SWEEP_FREQUENCIES,
                   metavar="START:STOP:STEP|V1,V2,...",
                   help="grid of the forcing frequency: a range (STOP is included "
                        "when it lies on the grid) or a list of increasing values, e.g. "
                        f"1.0,1.1,1.25 (default: {SWEEP_FREQUENCIES})")
    s.add_argument("--preset", default=DEFAULT_PRESET, type=preset_name,
                   help=f"parameter set (default: {DEFAULT_PRESET_HELP}); see "
                        "'vibimpact presets'")
    s.add_argument("--set", action="append", metavar="NAME=VALUE", default=[],
                   help="change a parameter of the preset, e.g. BT=0.05 (repeatable)")
    s.add_argument("--direction", choices=("up", "down", "both"), default=direction,
                   help=f"sweep direction (default: {direction})")
    s.add_argument("--workers", type=positive_int(1, MAX_WORKERS), default=default_workers(),
                   metavar="N", help="processes computing at once (default: min(2, CPUs) "
                   f"= {default_workers()}); does not change the result")
    s.add_argument("--blocks", type=positive_int(1, MAX_POINTS), default=16, metavar="N",
                   help="seeded blocks per direction, 1 = pure serial continuation "
                        "(default: 16)")
    s.add_argument("--overwrite", action="store_true", help="replace existing output files")
    s.add_argument("--no-progress", action="store_true",
                   help="no progress bar on stderr")
