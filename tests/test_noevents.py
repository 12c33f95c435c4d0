"""The era's integrator, ``method="rk4-fixed-noevents"``: classical RK4 at a fixed step,
the contact switch inside the right-hand side, no event location.

Its orders are what the theory of quadrature across a non-smooth point predicts: a step
that straddles a switch integrates the field's singular part with RK4's weights, so
the global error goes as ``h^(1 + a)`` for a force whose singular part is ``t^a``
(a jump, ``a = 0``: order 1; the Hertz ``d^{3/2}``: order 5/2), and as ``h^4`` while no
switch is crossed.
"""
import numpy as np
import pytest

import vibimpact as vi

#: steps per period of the order fits: 100 ... 3200, in steps of sqrt(2)
STEPS = np.unique(np.round(100 * 2 ** (np.arange(11) / 2)).astype(int))


def _era(params, steps, **kw):
    return vi.System(params, solver=vi.SolverSettings(method="rk4-fixed-noevents",
                                                      steps_per_period=int(steps)), **kw)


def _errors(params, state0, periods, steps=STEPS):
    """Largest error of the stroboscopic states against DOP853 at rtol 1e-13, per
    number of steps, and the reference run."""
    ref = vi.simulate(vi.System(params, solver=vi.SolverSettings(rtol=1e-13, atol=1e-15)),
                      periods=periods, transient=0, state0=state0)
    err = [np.abs(vi.simulate(_era(params, n), periods=periods, transient=0,
                              state0=state0).strobe[1:] - ref.strobe[1:]).max()
           for n in steps]
    return np.array(err), ref


def _order(steps, err):
    """The least-squares slope of log(error) against log(1 / steps)."""
    return -np.polyfit(np.log(steps), np.log(err), 1)[0]


def test_the_era_method_is_fourth_order_while_no_switch_is_crossed():
    """Hypothesis: on an impactless run (fig8 at eta = 0.6 from rest) the method is
    classical RK4: its error falls as h^4 (fitted order within 0.2 of 4)."""
    params = vi.presets.get("fig8").replace(eta=0.6)
    steps = STEPS[:7]
    err, ref = _errors(params, [0.0, 0.0, 0.0, 0.0], 10, steps)
    assert len(ref.impacts) == 0
    assert abs(_order(steps, err) - 4.0) < 0.2, err


@pytest.mark.parametrize("preset, eta, low, high", [
    ("fig10", 1.2, 0.4, 1.3),        # viscous tangential force: jumps at contact entry
    ("hard-impact", 1.3, 0.6, 1.4),  # restitution applied at the step's end, unlocated
    ("fig8", 1.0, 2.0, 3.0),         # Hertz force alone: d^{3/2}, continuous
])
def test_through_contacts_the_order_is_that_of_the_contact_laws_singularity(preset, eta,
                                                                             low, high):
    """Hypothesis: through contacts the method converges, at order about 1 where the
    field jumps at the switch (fig10's viscous tangential damping starts at contact
    entry; an impulsive impact reverses the velocity a fraction of a step late) and about
    5/2 where only the Hertz force d^{3/2} switches on (fig8): far below RK4's 4."""
    params = vi.presets.get(preset).replace(eta=eta)
    state0 = [0.0, 0.0] if preset == "hard-impact" else [0.9, 0.0, 0.0, 0.9]
    err, ref = _errors(params, state0, 2)
    assert len(ref.impacts) >= 2
    order = _order(STEPS, err)
    assert low < order < high, (order, err)
    assert err[-3:].max() < err[:3].min()  # it converges


def test_the_era_method_logs_the_contacts_a_located_run_finds():
    """Hypothesis: with 3200 steps per period the unlocated contact entries of a
    period-1 impacting motion (fig8, eta = 1.0) are those of the event-located DOP853
    run: the same count, each within one step after the located time (a switch is
    applied at the end of the step that crossed it), at the same place."""
    params = vi.presets.get("fig8").replace(eta=1.0)
    n = 3200
    ref = vi.simulate(vi.System(params), periods=5, transient=300)
    era = vi.simulate(_era(params, n), periods=5, transient=300)
    t_ref, t_era = ref.impacts["t_entry"], era.impacts["t_entry"]
    assert len(t_ref) >= 5 and len(t_era) == len(t_ref)
    h = 2 * np.pi / 1.0 / n
    lag = t_era - t_ref
    assert np.all(lag >= -1e-3 * h) and np.all(lag <= h * (1 + 1e-9)), lag / h
    dtheta = np.angle(np.exp(1j * np.radians(era.impacts["theta"] - ref.impacts["theta"])))
    assert np.degrees(np.abs(dtheta)).max() < 1.0


def test_every_analysis_runs_on_the_era_method():
    """Hypothesis: a sweep with every analysis (period, impacts, arcs, Floquet
    multipliers, Lyapunov exponent and 0-1 test where a point needs them) runs on the
    method, its variational equations included, and with 1600 steps per period labels
    two period-1 impacting points of fig8 as DOP853 does, with the largest Floquet
    multiplier within 1e-4."""
    params = vi.presets.get("fig8")
    eta = np.array([1.0, 1.1])
    ref = vi.sweep(params, eta)
    era = vi.sweep(_era(params, 1600), eta)
    assert list(era["label"].values.ravel()) == list(ref["label"].values.ravel())
    assert all("impacts" in str(label) for label in era["label"].values.ravel())
    np.testing.assert_allclose(era["floquet_abs_max"].values, ref["floquet_abs_max"].values,
                               atol=1e-4)


