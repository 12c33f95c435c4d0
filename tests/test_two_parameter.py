"""Two-parameter continuation of folds, period doublings and grazings
(vibimpact.analysis.continue_bifurcation, vibimpact continue2).

References computed in the tests themselves:

* the soft-impact oscillator is linear below grazing, so its grazing curve is where the
  linear response amplitude A / |1 - eta^2 + 2 i zeta eta| equals the gap d (SciPy's
  brentq solves it in eta);
* the forced Duffing oscillator's folds in the weakly nonlinear limit follow from the
  harmonic-balance amplitude equation u [(alpha - w^2 + 3/4 beta u)^2 + (delta w)^2] =
  gamma^2 (u = a^2; Nayfeh & Mook 1979, sec. 4.1): its folds are where d gamma^2/du = 0;
* the one-parameter continuation's refined period doubling and grazing
  (vibimpact.analysis.continue_orbit, refine_stability_change; tests/test_grazing.py's
  measured fig8 grazing).
"""
import numpy as np
import pytest
from scipy.optimize import brentq

import vibimpact as vi
from vibimpact import io
from vibimpact.analysis import (BifurcationCurve, continue_bifurcation, continue_orbit,
                                shoot_periodic_orbit, signed_gap)
from vibimpact.analysis.stability_change import impacts_per_period
from vibimpact.cli import main
from vibimpact.continuation.curves import curve_to_dataset, is_curve_dataset

SOFT = vi.presets.get("soft-impact")


def _linear_amplitude(eta, A, zeta=SOFT.zeta):
    return A / abs(1.0 - eta ** 2 + 2j * zeta * eta)


@pytest.fixture(scope="module")
def soft_curve():
    """The soft-impact grazing curve in (eta, A), A from 0.26 to 0.34."""
    system = vi.System(SOFT.replace(eta=0.83))
    return system, continue_bifurcation(system, [0.8, 0.0], 1, "grazing",
                                        pair=("eta", "A"), stop=(0.26, 0.34))


def test_soft_impact_grazing_curve_is_the_analytic_one(soft_curve):
    """Hypothesis: along the soft-impact grazing curve the linear response amplitude
    equals the gap d to 1e-6, and eta agrees with brentq's root of the analytic
    condition to 1e-8, at every point from A = 0.26 to 0.34."""
    _, c = soft_curve
    eta, A = c.values[:, 0], c.values[:, 1]
    assert c.values.shape[0] >= 5 and A.min() == 0.26 and A.max() == 0.34
    assert np.all(np.abs(_linear_amplitude(eta, A) - SOFT.d) < 1e-6)
    ref = [brentq(lambda e, a=a: _linear_amplitude(e, a) - SOFT.d, 0.5, 0.95, xtol=1e-14)
           for a in A]
    assert np.abs(eta - ref).max() < 1e-8
    assert np.abs(c.test).max() < 1e-8  # the signed gap


def test_the_curve_separates_impactless_from_impacting_orbits(soft_curve):
    """Hypothesis: just below the curve in eta (1e-4) the orbit has no impact, just
    above it one impact per period; the signed gap changes sign there."""
    system, c = soft_curve
    for (eta, A), x in zip(c.values[::3], c.states[::3]):
        counts, gaps = [], []
        for e in (eta - 1e-4, eta + 1e-4):
            q = system.with_params(eta=e, A=A)
            orb = shoot_periodic_orbit(q, x, 1)
            counts.append(impacts_per_period(q, orb.state, 1))
            gaps.append(signed_gap(q, orb.state, 1)[0])
        assert counts == [0, 1]
        assert gaps[0] < 0.0 < gaps[1]


DELTA, BETA, W0, W1 = 0.02, 1.0, 1.04, 1.08


def _hb_folds(w, delta=DELTA, alpha=1.0, beta=BETA):
    """Harmonic balance's two folds (gamma, amplitude) at frequency w: upper (large
    amplitude, jump down) first."""
    s = w ** 2 - alpha
    root = np.sqrt(s ** 2 - 3.0 * delta ** 2 * w ** 2)
    out = []
    for k in ((-s + root) / 3.0, (-s - root) / 3.0):  # k = alpha - w^2 + 3/4 beta u
        u = 4.0 / (3.0 * beta) * (k + s)
        out.append((np.sqrt(u * (k ** 2 + delta ** 2 * w ** 2)), np.sqrt(u)))
    return out


