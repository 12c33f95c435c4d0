"""The result of a simulation: :class:`Run`, its :class:`Status`, and the impact log."""
from __future__ import annotations

from typing import TYPE_CHECKING, Any

import enum
import numbers
from dataclasses import dataclass, field

import numpy as np

if TYPE_CHECKING:  # names of the annotations only
    from collections.abc import Mapping
    from typing import Any

    import xarray as xr
    from numpy.typing import ArrayLike

from ..models import contact as _contact
from .._kernel import boundary as _k


class Status(enum.Enum):
    """How a run ended."""

    OK = "ok"
    #: the state became non-finite or left the bound: a blow-up, not data
    DIVERGED = "diverged"
    #: the integrator could not go on (step-size underflow, step limit, Zeno events)
    FAILED = "failed"


_REASONS = {
    _k.OK: (Status.OK, ""),
    _k.DIVERGED_NONFINITE: (Status.DIVERGED, "state became non-finite"),
    _k.DIVERGED_BOUND: (Status.DIVERGED, "state left the bound"),
    _k.STEP_UNDERFLOW: (Status.FAILED, "step size underflow"),
    _k.MAX_STEPS: (Status.FAILED, "step limit per forcing period reached"),
    _k.ZENO: (Status.FAILED, "accumulating switching events (Zeno)"),
}


def status_of(code):
    """(Status, reason) of a kernel status code."""
    return _REASONS[int(code)]


#: fields of :attr:`Run.impacts`, one record per contact (:mod:`vibimpact.models.contact`)
IMPACT_DTYPE = _contact.IMPACT_DTYPE

#: fields of :attr:`Run.events`, one record per located switching event
EVENT_DTYPE_FIELDS = ("t", "which", "mode_before", "mode_after", "state")


@dataclass
class Run:
    """Result of :func:`vibimpact.simulate`.

    Attributes
    ----------
    params : Params or DuffingParams or ndarray
    model : str
    strobe : ndarray, shape (periods + 1, n)
        Stroboscopic (Poincare) samples at ``tau_k = 2 pi k / omega`` for
        ``k = transient, ..., transient + periods``.  Fewer rows when the run stopped early
        (see :attr:`status`): rows are never padded with NaN.
    t_strobe : ndarray, shape (len(strobe),)
    impacts : ndarray of :data:`IMPACT_DTYPE`
        One record per contact entered after the transient (empty for a model without
        a contact).
    events : dict of ndarray
        Raw event log: ``t``, ``which`` (switch index), ``mode_before``, ``mode_after``,
        ``state``.  The model's switches (for the built-in rotor, switch 0 is contact
        entry/exit, 1 a friction switch, 2 an extremum of ``R``, an observer).
    dense : ndarray, shape (periods * dense + 1, n) or None
        Evenly spaced samples, only when asked for.
    t_dense : ndarray or None
    status : Status
    reason : str
        Why the run stopped, empty when OK.
    counters : dict
        ``steps``, ``rhs_evals``, ``rejected``, ``events``, ``observed``.
    final_state : ndarray, shape (n,)
        State at the last stroboscopic time (the last row of ``strobe``).
    solver : dict
        ``method``, ``rtol``, ``atol``, ``steps_per_period``, ``max_step``, ``event_tol``.
    state0 : ndarray, shape (n,) or None
        The initial state at ``tau = 0`` the run started from (None: not recorded).
    periods : int or None
        Forcing periods asked for after the transient (``len(strobe) - 1`` when the run
        reached its end; None: not recorded).
    transient : int
        Forcing periods integrated first and discarded.
    dense_per_period : int
        Dense samples kept per forcing period (0: none).
    """

    params: object
    model: str
    strobe: np.ndarray
    t_strobe: np.ndarray
    impacts: np.ndarray
    events: dict
    dense: np.ndarray | None
    t_dense: np.ndarray | None
    status: Status
    reason: str
    counters: dict
    final_state: np.ndarray
    solver: dict = field(default_factory=dict)
    state0: np.ndarray | None = None
    periods: int | None = None
    transient: int = 0
    dense_per_period: int = 0
    #: the model's contact declaration (:class:`vibimpact.models.contact.Contact`; None: the
    #: model declares none), to rebuild the impact records of joined runs
    contact: object = field(default=None, repr=False, compare=False)

    @property
    def ok(self):
        """True when the run reached its end."""
        return self.status is Status.OK

    def to_dataset(self, command: str | None = None, *,
                   attrs: Mapping[str, Any] | None = None) -> xr.Dataset:
        """The run as an ``xarray.Dataset``: the dataset ``vibimpact simulate -o`` writes.

        The same function makes both (:func:`vibimpact.io.run_to_dataset`), so the data
        variables and coordinates of ``run.to_dataset()`` are those of the file that
        ``vibimpact simulate`` writes for the same run, and its global attributes are
        the file's less the command line's own (``command``, ``preset``, the wall time,
        the ``start_*`` provenance of ``--from``) and the CF and provenance attributes
        every writer adds (:func:`vibimpact.io.write_netcdf`).

        Parameters
        ----------
        command : str, optional
            The command line (or call) that made the run, stored as ``command``.
        attrs : dict, optional
            Further global attributes.

        Returns
        -------
        xarray.Dataset
            See :func:`vibimpact.io.run_to_dataset`.

        Examples
        --------
        >>> import vibimpact as vi
        >>> run = vi.simulate(vi.presets.get("fig8").replace(eta=1.25), periods=5)
        >>> ds = run.to_dataset()
        >>> ds["strobe"].shape, ds["state0"].values.tolist()
        ((6, 4), [0.0, 0.0, 0.0, 0.0])
        """
        return run_to_dataset(self, command, attrs=attrs)


