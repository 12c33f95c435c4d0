"""Types of the transitions of a sweep, and the Floquet analysis of sweeps (issue 8).

Every located transition is checked against plain simulation on both sides of the
refined value, which needs neither the shooting nor the multipliers.
"""
import json

import numpy as np
import pytest

import vibimpact as vi
from vibimpact.analysis import detect_period
from vibimpact.sweeps import SweepSettings
from vibimpact.base.bifurcation_kinds import BifurcationKind, kinds_in
from vibimpact.sweeps.transitions import format_transitions, transition_types
from conftest import continued_state, preset

#: fig8 at B = Ec = 0.1, the configuration the expected transitions were measured at
FIG8 = preset("fig8")


def _contacts(eta, state, periods=50):
    """Contact entries of the attractor reached from ``state`` at ``eta``."""
    run = vi.simulate(FIG8.replace(eta=eta), periods=periods, transient=400, state0=state,
                      solver=vi.SolverSettings(rtol=1e-10))
    return run.impacts.size


def test_grazing_of_the_low_branch_is_found_and_confirmed_by_simulation():
    """Sweeping up from rest, the impactless period-1 orbit first touches the retainer
    (grazing); simulation 2e-4 below the refined eta shows no contact, 2e-4 above it
    contacts."""
    ds = vi.sweep(FIG8, np.array([0.945, 0.95, 0.955, 0.96]),
                  continuation=vi.Continuation(blocks=1))
    tt = transition_types(ds, tol=1e-4)
    assert tt.sizes["boundary"] == 1
    assert str(tt["type"].values[0]) == "grazing"
    eta = float(tt["eta"].values[0])
    assert 0.95 < eta < 0.955 and tt["eta_hi"].values[0] - tt["eta_lo"].values[0] <= 1e-4
    x = ds["final_state"].values[1]
    assert _contacts(eta - 2e-4, x) == 0
    assert _contacts(eta + 2e-4, x) > 0
    assert float(tt["gap"].values[0]) < 1e-3  # the orbit's closest approach is ~0


def test_period_doubling_after_a_second_contact_is_found():
    """Between eta = 0.970 and 0.975 the period-1 orbit first gains a contact (grazing),
    then doubles its period; plain simulation (detect_period after 3000 periods) sees
    period 1 just below the located doubling and period 2 just above it."""
    ds = vi.sweep(FIG8, np.array([0.965, 0.97, 0.975]),
                  continuation=vi.Continuation(blocks=1))
    tt = transition_types(ds, tol=1e-4)
    assert str(tt["type"].values[0]) == "grazing + period doubling"
    ev = str(tt["evidence"].values[0])
    eta_pd = float(ev.split("period doubling at eta = ")[1].split(":")[0])
    assert 0.97 < eta_pd < 0.975
    x = ds["final_state"].values[1]
    periods = []
    for eta in (eta_pd - 3e-4, eta_pd + 3e-4):
        run = vi.simulate(FIG8.replace(eta=eta), periods=64, transient=3000, state0=x,
                          solver=vi.SolverSettings(rtol=1e-10))
        periods.append(detect_period(run.strobe, tol=1e-6))
    assert periods == [1, 2]


def test_fold_at_grazing_with_hysteresis_on_the_down_sweep():
    """Sweeping down on the impactless low branch, the orbit reaches the retainer and
    vanishes (fold at grazing, eta ~ 1.0575): the motion jumps to the impacting branch,
    which coexists with the low orbit just above the fold (hysteresis)."""
    x = vi.simulate(FIG8.replace(eta=1.3), periods=1, transient=300).final_state
    ds = vi.sweep(FIG8, np.array([1.055, 1.06, 1.065]), direction="down", state0=x,
                  continuation=vi.Continuation(blocks=1))
    tt = transition_types(ds, tol=1e-4)
    assert str(tt["type"].values[0]) == "grazing + fold"
    assert 1.055 < float(tt["eta"].values[0]) < 1.06
    assert "coexists" in str(tt["hysteresis"].values[0])
    # independent: just above the fold the low orbit and the impacting motion coexist
    eta = float(tt["eta_hi"].values[0]) + 5e-4
    assert _contacts(eta, ds["final_state"].values[1]) == 0  # from the low branch
    assert _contacts(eta, ds["final_state"].values[0]) > 0  # from the jumped-to motion


def _impacts_per_period(eta, state, periods=20):
    """Impacts per forcing period of the attractor reached from ``state`` at ``eta``."""
    return _contacts(eta, state, periods) / periods