@pytest.mark.parametrize("which,guess", [(0, lambda a, w: [0.0, a * w]),
                                         (1, lambda a, w: [-a, 0.0])])
def test_duffing_fold_curves_agree_with_harmonic_balance(which, guess):
    """Hypothesis: the weakly nonlinear Duffing oscillator's fold curves in (gamma,
    omega) (delta 0.02, beta 1, omega 1.04..1.08, amplitudes 0.2-0.4) agree with
    harmonic balance's to 0.5 % in gamma; the upper fold's error grows with its
    amplitude (harmonic balance is exact only in the weak limit); one multiplier is +1
    to 1e-6 on every point."""
    gamma0, a0 = _hb_folds(W0)[which]
    system = vi.System(vi.DuffingParams(delta=DELTA, alpha=1.0, beta=BETA,
                                        gamma=gamma0 * (1.02 if which == 0 else 0.98),
                                        omega=W0))
    c = continue_bifurcation(system, guess(a0, W0), 1, "fold", pair=("gamma", "omega"),
                             stop=W1, step=0.01)
    assert c.values[-1, 1] == W1
    hb = np.array([_hb_folds(w)[which][0] for w in c.values[:, 1]])
    err = c.values[:, 0] / hb - 1.0
    assert np.abs(err).max() < 5e-3
    if which == 0:
        assert abs(err[-1]) > abs(err[0])
    mu = c.multipliers[:, 0]
    assert np.all(np.abs(mu - 1.0) < 1e-6)


def test_duffing_period_doubling_curve_starts_at_the_refined_one_parameter_value():
    """Hypothesis: the period-doubling curve of the double-well Duffing oscillator in
    (gamma, omega) passes through the period doubling that one-parameter continuation
    with bisection finds at omega = 1.2 (to 1e-6), and a multiplier is -1 (to 1e-6)
    all along omega 1.18..1.22."""
    s = vi.System(vi.DuffingParams(delta=0.3, alpha=-1.0, beta=1.0, gamma=0.25,
                                   omega=1.2))
    x = s.simulate(periods=1, transient=300, state0=[1.0, 0.0]).final_state
    br = continue_orbit(s, x, param="gamma", stop=0.28, refine=1e-8, amplitude=False)
    (i, _, value), = [b for b in br.bifurcations if b[1] == "period doubling"]
    c = continue_bifurcation(s.with_param("gamma", br.values[i - 1]), br.states[i - 1], 1,
                             "pd", pair=("gamma", "omega"), stop=(1.18, 1.22))
    at = int(np.argmin(np.abs(c.values[:, 1] - 1.2)))
    assert c.values[at, 1] == 1.2 and abs(c.values[at, 0] - value) < 1e-6
    mu = c.multipliers[:, 0]
    assert np.all(np.abs(mu + 1.0) < 1e-6)
    assert c.values[0, 1] == 1.18 and c.values[-1, 1] == 1.22


FIG8_GRAZING_ETA = 1.19141097  # tests/test_grazing.py: measured to 2e-10


def test_fig8_grazing_curve_in_eta_kh_by_the_command_line(tmp_path, capsys):
    """Hypothesis: 'vibimpact continue2' seeded from fig8's P1 branch traces its grazing
    in (eta, kh): at kh = 120 (the preset's) it is the one-parameter grazing to 1e-7;
    eta grows with kh (a stiffer contact hits later); the file reads back as a curve
    with the grazing's kind code; every point's impacts per period are 2 or 3."""
    out = tmp_path / "graze.nc"
    rc = main(["continue2", "--preset", "fig8", "--eta", "1.185", "--approach", "1.1",
               "--stop1", "1.2", "--kind", "grazing", "--param2", "kh", "--range2",
               "116:124", "--step", "4", "-o", str(out)])
    assert rc == 0
    assert "P1 grazing curve" in capsys.readouterr().out
    ds = io.read_netcdf(out)
    assert is_curve_dataset(ds) and ds.attrs["curve_params"] == "eta,kh"
    assert int(ds["bifurcation_kind"]) == vi.BifurcationKind.GRAZING.code
    kh, eta = ds["kh"].values, ds["eta"].values
    at = int(np.argmin(np.abs(kh - 120.0)))
    assert kh[at] == 120.0 and abs(eta[at] - FIG8_GRAZING_ETA) < 1e-7
    assert np.all(np.diff(eta) > 0) and np.all(np.diff(kh) > 0)
    assert set(ds["impacts_per_period"].values.tolist()) <= {2, 3}


