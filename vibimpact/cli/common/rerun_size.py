"""How much work the command recorded in a file is, before ``vibimpact rerun`` starts it.

A file may come from anyone, and its ``command`` attribute says what ``rerun`` runs: a
crafted one asked for a classify of 100,000 points in both directions, or 10,000,000
forcing periods, and ``rerun`` started it without a word.  :func:`size_of` reads the
size from the recorded command's parsed arguments with the commands' own grid parser
(:func:`vibimpact.sweeps.parse_range`), before any work; ``rerun`` says it on stderr
and refuses a command over one of the limits below unless ``--yes`` is given.  The
limits are far above every example of the README and the user guide (at most a few
hundred points, 700 forcing periods, a 400-point branch) and far below the command's
own limits (:mod:`vibimpact.base._limits`).  Standard library only at import.
"""
import math

#: most sweep points (every direction counted) or map cells a rerun starts unasked
RERUN_MAX_POINTS = 20_000
#: most forcing periods a rerun integrates unasked: a simulate's transient and recorded
#: periods, or continue's --transient over every --approach step
RERUN_MAX_PERIODS = 1_000_000
#: most stored samples of a simulate rerun (stroboscopic and --dense), unasked
RERUN_MAX_SAMPLES = 10_000_000
#: most orbit periods along a continued branch (--max-points x --period, the doubled
#: branch of --switch included) a rerun starts unasked
RERUN_MAX_BRANCH_PERIODS = 20_000
#: most worker processes a rerun starts unasked
RERUN_MAX_WORKERS = 64
#: continue --approach steps eta by this much (the continue command's epilog)
_APPROACH_STEP = 0.02


class Size:
    """The size of a recorded command: what it computes, in words, and the limits it
    is over.

    Attributes
    ----------
    parts : list of str
        ``"301 sweep points (up)"``, ``"700 forcing periods"``, ...
    seconds : float or None
        A rough estimate of the computing time on one core (None when unknown).
    over : list of str
        One phrase per limit exceeded (``"200000 sweep points, more than 20000"``).
    """

    def __init__(self):
        self.parts, self.over, self.seconds = [], [], None

    def add(self, value, what, limit, seconds=None):
        """Count ``value`` ``what`` against ``limit`` (and ``seconds`` of work)."""
        self.parts.append(f"{value:,} {what}")
        if value > limit:
            self.over.append(f"{value:,} {what}, more than the {limit:,} a rerun starts "
                             f"without asking")
        if seconds is not None:
            self.seconds = (self.seconds or 0.0) + seconds

    def cost(self):
        """``"about N s of computing on one core"`` ("" when not known)."""
        from ...base._limits import human_duration

        if self.seconds is None:
            return ""
        return f"about {human_duration(self.seconds)} of computing on one core"

    def text(self):
        """``"301 sweep points, 2 worker processes, about N s of computing on one
        core"``."""
        return ", ".join(self.parts + ([self.cost()] if self.cost() else []))


def _grid_size(text, option, name="eta", positive=True):
    """The number of values of the grid ``text`` of ``option`` (``START:STOP:STEP`` or a
    list); UsageError, worded as the command words it, for a grid it refuses."""
    from .errors import error_text, UsageError
    from ...sweeps import parse_range

    try:
        return int(parse_range(text, name=name, positive=positive).size)
    except (ValueError, TypeError) as exc:
        raise UsageError(f"{option}: {error_text(exc)}") from None


def _points(size, args, count):
    from ...base._limits import SECONDS_PER_POINT

    directions = 2 if getattr(args, "direction", "up") == "both" else 1
    total = count * directions
    what = "map cells" if args.command == "map" else "sweep points"
    size.add(total, what + (" (both directions)" if directions == 2 else ""),
             RERUN_MAX_POINTS, total * SECONDS_PER_POINT)