def test_the_era_methods_lyapunov_spectrum_through_impacts_sums_to_minus_two_b():
    """Hypothesis: fig8's field has the divergence -2B everywhere (the Hertz force
    depends on the position only), so its Lyapunov spectrum sums to -2B; the variational
    equations of the method, with the saltation of each unlocated contact switch applied
    at the step's end, keep that sum to 1e-6 on an impacting run at 400 steps per
    period, and closer at 1600."""
    from vibimpact.analysis import Averaging, lyapunov_spectrum

    params = vi.presets.get("fig8").replace(eta=1.0)
    averaging = Averaging(transient=100, min_periods=100, max_periods=100, block=50)
    run = vi.simulate(_era(params, 400), periods=20, transient=100,
                      state0=[0.5, 0.0, 0.0, 0.5])
    assert len(run.impacts) >= 20
    gaps = [abs(lyapunov_spectrum(_era(params, n), [0.5, 0.0, 0.0, 0.5],
                                  averaging=averaging, floquet=False).exponents.sum()
                + 2 * params.B) for n in (400, 1600)]
    assert gaps[0] < 1e-6 and gaps[1] < gaps[0], gaps


def test_the_era_method_applies_an_impulsive_impact_at_the_steps_end():
    """Hypothesis: a hard impact (restitution law) is applied at the end of the step that
    penetrated the stop: the period-1 motion of the hard-impact preset keeps one impact
    per period, each logged approaching the stop at the speed the located DOP853 run
    finds, to 1 %, and one step late at most."""
    params = vi.presets.get("hard-impact")
    n = 1600
    ref = vi.simulate(vi.System(params), periods=10, transient=300)
    era = vi.simulate(_era(params, n), periods=10, transient=300)

    def hits(run):
        ev = run.events
        i = np.flatnonzero((ev["which"] == 0) & (ev["mode_before"][:, 0] == 0))
        return ev["t"][i], ev["state"][i, 1]

    (t_ref, v_ref), (t_era, v_era) = hits(ref), hits(era)
    assert len(t_ref) == len(t_era) == 10
    assert np.all(v_era > 0)
    np.testing.assert_allclose(v_era, v_ref, rtol=1e-2)
    h = 2 * np.pi / params.eta / n
    assert np.all((t_era - t_ref >= -1e-3 * h) & (t_era - t_ref <= h * (1 + 1e-9)))


def test_the_variational_equations_on_the_era_method_converge_to_the_monodromy():
    """Hypothesis: the variational equations integrated by the method (no switch crossed:
    an impactless state of fig8 at eta = 0.6) give the stroboscopic map's Jacobian of
    DOP853 to 1e-8 at 400 steps per period (RK4's h^4)."""
    params = vi.presets.get("fig8").replace(eta=0.6)
    x = np.array([0.1, -0.2, 0.0, 0.05])
    m_ref = vi.System(params).monodromy(x).matrix
    m_era = _era(params, 400).monodromy(x).matrix
    np.testing.assert_allclose(m_era, m_ref, atol=1e-8)


def test_the_two_trajectory_exponent_runs_on_the_era_method():
    """Hypothesis: the two-trajectory estimate of the largest exponent runs on the
    method's own loop: on an impactless state of fig8 (eta = 0.6, every exponent near
    -B/2) it gives DOP853's value to 1e-5."""
    from vibimpact.analysis import Averaging, largest_lyapunov

    params = vi.presets.get("fig8").replace(eta=0.6)
    averaging = Averaging(transient=50, min_periods=100, max_periods=100, block=50)
    ref = largest_lyapunov(vi.System(params), [0.1, 0.0, 0.0, 0.1], averaging=averaging)
    era = largest_lyapunov(_era(params, 400), [0.1, 0.0, 0.0, 0.1], averaging=averaging)
    assert abs(ref.exponents[0] + params.B / 2) < 2e-3
    assert abs(era.exponents[0] - ref.exponents[0]) < 1e-5, (era.exponents, ref.exponents)


def test_a_sweeps_file_names_the_integrator_that_ran(tmp_path):
    """Hypothesis: a sweep's ``solver_<setting>`` attributes (as a run's, an orbit's or a
    branch's file has them) are the integrator that ran -- the System's own method and
    steps where it has them (here the era's method at 100 steps), the sweep's DOP853 at
    rtol 1e-8 otherwise -- and survive the NetCDF file, so that a label's provenance is
    in its file (the ``settings`` attribute alone said DOP853 for both)."""
    from vibimpact.io import read_netcdf, write_netcdf

    params = vi.presets.get("fig8")
    eta = np.array([1.0])
    run = vi.Execution(workers=1, progress=False)
    write_netcdf(vi.sweep(_era(params, 100), eta, execution=run), tmp_path / "era.nc")
    own = read_netcdf(tmp_path / "era.nc").attrs
    plain = vi.sweep(params, eta, execution=run).attrs
    assert own["solver_method"] == "rk4-fixed-noevents"
    assert own["solver_steps_per_period"] == 100
    assert plain["solver_method"] == "dop853" and plain["solver_rtol"] == 1e-8