def test_curve_dataset_holds_the_curve(soft_curve, tmp_path):
    """Hypothesis: the dataset (and its NetCDF file) holds the curve's parameters,
    states and multipliers unchanged."""
    system, c = soft_curve
    assert isinstance(c, BifurcationCurve)
    ds = curve_to_dataset(c, system)
    io.write_netcdf(ds, tmp_path / "c.nc")
    back = io.read_netcdf(tmp_path / "c.nc")
    np.testing.assert_array_equal(back["eta"].values, c.values[:, 0])
    np.testing.assert_array_equal(back["A"].values, c.values[:, 1])
    np.testing.assert_array_equal(back["orbit_state"].values, c.states)
    np.testing.assert_array_equal(back["floquet_real"].values + 1j *
                                  back["floquet_imag"].values, c.multipliers)


@pytest.mark.parametrize("kwargs,name", [
    (dict(kind="hopf"), "kind"),
    (dict(kind="grazing", pair=("eta", "eta")), "pair"),
    (dict(kind="fold", pair=("eta", "nope")), "param"),
    (dict(kind="fold", stop=(0.9, 1.0)), "stop"),
])
def test_bad_input_names_the_argument(kwargs, name):
    """Hypothesis: bad input raises ValueError naming the argument."""
    system = vi.System(vi.DuffingParams())
    args = dict(pair=("omega", "gamma"), stop=0.6)
    args.update(kwargs)
    if args["pair"] == ("eta", "eta") or args["pair"] == ("eta", "nope"):
        system = vi.System(SOFT)
    with pytest.raises(ValueError, match=f"^{name}"):
        continue_bifurcation(system, [0.0, 0.0], 1, **args)


def test_grazing_of_a_model_without_contact_is_refused():
    """Hypothesis: a grazing curve needs a contact: the Duffing oscillator is refused
    naming pair."""
    with pytest.raises(ValueError, match="^pair.*no contact"):
        continue_bifurcation(vi.System(vi.DuffingParams()), [0.0, 0.0], 1, "grazing",
                             pair=("omega", "gamma"), stop=0.6)


@pytest.mark.parametrize("argv,words", [
    (["--kind", "hopf", "--param2", "kh", "--range2", "110:130"], "--kind"),
    (["--kind", "fold", "--param2", "kh", "--range2", "130:140"], "--range2"),
    (["--kind", "fold", "--param2", "nope", "--range2", "1:2"], "--param2"),
    (["--kind", "fold", "--param2", "kh", "--range2", "1"], "--range2"),
])
def test_bad_command_lines_get_one_line_and_exit_2(argv, words, tmp_path, capsys):
    """Hypothesis: bad input to continue2 is one line naming the option, exit status 2,
    nothing written."""
    out = tmp_path / "c.nc"
    assert main(["continue2", "--preset", "fig8", *argv, "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and words in err[0]
    assert not out.exists()


@pytest.mark.parametrize("kwargs", [dict(step=1e-300), dict(step=0.01, min_step=1e-300)],
                         ids=["step", "min_step"])
def test_a_step_below_the_float_resolution_is_refused(kwargs):
    """Hypothesis: a curve whose smallest step in p2 cannot move p2 in floating point
    (p2 + min_step == p2) is refused naming min_step, before any location (it could
    only mark the same value again and again)."""
    with pytest.raises(ValueError, match="^min_step .*float resolution"):
        continue_bifurcation(vi.System(SOFT), [0.8, 0.0], 1, "grazing", pair=("eta", "A"),
                             stop=0.31, **kwargs)