def test_a_new_impact_at_the_same_period_is_typed_grazing():
    """Hypothesis: on fig8's impacting P1 branch (reached by continuation) the orbit
    gains a third impact per period between eta = 1.19 and 1.193 while staying period 1
    and stable; the transition is typed grazing (one BifurcationKind, no multiplier
    event), and plain simulation 2e-4 on either side of its refined bracket sees 2 and
    3 impacts per period."""
    x0 = continued_state("fig8", 1.18)
    ds = vi.sweep(FIG8, np.array([1.18, 1.19, 1.193]), state0=x0,
                  continuation=vi.Continuation(blocks=1))
    assert list(ds["period"].values) == [1, 1, 1]
    assert list(ds["impacts_per_period"].values) == [2, 2, 3]
    tt = transition_types(ds, tol=1e-4)
    assert tt.sizes["boundary"] == 1
    assert kinds_in(tt["type"].values[0]) == [BifurcationKind.GRAZING]
    lo, hi = float(tt["eta_lo"].values[0]), float(tt["eta_hi"].values[0])
    assert 1.19 <= lo < hi <= 1.193 and hi - lo <= 1e-4
    x = ds["final_state"].values[1]
    assert _impacts_per_period(lo - 2e-4, x) == 2
    assert _impacts_per_period(hi + 2e-4, x) == 3


@pytest.fixture(scope="module")
def floquet_sweep():
    """fig8 on the impacting upper branch, eta = 1.16 .. 1.19, with the Floquet analysis
    and the largest Lyapunov exponent at every point."""
    x0 = continued_state("fig8", 1.16)
    grid = np.round(np.arange(1.16, 1.19 + 1e-9, 0.01), 12)
    return vi.sweep(FIG8, grid, state0=x0,
                    settings=SweepSettings(lyapunov="always", lyap_target=1e-3,
                                           lyap_min=300),
                    continuation=vi.Continuation(blocks=1))


def test_floquet_multipliers_are_stored_and_agree_with_the_lyapunov_exponent(
        floquet_sweep):
    """Every periodic point carries its multipliers (complex, split real/imag, dim
    multiplier) and stability; ln|mu|max / (n T) equals the sweep's own largest
    Lyapunov exponent within its error bar."""
    ds = floquet_sweep
    assert ds["floquet_real"].dims == ("eta", "multiplier")
    assert ds.sizes["multiplier"] == 4
    per = ds["period"].values
    assert (per == 1).all()
    assert (ds["stable"].values == 1).all()
    mu = ds["floquet_real"].values + 1j * ds["floquet_imag"].values
    assert np.allclose(np.abs(mu).max(axis=1), ds["floquet_abs_max"].values)
    T = 2 * np.pi * per / ds["eta"].values
    lam = np.log(ds["floquet_abs_max"].values) / T
    err = np.abs(lam - ds["lyapunov"].values)
    assert np.all(err < 4 * ds["lyapunov_err"].values + 1e-3), (lam, ds["lyapunov"].values)


def test_a_label_change_on_the_same_orbit_is_typed_none(floquet_sweep):
    """When only the label changes (here: a loaded-arcs text edited by hand) the orbit
    on both sides is the same and both boundaries are typed 'none'."""
    ds = floquet_sweep.copy(deep=True)
    lab = ds["label"].values.copy()
    lab[2] = lab[2] + " (edited)"
    ds["label"] = ("eta", lab)
    tt = transition_types(ds)
    assert list(tt["type"].values) == ["none", "none"]
    assert all("label changed only" in str(e) for e in tt["evidence"].values)


def test_the_table_has_one_typed_row_per_interval_boundary(floquet_sweep):
    """format_transitions gives one Markdown row per boundary; every type is a
    BifurcationKind (a chain of them)."""
    ds = floquet_sweep.copy(deep=True)
    lab = ds["label"].values.copy()
    lab[-1] = "something else"
    ds["label"] = ("eta", lab)
    tt = transition_types(ds, refine=False)
    assert tt.sizes["boundary"] == len(vi.intervals(ds)["start"]) - 1
    for t in tt["type"].values:
        assert all(isinstance(k, BifurcationKind) for k in kinds_in(t))
    md = format_transitions(tt)
    assert md.count("\n") == 1 + tt.sizes["boundary"]


def test_params_are_read_from_the_dataset(floquet_sweep):
    """Without p, the sweep's parameters come from its attributes: the same table as
    with p given."""
    params = json.loads(floquet_sweep.attrs["params"])
    assert params["kh"] == FIG8.kh
    ds = floquet_sweep.copy(deep=True)
    lab = ds["label"].values.copy()
    lab[0] = "edited"
    ds["label"] = ("eta", lab)
    a = transition_types(ds, refine=False)
    b = transition_types(ds, p=FIG8, refine=False)
    assert a.sizes["boundary"] == 1
    assert list(a["type"].values) == list(b["type"].values)
    assert list(a["evidence"].values) == list(b["evidence"].values)


@pytest.mark.parametrize("kwargs, name", [
    (dict(tol=0.0), "tol"),
    (dict(p=vi.DuffingParams()), "p"),
    (dict(direction="sideways"), "direction"),
    (dict(settings="fast"), "settings"),
])
def test_bad_input_names_the_argument(floquet_sweep, kwargs, name):
    """Bad arguments raise ValueError naming the argument."""
    with pytest.raises(ValueError, match=name):
        transition_types(floquet_sweep, **kwargs)


def test_a_dataset_that_is_not_a_sweep_is_refused():
    """A dataset without labels and final states is refused, naming ds."""
    import xarray as xr

    with pytest.raises(ValueError, match="ds"):
        transition_types(xr.Dataset({"x": ("eta", np.zeros(3))}))