def impacts_of(contact, p, events, t0, period):
    """The impact records of an event log: :func:`vibimpact.models.contact.impacts_from_events`
    for a model that declares a contact, none otherwise.

    Parameters
    ----------
    contact : Contact or None
    p : ndarray
        Parameter vector.
    events : dict
        The event log (:attr:`Run.events`).
    t0, period : float
        Start of the recorded window, forcing period.

    Returns
    -------
    ndarray of :data:`IMPACT_DTYPE`
    """
    if contact is None:
        return np.zeros(0, dtype=IMPACT_DTYPE)
    return _contact.impacts_from_events(contact, p, events["t"], events["which"],
                                        events["mode_before"], events["state"], t0, period,
                                        mode_after=events["mode_after"])


def join_runs(runs, period):
    """One run from consecutive runs of whole forcing periods, each started at ``tau = 0``
    where the previous one ended (a transient integrated in chunks).

    Parameters
    ----------
    runs : sequence of Run
        Finished (status OK) runs of the same model and parameters, without transient;
        ``runs[i + 1]`` starts at ``runs[i].final_state``.
    period : float
        Forcing period ``T``: run ``i`` is shifted by the periods of the runs before it.

    Returns
    -------
    Run
        Strobe and dense samples joined (the shared end points once), the event log
        shifted and joined, the contact records rebuilt from the joined log (a contact
        that spans two runs is one record), counters summed.
    """
    runs = list(runs)
    if not runs or any(r.status is not Status.OK for r in runs):
        raise ValueError("runs must be one or more finished runs")
    offs = np.cumsum([0] + [r.strobe.shape[0] - 1 for r in runs[:-1]]) * period
    first = runs[0]
    strobe = np.concatenate([first.strobe] + [r.strobe[1:] for r in runs[1:]])
    events = {k: np.concatenate([r.events[k] for r in runs]) for k in EVENT_DTYPE_FIELDS}
    events["t"] = np.concatenate([r.events["t"] + o for r, o in zip(runs, offs)])
    impacts = impacts_of(first.contact, _vector(first.params), events, 0.0, period)
    dense = t_dense = None
    if first.dense is not None:
        dense = np.concatenate([first.dense] + [r.dense[1:] for r in runs[1:]])
        t_dense = np.concatenate([first.t_dense] + [r.t_dense[1:] + o
                                                    for r, o in zip(runs[1:], offs[1:])])
    counters = {k: sum(r.counters[k] for r in runs) for k in first.counters}
    return Run(params=first.params, model=first.model, strobe=strobe,
               t_strobe=np.arange(strobe.shape[0]) * period, impacts=impacts,
               events=events, dense=dense, t_dense=t_dense, status=Status.OK, reason="",
               counters=counters, final_state=runs[-1].final_state.copy(),
               solver=dict(first.solver), state0=first.state0,
               periods=strobe.shape[0] - 1, transient=first.transient,
               dense_per_period=first.dense_per_period, contact=first.contact)