def _n_state(args):
    """The number of states of the recorded simulate's model (None for a preset the
    command refuses)."""
    recorded = getattr(args, "recorded_start", None)  # simulate --from: the record's
    if recorded is not None:
        return len(recorded[0].state)
    from ...models import presets
    from ...core.system import to_system

    try:
        return to_system(presets.get(args.preset or presets.DEFAULT)).n_state
    except ValueError:
        return None


def _simulate(size, args):
    from ...base._limits import SECONDS_PER_PERIOD
    from .run_limits import check_run_limits

    dense = args.dense if args.dense is not None else (64 if args.plot else 0)
    n_state = _n_state(args)
    if n_state is not None:  # the command's own limits first: --yes does not lift them
        check_run_limits(args, dense, n_state)
    periods = args.periods + args.transient
    size.add(periods, "forcing periods", RERUN_MAX_PERIODS, periods * SECONDS_PER_PERIOD)
    samples = (args.periods + 1) + (args.periods * dense + 1 if dense else 0)
    size.add(samples, "samples stored", RERUN_MAX_SAMPLES)


def _continue(size, args):
    from ...base import _limits
    from .errors import error_text, UsageError

    try:  # the command's own limit first: --yes does not lift it
        _limits.check_points(args.max_points, "--max-points")
    except ValueError as exc:
        raise UsageError(error_text(exc)) from None
    steps = 1
    if args.approach is not None:
        eta = args.eta
        if eta is None:  # the preset's
            from ...models import presets

            try:  # the preset's forcing frequency
                name = args.preset or presets.DEFAULT
                eta = presets.get(name).as_array()[presets.model_of(name).omega_index]
            except ValueError:  # an unknown preset: the command refuses it
                eta = args.approach
        distance = abs(float(eta) - float(args.approach))
        if math.isfinite(distance):
            steps += math.ceil(distance / _APPROACH_STEP)
    start = args.transient * steps  # no estimate of time: the branch's is not known
    size.add(start, "forcing periods to the start", RERUN_MAX_PERIODS)
    branch = args.max_points * args.period * (3 if args.switch else 1)
    size.add(branch, "orbit periods along the branch" + (" and its --switch branch"
                                                         if args.switch else ""),
             RERUN_MAX_BRANCH_PERIODS)


def size_of(args):
    """The :class:`Size` of the parsed recorded command ``args`` (simulate's ``--plot``
    counted as the 64 dense samples per period it implied, which rerun keeps);
    UsageError for a grid or a size the command itself refuses (said as the command
    says it: ``--yes`` does not lift the command's own limits)."""
    size = Size()
    name = args.command
    if name in ("classify", "bifurcation"):
        _points(size, args, _grid_size(args.eta, "--eta"))
    elif name == "map":
        etas = _grid_size(args.eta, "--eta")
        if len(args.vary) == 1:  # else the command refuses it
            vary, _, spec = args.vary[0].partition("=")
            _points(size, args, etas * _grid_size(spec, "--vary", vary.strip() or "--vary",
                                                   positive=False))
    elif name == "simulate":
        _simulate(size, args)
    elif name == "continue":
        _continue(size, args)
    workers = getattr(args, "workers", None)
    if workers is not None:
        size.add(workers, "worker processes" if workers != 1 else "worker process",
                 RERUN_MAX_WORKERS)
    return size


def limits_text():
    """The limits, for the help and the refusal."""
    return (f"{RERUN_MAX_POINTS:,} sweep points or map cells, {RERUN_MAX_PERIODS:,} "
            f"forcing periods, {RERUN_MAX_SAMPLES:,} stored samples, "
            f"{RERUN_MAX_BRANCH_PERIODS:,} orbit periods along a branch or "
            f"{RERUN_MAX_WORKERS} worker processes")


__all__ = ["RERUN_MAX_BRANCH_PERIODS", "RERUN_MAX_PERIODS", "RERUN_MAX_POINTS",
           "RERUN_MAX_SAMPLES", "RERUN_MAX_WORKERS", "Size", "limits_text", "size_of"]
