"""The type of every transition of a sweep's interval map, refined below the sweep step.

A response curve says *where* the motion changes; :func:`transition_types` says *how*, at
each boundary of :func:`vibimpact.intervals` (in sweep order, for each direction), by
the short name of a :class:`~vibimpact.base.bifurcation_kinds.BifurcationKind`:

===================  ==================================================================
``period doubling``  a Floquet multiplier of the periodic orbit leaves through -1 (or
                     the period-2n orbit collapses onto period n): a cascade to chaos
                     may follow
``fold``             a multiplier through +1: the orbit vanishes at a turning point and
                     the motion jumps, with hysteresis between up and down sweeps
``Neimark-Sacker``   a complex pair leaves the unit circle: quasi-periodic motion
``grazing``          the orbit's contacts change (the minimum gap reaches 0): impactless
                     <-> impacting, a new contact point (its impacts per period change
                     at the same period), a permanent contact lifting off
``stick-slip``       the orbit's friction events change
``intermittency``    chaos ends where the periodic orbit is born in a fold (type-I
                     intermittency before it)
``crisis``           a chaotic (or quasi-periodic) attractor appears, disappears or
                     changes size with no local bifurcation of a periodic orbit
``coexistence``      the from-side attractor persists across the step but the sweep
                     moved to another, coexisting one (no bifurcation in the step)
``none``             the same orbit on both sides: only the label changed (loaded arcs
                     regrouped, or a slowly converging orbit read as 'long period')
===================  ==================================================================

Several events inside one sweep step are joined in sweep order ("grazing + period
doubling").  A fold at a grazing (the stiff Hertz contact makes the orbit vanish a few
1e-5 in eta after it touches) reads "grazing + fold".  When the sweep leaves a stable
orbit at a grid point and the orbit ends by an event less than half a step beyond it
(its basin shrinks next to a fold), that event is reported, outside the step.

How: the periodic orbit on the *from* side (sweep order) is found by shooting from the
sweep's ``final_state`` and followed by Newton continuation towards the other grid point
(:func:`vibimpact.analysis.locate_bifurcation`); the first value where it stops
persisting is bisected to ``tol`` and its multipliers name the type.  When the from side
is not periodic, the periodic orbit of the *to* side is followed backwards (a fold there:
intermittency; it persists stably into the chaotic side: crisis).  Between two
non-periodic sides the boundary is bisected by re-running the sweep's own point analysis
(:func:`vibimpact.sweeps.analyse_point`) from the from-side state.

References: Kuznetsov (2004) ch. 4; Seydel (2010) ch. 7; Leine & Nijmeijer (2004) ch. 7;
di Bernardo et al. (2008) ch. 8 (grazing); Grebogi, Ott & Yorke (1983), "Crises, sudden
changes in chaotic attractors, and transient chaos", Physica D 7, 181; Pomeau & Manneville
(1980), "Intermittent transition to turbulence in dissipative dynamical systems", Commun.
Math. Phys. 74, 189.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from ..analysis.classify import Label
from ..base.bifurcation_kinds import BifurcationKind
from ..analysis.continuation import locate_bifurcation
from ..analysis.period import detect_period
from ..analysis.shooting import shoot_periodic_orbit
from .. import models
from ..io.recorded import model_name
from ..core.run import Status
from ..base import _json, _validate as _v
from ..core.simulation import simulate
from ..core.solver import SolverSettings
from ..core.system import System
from .dataset import label_text, sweep_params
from ..points.point import REGIME_CODES, SweepSettings, analyse_point

if TYPE_CHECKING:  # names of the annotations only
    from collections.abc import Callable

    import xarray as xr

    from ..analysis.bifurcation import Bifurcation
    from ..models.params import DuffingParams, Params

__all__ = ["transition_types", "format_transitions"]

_PERIODIC = REGIME_CODES[Label.PERIODIC]
_QUASI = REGIME_CODES[Label.QUASIPERIODIC]
_CHAOTIC = REGIME_CODES[Label.CHAOTIC]
_UNSETTLED = REGIME_CODES[Label.UNSETTLED]
_SHOOT: dict[str, Any] = dict(tol=1e-9, max_iter=12)
_SEEDED = {False: "", True: " (a sweep block starts there from a seeded state, not from "
                            "the previous point)"}


def _params_of(ds, p):
    if p is not None:
        swept = model_name(ds.attrs, "ds")
        model = models.of_params(p)
        if model is None or model.name != swept:
            want = models.get(swept).param_set if swept in models.names() else None
            raise ValueError(f"p must be the parameter set of the swept model ({swept}: "
                             f"{getattr(want, '__name__', '?')}), got {type(p).__name__}")
        return p
    try:
        return sweep_params(ds)
    except ValueError as exc:
        raise ValueError(f"p: not given and {exc}") from None


def _settings_of(ds):
    from ..engine.plan import settings_from_attrs

    try:
        return settings_from_attrs(_json.loads(ds.attrs["settings"], "settings"))
    except (KeyError, TypeError, ValueError):
        return SweepSettings()


def _seeded_positions(ds, n):
    """Sweep-order positions where a block started from a seeded state (not from the
    previous point): a change of attractor there need not be a bifurcation."""
    from ..engine.plan import block_starts

    try:
        blocks = int(ds.attrs.get("blocks", 1))
        cont = int(ds.attrs.get("continuation", 1))
    except (TypeError, ValueError):
        return set()
    if not cont:
        return set(range(n))
    return set(block_starts(n, blocks)[1:-1])


class _Point:
    """One grid point of a sweep direction."""

    def __init__(self, sub, i, direction, seeded=False):
        self.direction = direction
        self.index = int(i)
        self.seeded = seeded
        self.eta = float(sub["eta"].values[i])
        self.label = str(sub["label"].values[i])
        self.regime = int(sub["regime"].values[i])
        self.period = int(sub["period"].values[i])
        self.contact = int(sub["contact"].values[i]) if "contact" in sub else -1
        self.state = np.asarray(sub["final_state"].values[i], dtype=np.float64)

    @property
    def key(self):
        return (self.regime, self.period, self.contact)


def _attractor(p, pt, hints, periods=400):
    """The stable periodic orbit the motion at ``pt`` converges to, or None.

    The sweep's own period is not trusted near a bifurcation (a slowly decaying flip
    transient passes its period-2 test): the motion is re-run from the point's
    ``final_state`` at tight tolerances, its period detected at 1e-7, and the orbit shot.
    Without a period, the sweep's and neighbours' periods are shot and accepted when the
    motion visibly converges to the orbit (a slowly converging orbit near a bifurcation,
    labelled 'long period', 'quasi-periodic' or 'unsettled' by the sweep).
    """
    if pt.regime not in (_PERIODIC, _QUASI, _CHAOTIC, _UNSETTLED) or \
            not np.all(np.isfinite(pt.state)):
        return None
    q = p.replace(eta=pt.eta)
    run = simulate(q, periods=periods, state0=pt.state,
                   solver=SolverSettings(rtol=1e-10, atol=1e-12))
    if run.status is not Status.OK:
        return None
    st = run.strobe
    n = detect_period(st[-193:], tol=1e-7, max_period=64)
    cands = [n] if n else []
    if pt.regime != _CHAOTIC:
        cands += [pt.period] + list(hints) + [2 * h for h in hints] + [1, 2]
    tried = set()
    for m in cands:
        if not m or m in tried:
            continue
        tried.add(m)
        orb = shoot_periodic_orbit(System(q), st[-1], m, **_SHOOT)
        if not (orb.converged and orb.minimal_period == m and orb.abs_max < 1.0):
            continue
        scale = max(1.0, float(np.abs(orb.cycle).max()))
        d_end = float(np.abs(orb.cycle - st[-1]).max(axis=1).min())
        if m == n and d_end <= 1e-5 * scale:
            return orb
        d_mid = float(np.abs(orb.cycle - st[st.shape[0] // 2]).max(axis=1).min())
        if d_end <= 1e-2 * scale and d_end < 0.5 * d_mid:  # converging to it
            return orb
    return None


def _same_orbit(o1, o2):
    """Two shot orbits are one (same minimal period, same points to 1e-6)."""
    if o1 is None or o2 is None or o1.minimal_period != o2.minimal_period:
        return False
    scale = max(1.0, float(np.abs(o1.cycle).max()))
    return float(np.abs(o1.cycle - o2.state).max(axis=1).min()) <= 1e-6 * scale


def _point_label(p, eta, state, settings):
    res = analyse_point(p.replace(eta=float(eta)), state, settings).as_dict()
    lab = label_text(res["regime"], res["period"], res["impacts_per_period"], res["arcs"],
                      res["contact"])
    return lab, (int(res["regime"]), int(res["period"]), int(res["contact"])), res


def _bisect_by_simulation(p, a, b, settings, tol):
    """Bracket where the from-side label stops being reproduced from the from side."""
    use_key = a.key != b.key
    lo, hi, x = a.eta, b.eta, a.state
    while abs(hi - lo) > tol:
        mid = 0.5 * (lo + hi)
        lab, key, res = _point_label(p, mid, x, settings)
        same = key == a.key if use_key else lab == a.label
        if same:
            lo = mid
            fs = res["final_state"]
            if np.all(np.isfinite(fs)):
                x = fs
        else:
            hi = mid
    return lo, hi


def _coexists(p, eta, orb, other_state, periods=200):
    """Whether the motion started from ``other_state`` at ``eta`` stays away from ``orb``
    (two attractors at one eta: hysteresis)."""
    if not np.all(np.isfinite(other_state)):
        return False
    run = simulate(p.replace(eta=float(eta)), periods=1, transient=periods - 1,
                   state0=other_state, solver=SolverSettings(rtol=1e-9))
    if run.status is not Status.OK:
        return False
    scale = max(1.0, float(np.abs(orb.cycle).max()))
    return float(np.abs(orb.cycle - run.final_state).max(axis=1).min()) > 1e-3 * scale


def _mu_text(orb):
    mu = orb.multipliers[0]
    return mu, f"{mu.real:+.4f}{mu.imag:+.4f}j (|mu| {abs(mu):.4f})"


def _reproduces(p, a, eta, settings):
    """Whether the from-side motion, continued from ``a``'s state, is still there at
    ``eta`` (the sweep's point analysis gives the same kind of motion)."""
    lab, key, _ = _point_label(p, eta, a.state, settings)
    return key == a.key if key[0] != _PERIODIC else lab == a.label


def _follow(p, orb, start, stop, width, max_events=4):
    """Events met by a stable orbit followed from ``start`` to ``stop``: a list of
    :class:`Bifurcation`; after a grazing or stick-slip change the orbit (new contacts)
    is followed on, so a step may show e.g. grazing then period doubling.  The last entry
    has kind NONE when the orbit reaches ``stop``."""
    events: list[Bifurcation] = []
    x, n, lo = orb.state, orb.n, start
    while len(events) < max_events:
        system = System(p)
        bif = locate_bifurcation(system, x, n, param=system.model.frequency_name, start=lo,
                                 stop=stop, tol=width, shoot_kw=_SHOOT)
        events.append(bif)
        nxt = bif.beyond
        if bif.kind not in (BifurcationKind.GRAZING, BifurcationKind.STICK_SLIP) or \
                nxt is None or not nxt.stable \
                or nxt.minimal_period != n or bif.bracket[1] == stop:
            break
        x, lo = nxt.state, bif.bracket[1]
    return events


def _kind_text(events, from_chaos=False):
    """The chain of event kinds, in sweep order, as one string."""
    names: list[BifurcationKind] = []
    for i, e in enumerate(events):
        k = e.kind
        if k == BifurcationKind.FOLD and from_chaos and i == 0:
            k = BifurcationKind.INTERMITTENCY
        if e.kind == BifurcationKind.FOLD and e.at_grazing and \
                (not names or names[-1] != BifurcationKind.GRAZING):
            names.append(BifurcationKind.GRAZING)
        names.append(k)
    return " + ".join(names)


def _event_text(events):
    return "; then ".join(f"{e.kind} at eta = {e.value:.5f}: {e.detail}" for e in events)


def _classify(p, a, b, settings, tol, refine, cache):
    """Type, refined bracket and evidence of one boundary from point a to point b."""
    width = tol if refine else abs(b.eta - a.eta) * 1.0000001
    out = dict(type=BifurcationKind.UNRESOLVED, lo=min(a.eta, b.eta), hi=max(a.eta, b.eta),
               mu=complex(np.nan, np.nan), gap=np.nan, evidence="", method="",
               hysteresis="")

    def attractor(pt, other):
        k = (pt.direction, pt.index)
        if k not in cache:
            cache[k] = _attractor(p, pt, [other.period])
        return cache[k]

    def by_simulation():
        if refine:
            out["lo"], out["hi"] = sorted(_bisect_by_simulation(p, a, b, settings, tol))
            out["method"] += " + simulation" if out["method"] else "simulation"

    orb_a = attractor(a, b)
    orb_b = attractor(b, a)
    if orb_a is not None:
        events = _follow(p, orb_a, a.eta, b.eta, width)
        real = [e for e in events if e.kind != BifurcationKind.NONE]
        first, last = events[0], events[-1]
        out.update(method="shooting, from side", gap=first.gap)
        out["mu"], txt = _mu_text(first.orbit)
        if real:
            out.update(type=_kind_text(real), lo=min(first.bracket),
                       hi=max(first.bracket),
                       evidence=f"P{orb_a.n}: {_event_text(real)}")
        if last.kind == BifurcationKind.FOLD:
            eta_in = last.bracket[0]
            co = _coexists(p, eta_in, last.orbit, b.state)
            out["hysteresis"] = (f"coexists with the to-side motion at eta = "
                                 f"{eta_in:.5f}" if co else "no coexistence found")
            if b.regime == _CHAOTIC:
                out["evidence"] += "; jump to chaos"
        if last.kind != BifurcationKind.NONE:
            return out
        # the orbit persists, stable, up to b
        if _same_orbit(last.orbit, orb_b):
            if not real:
                misread = [pt.eta for pt in (a, b) if pt.regime != _PERIODIC or
                           pt.period != orb_b.minimal_period]
                why = (f"the sweep misread the slowly converging orbit at eta = "
                       f"{', '.join(f'{e:.4f}' for e in misread)}" if misread
                       else "loaded arcs regrouped")
                out.update(type=BifurcationKind.NONE,
                           evidence=f"P{orb_a.n} persists, stable, same contacts ({txt} "
                                    f"at eta = {b.eta:.4f}), and is the to-side motion: "
                                    f"the label changed only ({why})")
            return out
        # does the orbit end just beyond b?  Then the sweep left it early, where its
        # basin had shrunk (next to a fold), and the event is that fold.
        beyond = b.eta + 0.5 * (b.eta - a.eta)
        more = _follow(p, last.orbit, b.eta, beyond, width)
        late = [e for e in more if e.kind != BifurcationKind.NONE]
        if late and not real and not b.seeded:
            e = late[0]
            out.update(type=_kind_text(late), lo=min(e.bracket), hi=max(e.bracket),
                       mu=e.orbit.multipliers[0], gap=e.gap,
                       evidence=f"P{orb_a.n} persists, stable, to eta = {b.eta:.4f} but the "
                                f"sweep left it there; it ends just beyond, outside the "
                                f"step: {_event_text(late)}",
                       hysteresis="coexisting attractors")
            return out
        out.update(type=" + ".join(([out["type"]] if real else []) +
                                   [BifurcationKind.COEXISTENCE]),
                   hysteresis="coexisting attractors",
                   evidence=(out["evidence"] + "; " if real else "") +
                   f"P{orb_a.n} persists, stable, to eta = {b.eta:.4f}; the sweep moved to "
                   f"another attractor there" + _SEEDED[b.seeded])
        return out
    if orb_b is not None:
        events = _follow(p, orb_b, b.eta, a.eta, width)
        real = [e for e in events if e.kind != BifurcationKind.NONE]
        last = events[-1]
        out.update(method="shooting, to side backwards", gap=last.gap)
        out["mu"], txt = _mu_text(last.orbit)
        if last.kind == BifurcationKind.NONE:
            note = (f"; on the way {_event_text(real[::-1])}" if real else "")
            if _reproduces(p, a, b.eta, settings):
                out.update(type=BifurcationKind.COEXISTENCE,
                           hysteresis="coexisting attractors",
                           evidence=f"P{orb_b.n} of the to side exists, stable, back to "
                                    f"eta = {a.eta:.4f} ({txt}), and the from-side motion "
                                    f"still exists at eta = {b.eta:.4f}{note}" +
                                    _SEEDED[b.seeded])
                return out
            out.update(type=BifurcationKind.CRISIS, hysteresis="coexisting attractors",
                       evidence=f"P{orb_b.n} of the to side exists, stable, back to eta = "
                                f"{a.eta:.4f} ({txt}): the from-side attractor ends without "
                                f"a local bifurcation (boundary crisis){note}")
            by_simulation()
            return out
        fwd = real[::-1]
        out.update(type=_kind_text(fwd, from_chaos=a.regime == _CHAOTIC),
                   lo=min(last.bracket), hi=max(last.bracket),
                   evidence=f"P{orb_b.n} of the to side, followed back; in sweep order: "
                            f"{_event_text(fwd)}")
        return out
    # neither side has a stable periodic orbit
    by_simulation()
    contact = {a.contact, b.contact}
    if 0 in contact and len(contact) > 1:
        out.update(type=BifurcationKind.GRAZING,
                   evidence=f"contact flag {a.contact} -> {b.contact} between "
                            "non-periodic motions")
    else:
        what = "quasi-periodic" if _QUASI in (a.regime, b.regime) else "chaotic"
        out.update(type=BifurcationKind.CRISIS,
                   evidence=f"no stable periodic orbit on either side; the {what} "
                            "attractor changes")
    return out


@_v.checks_flags
def transition_types(ds: xr.Dataset, p: Params | DuffingParams | System | None = None, *,
                     refine: bool = True, tol: float = 1e-4, direction: str | None = None,
                     settings: SweepSettings | None = None,
                     progress: bool | str | Callable[[int], object] = False) -> xr.Dataset:
    """The type of every boundary of the sweep's interval map, refined by bisection.

    Parameters
    ----------
    ds : xarray.Dataset
        From :func:`vibimpact.sweep`, with ``label``, ``regime``, ``period`` and
        ``final_state`` (any analyses; any direction).
    p : Params, optional
        The sweep's parameters (read from ``ds.attrs["params"]`` by default).
    refine : bool
        Bisect each boundary in ``eta`` to ``tol``; False keeps the grid points and only
        names the type.
    tol : float
        Width of the refined bracket in ``eta``.
    direction : {"up", "down"}, optional
        Of a ``direction="both"`` sweep: only this one.
    settings : SweepSettings, optional
        Point analysis for the simulation bisections (the sweep's, from its attributes,
        by default).
    progress : bool, str or callable
        A progress bar on stderr, named "transitions" (True) or by the text given; a
        callable is called as ``progress(1)`` with every boundary typed instead.

    Returns
    -------
    xarray.Dataset
        Dim ``boundary``, in sweep order per direction: ``direction``, ``eta_from`` and
        ``eta_to`` (the grid points on both sides), ``eta_lo``, ``eta_hi`` (the refined
        bracket of the first event), ``eta`` (its midpoint), ``from_label``,
        ``to_label``, ``type`` (the short name of a
        :class:`~vibimpact.base.bifurcation_kinds.BifurcationKind`, or several joined by
        " + " when one sweep step holds several events, in sweep order: e.g. "grazing +
        period doubling", :func:`~vibimpact.base.bifurcation_kinds.kinds_in` splits it; the
        evidence gives each event's eta), ``mu_real``, ``mu_imag`` (the
        largest Floquet multiplier of the followed orbit at the bracket's persisting
        end; NaN when no orbit was followed), ``gap`` (its smallest ``|penetration|`` at
        an extremum of the penetration, :func:`vibimpact.analysis.bifurcation.grazing_gap`;
        ``|R - 1|`` for the built-in rotor: 0 at grazing), ``method``, ``evidence`` and
        ``hysteresis`` (text).

    Raises
    ------
    ValueError
        Naming the argument.

    Notes
    -----
    The sweep's labels are not trusted near a bifurcation: each side's motion is re-run
    400 periods at rtol 1e-10 from the point's ``final_state``, its period detected at
    1e-7 and its orbit shot; an orbit counts as the side's attractor when the motion
    converges to it.  Two orbits are "the same" when their points agree to 1e-6.  A
    fold whose largest multiplier at the bracket is not real positive is reported as
    such in the evidence ("non-smooth"), and one within ``10 tol`` of a grazing in gap
    as "grazing + fold".  Its cost on the presets is timed in ``reports/transitions.md``
    (each preset's section, "typing").

    Examples
    --------
    >>> import numpy as np, vibimpact as vi
    >>> p = vi.presets.get("fig8").replace(B=0.1, Ec=0.1)
    >>> ds = vi.sweep(p, [0.945, 0.95, 0.955, 0.96],
    ...               continuation=vi.Continuation(blocks=1))
    >>> tt = vi.transition_types(ds)
    >>> str(tt["type"].values[0])
    'grazing'
    """
    import xarray as xr

    if "label" not in ds or "final_state" not in ds or "eta" not in ds.dims:
        raise ValueError("ds must be a sweep dataset (variables label, final_state; dim "
                         "eta)")
    p = _params_of(ds, p)
    tol = _v.positive("tol", tol)
    settings = _settings_of(ds) if settings is None else settings
    if not isinstance(settings, SweepSettings):
        raise ValueError("settings must be a SweepSettings")
    if "direction" in ds.dims:
        dirs = list(ds["direction"].values)
        if direction is not None:
            if direction not in dirs:
                raise ValueError(f"direction must be one of {dirs}, got {direction!r}")
            dirs = [direction]
        subs = [(str(d), ds.sel(direction=d)) for d in dirs]
    else:
        d = ds.attrs.get("sweep_direction", ds.attrs.get("direction", "up"))
        if direction is not None and direction != d:
            raise ValueError(f"direction must be {d!r} for this dataset, got {direction!r}")
        subs = [(str(d), ds)]
    jobs = []
    for d, sub in subs:
        eta = sub["eta"].values
        order = np.arange(eta.size) if d != "down" else np.arange(eta.size)[::-1]
        lab = sub["label"].values
        seeds = _seeded_positions(ds, eta.size)
        for k in range(order.size - 1):
            i, j = order[k], order[k + 1]
            if lab[i] != lab[j]:
                jobs.append((d, _Point(sub, i, d), _Point(sub, j, d, k + 1 in seeds)))
    from ..engine.progress import callback

    rows = []
    cache: dict = {}
    with callback(progress, len(jobs), "transitions", unit="boundary") as report:
        for d, a, b in jobs:
            r = _classify(p, a, b, settings, tol, refine, cache)
            rows.append((d, a, b, r))
            report(1)

    def col(f, dtype=None):
        return np.array([f(*r) for r in rows], dtype=dtype)

    dim = "boundary"
    out = xr.Dataset(
        {"direction": (dim, col(lambda d, a, b, r: d, object)),
         "eta_from": (dim, col(lambda d, a, b, r: a.eta, float),
                      dict(long_name="last grid point of the from interval")),
         "eta_to": (dim, col(lambda d, a, b, r: b.eta, float),
                    dict(long_name="first grid point of the to interval")),
         "eta_lo": (dim, col(lambda d, a, b, r: r["lo"], float),
                    dict(long_name="refined bracket, lower end")),
         "eta_hi": (dim, col(lambda d, a, b, r: r["hi"], float),
                    dict(long_name="refined bracket, upper end")),
         "eta": (dim, col(lambda d, a, b, r: 0.5 * (r["lo"] + r["hi"]), float),
                 dict(long_name="refined transition eta")),
         "from_label": (dim, col(lambda d, a, b, r: a.label, object)),
         "to_label": (dim, col(lambda d, a, b, r: b.label, object)),
         "type": (dim, col(lambda d, a, b, r: str(r["type"]), object)),
         "mu_real": (dim, col(lambda d, a, b, r: r["mu"].real, float),
                     dict(long_name="largest Floquet multiplier, real part")),
         "mu_imag": (dim, col(lambda d, a, b, r: r["mu"].imag, float),
                     dict(long_name="largest Floquet multiplier, imaginary part")),
         "gap": (dim, col(lambda d, a, b, r: r["gap"], float),
                 dict(long_name="smallest |R - 1| at an extremum of R of the followed "
                                "orbit (0: grazing)")),
         "method": (dim, col(lambda d, a, b, r: r["method"], object)),
         "evidence": (dim, col(lambda d, a, b, r: r["evidence"], object)),
         "hysteresis": (dim, col(lambda d, a, b, r: r["hysteresis"], object))},
        attrs=dict(title="vibimpact transition types", tol=float(tol),
                   refine=int(bool(refine)), source=ds.attrs.get("source", "")))
    return out


def format_transitions(tt, markdown=True):
    """The transition table as Markdown (or aligned text)."""
    head = ("direction", "eta grid", "eta refined", "from", "to", "type", "|mu|",
            "evidence")
    rows = []
    for k in range(tt.sizes.get("boundary", 0)):
        mu = complex(tt["mu_real"].values[k], tt["mu_imag"].values[k])
        mtxt = "" if not np.isfinite(abs(mu)) else f"{abs(mu):.3f}"
        lo, hi = float(tt["eta_lo"].values[k]), float(tt["eta_hi"].values[k])
        ev = str(tt["evidence"].values[k])
        hy = str(tt["hysteresis"].values[k])
        if hy:
            ev = f"{ev}; {hy}"
        rows.append((str(tt["direction"].values[k]),
                     f"{float(tt['eta_from'].values[k]):.3f}->"
                     f"{float(tt['eta_to'].values[k]):.3f}",
                     f"{0.5 * (lo + hi):.5f} ± {0.5 * (hi - lo):.1e}",
                     str(tt["from_label"].values[k]), str(tt["to_label"].values[k]),
                     str(tt["type"].values[k]), mtxt, ev))
    if markdown:
        lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
        lines += ["| " + " | ".join(r) + " |" for r in rows]
        return "\n".join(lines)
    w = [max(len(h), *(len(r[i]) for r in rows)) if rows else len(h)
         for i, h in enumerate(head[:-1])]
    lines = ["  ".join(h.ljust(w[i]) for i, h in enumerate(head[:-1]))]
    lines += ["  ".join(c.ljust(w[i]) for i, c in enumerate(r[:-1])) for r in rows]
    return "\n".join(lines)