def _state_names(model, n):
    """The state names a built-in model declares (a user model's run: x0, x1, ...)."""
    from .. import models

    if model in models.names():
        return models.get(model).state_names
    return tuple(f"x{i}" for i in range(n))


def state_text(model, name):
    """What the state ``name`` of ``model`` (a :class:`~vibimpact.models.Model`, or the
    name of a registered one) is, in words: the model's own words
    (:attr:`vibimpact.models.Model.state_text`); None when it has none (never another
    model's words)."""
    from .. import models

    own = getattr(model, "state_text", None)
    if own is None:
        own = models.get(model).state_text if model in models.names() else {}
    return own.get(name)


#: impact record field -> (units, long_name with the model's words,
#: :func:`vibimpact.models.words.file_words`)
_IMPACT_ATTRS = {
    "t_entry": ("1", "time {time} of contact entry"),
    "theta": ("degree", "contact angle at entry ({angle})"),
    "v_impact": ("1", "normal impact speed at entry"),
    "penetration": ("1", "maximum penetration during the contact{unit}"),
    "duration": ("1", "contact duration in {time} (NaN: still in contact at the end)"),
    "t_exit": ("1", "time {time} of contact exit (NaN: still in contact)"),
    "period": ("1", "forcing period of the entry, counted from the end of the transient"),
    "theta_exit": ("degree", "contact angle at exit on the branch of theta (theta + angle "
                   "travelled in contact); NaN: still in contact"),
    "theta_min": ("degree", "smallest contact angle reached during the contact, on the "
                  "branch of theta"),
    "theta_max": ("degree", "largest contact angle reached during the contact, on the "
                  "branch of theta"),
}


def _time(words):
    """The time coordinate's words: ``"time"``, or ``"time NAME"`` for a model that names
    its time (``"time tau"``)."""
    return "time" if words["time"] == "time" else f"time {words['time']}"


def _vector(params):
    """A run's parameters as the vector the kernel read."""
    return params.as_array() if hasattr(params, "as_array") else np.asarray(params, float)


def _attr_value(value):
    """A value NetCDF can store as an attribute: str, int or float."""
    if value is None:
        return ""
    if isinstance(value, (bool, np.bool_)):
        return int(value)
    if isinstance(value, numbers.Integral):
        return int(value)
    if isinstance(value, numbers.Real):
        return float(value)
    if isinstance(value, str):
        return value
    if hasattr(value, "value") and isinstance(value.value, str):  # an Enum such as Status
        return value.value
    return str(value)


def _params_dict(params):
    if hasattr(params, "as_dict"):
        return params.as_dict()
    vec = np.atleast_1d(np.asarray(params, dtype=np.float64))
    return {f"p{i}": float(v) for i, v in enumerate(vec)}


