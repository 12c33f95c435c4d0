"""``vibimpact simulate --from SWEEP.nc``: where a run starts when it starts from a sweep.

A sweep with continuation follows one attractor through eta; from rest a run at the same
eta may land on another one that coexists with it (fig8 at eta = 1.25: the sweep up from
1.1 is chaotic, the run from rest impactless).  ``--from`` starts the run from the sweep's
state at that grid value and direction (:func:`vibimpact.sweeps.sweep_start`), with the
sweep's parameters; ``--set`` changes named ones explicitly; ``--preset`` and ``--state0``
are refused with it.

The file written records the start: the state as the ``state0`` variable, the sweep's
point, label, parameters and command as ``start_*`` attributes
(:meth:`vibimpact.sweeps.SweepStart.attrs`).  ``vibimpact rerun`` starts from that record
(:func:`recorded_start`) and never reads the sweep's file, which may have moved, changed
or gone since.  Only the standard library is imported at module level.
"""
import os

from .args import parse_sets, with_sets
from .errors import error_text, UsageError
from .files import read_input

#: how :func:`vibimpact.sweeps.sweep_start`'s messages name what the command line gives
#: as the file of --from and the options --eta and --direction
_FROM_NAMES = {"ds": "the file", "eta": "--eta", "direction": "--direction"}


def start_of(args):
    """The parameters, initial state and file attributes of ``simulate --from``.

    Reads the sweep named by ``args.from_sweep`` at ``args.eta`` and ``args.direction``,
    or takes ``args.recorded_start`` (set by ``vibimpact rerun`` from the file being
    rerun) without reading any sweep.

    Returns
    -------
    params : Params
        The sweep's parameters at the grid value of eta, ``--set`` applied.
    state0 : ndarray
        The sweep's ``final_state`` there.
    attrs : dict
        ``preset`` (the sweep's) and the start's provenance (``start_*``).
    note : str
        A sentence for the summary line.

    Raises
    ------
    UsageError
        For ``--preset`` or ``--state0`` with ``--from``, and for everything
        :func:`vibimpact.sweeps.sweep_start` refuses, naming the file.
    """
    from ...sweeps.start import sweep_start

    path = os.fspath(args.from_sweep)
    for given, option in ((args.preset, "--preset"), (args.state0, "--state0")):
        if given is not None:
            raise UsageError(f"{option} cannot be combined with --from: the run starts "
                             "from the sweep's state with the sweep's parameters (change "
                             "a parameter explicitly with --set NAME=VALUE)")
    sets = parse_sets(args.set)
    recorded = getattr(args, "recorded_start", None)
    if recorded is not None:
        start, preset = recorded
    else:
        ds = read_input(path, "--from")
        try:
            start = sweep_start(ds, args.eta, args.direction, source=path,
                                names=_FROM_NAMES)
        except (TypeError, ValueError) as exc:
            raise UsageError(f"--from {path!r}: {error_text(exc)}") from None
        preset = str(ds.attrs.get("preset", ""))
    params = with_sets(start.params, sets)
    changed = ", ".join(f"{k}={v:g}" for k, v in sets.items())
    note = (f"started from {path} at eta = {start.eta:.12g} ({start.direction}), where the "
            f"sweep found '{start.label}'"
            + (f"; parameters changed from the sweep's: {changed}" if changed else ""))
    return params, start.state, {"preset": preset, **start.attrs()}, note


def recorded_start(ds, path):
    """The start recorded in the run file ``ds`` (read from ``path``) that ``vibimpact
    rerun`` hands to ``simulate --from`` as ``args.recorded_start``: ``(SweepStart,
    preset)``; UsageError when the file records none."""
    from ...sweeps.start import SweepStart

    try:
        start = SweepStart.from_run_dataset(ds, name="it")
    except ValueError as exc:
        raise UsageError(f"{path!r} was written by 'simulate --from' but "
                         f"{error_text(exc)}") from None
    return start, str(ds.attrs.get("preset", ""))


__all__ = ["recorded_start", "start_of"]
