"""The limits of one run (forcing periods, memory) in the words of the command line's
options: ``simulate`` checks them before it computes, ``rerun`` before it announces."""
from .errors import error_text, UsageError


def check_run_limits(args, dense, n_state):
    """The limits of :func:`vibimpact.base._limits.check_run` (forcing periods, memory),
    checked here so that the refusal names the options (``--periods 5 with --dense
    10``), not the API's arguments (``periods=5``)."""
    from ...base import _limits

    total = args.periods + args.transient
    if total > _limits.MAX_PERIODS:
        cost = _limits.human_duration(total * _limits.SECONDS_PER_PERIOD)
        raise UsageError(f"--periods {args.periods} + --transient {args.transient} is "
                         f"{total} forcing periods (about {cost} at "
                         f"~{_limits.SECONDS_PER_PERIOD * 1e3:g} ms per period); at most "
                         f"{_limits.MAX_PERIODS} in one run")
    samples = (f"--dense {dense}" if args.dense is not None else
               f"the {dense} samples per period of --plot")
    try:
        _limits.check_memory(_limits.run_bytes(args.periods, dense, n_state),
                             f"--periods {args.periods} with {samples}")
    except ValueError as exc:
        raise UsageError(error_text(exc)) from None