def run_to_dataset(run: Run, command: str | None = None, *, state0: ArrayLike | None = None,
                   attrs: Mapping[str, Any] | None = None) -> xr.Dataset:
    """A :class:`~vibimpact.Run` as an ``xarray.Dataset``.

    Parameters
    ----------
    run : Run
        The result of :func:`vibimpact.simulate`.
    command : str, optional
        The command line (or call) that made the run, stored as the ``command`` attribute.
    state0 : array_like, optional
        The initial state at ``tau = 0``, stored as the variable ``state0``; the one the
        run records (:attr:`Run.state0 <vibimpact.Run.state0>`) by default.
    attrs : dict, optional
        Further global attributes (values converted to str, int or float).

    Returns
    -------
    xarray.Dataset
        Variables ``strobe`` (``sample``, ``state``) with coordinate ``t_strobe``;
        ``impact_<field>`` on dimension ``impact`` for each field of
        :data:`vibimpact.core.run.IMPACT_DTYPE`; ``trajectory`` (``time``, ``state``) when the
        run kept dense output; ``state0`` when the initial state is known.  Global
        attributes: ``model``, ``status``, ``reason``, ``param_<name>``,
        ``solver_<key>``, ``counter_<name>``, ``periods``, ``transient``, ``dense``,
        ``vibimpact_version``, ``command``.  :meth:`vibimpact.Run.to_dataset` and
        ``vibimpact simulate -o`` both make it here (also as
        :func:`vibimpact.io.run_to_dataset`).

    Examples
    --------
    >>> import vibimpact as vi
    >>> from vibimpact.io import run_to_dataset
    >>> run = vi.simulate(vi.presets.get("fig8").replace(eta=1.25), periods=5, transient=5)
    >>> run_to_dataset(run).strobe.shape
    (6, 4)
    """
    import xarray as xr

    from .. import __version__

    strobe = np.asarray(run.strobe, dtype=np.float64)
    n = strobe.shape[1]
    names = _state_names(run.model, n)
    if len(names) != n:
        names = tuple(f"x{i}" for i in range(n))
    from .. import models
    from ..models.words import file_words

    words = file_words(models.get(run.model) if run.model in models.names() else None)
    state_coord = ("state", list(names), {"long_name": "state variable"})
    data_vars: dict[str, tuple[Any, ...]] = {
        "strobe": (("sample", "state"), strobe,
                   {"units": "1", "long_name": "stroboscopic (Poincare) samples at "
                    "{time}_k = 2 pi k / {freq}, after the transient".format(**words)}),
    }
    coords: dict[str, tuple[Any, ...]] = {
        "state": state_coord,
        "t_strobe": ("sample", np.asarray(run.t_strobe, dtype=np.float64),
                     {"units": "1", "long_name": f"{_time(words)} of the stroboscopic "
                                                 "samples"}),
    }
    for var in run.impacts.dtype.names or ():
        units, long_name = _IMPACT_ATTRS.get(var, ("1", var))
        long_name = long_name.format(**words)
        values = np.asarray(run.impacts[var])
        if values.dtype == np.int64:  # as written: CF-1.8 has no 64-bit integers
            values = values.astype(np.int32)
        data_vars[f"impact_{var}"] = ("impact", values,
                                        {"units": units, "long_name": long_name})
    if run.dense is not None:
        data_vars["trajectory"] = (("time", "state"), np.asarray(run.dense, np.float64),
                                   {"units": "1", "long_name": "evenly sampled trajectory"})
        coords["time"] = ("time", np.asarray(run.t_dense, dtype=np.float64),
                          {"units": "1", "long_name": _time(words)})
    state0 = run.state0 if state0 is None else state0
    if state0 is not None:
        data_vars["state0"] = ("state", np.asarray(state0, dtype=np.float64).reshape(n),
                               {"units": "1", "long_name": f"initial state at {_time(words)} = 0"})
    ds = xr.Dataset(data_vars, coords=coords)
    for name in names:
        text = state_text(run.model, name)
        if text is not None:
            ds.attrs[f"state_{name}"] = text

    glob = {"title": f"vibimpact simulation ({run.model} model)", "model": run.model,
            "status": run.status, "reason": run.reason,
            "vibimpact_version": __version__, "command": command}
    glob.update({f"param_{k}": v for k, v in _params_dict(run.params).items()})
    glob.update({f"solver_{k}": v for k, v in (run.solver or {}).items()})
    glob.update({f"counter_{k}": v for k, v in (run.counters or {}).items()})
    if run.periods is not None:
        glob.update(periods=run.periods, transient=run.transient,
                    dense=run.dense_per_period)
    glob.update(attrs or {})
    ds.attrs.update({k: _attr_value(v) for k, v in glob.items()})
    return ds
