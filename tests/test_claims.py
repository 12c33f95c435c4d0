"""The automated check of the paper's interval claims on synthetic sweep datasets."""
import numpy as np
import pytest
import xarray as xr

from vibimpact.paper import claims as C

STEP = 0.005
ETA = np.round(np.arange(1.0, 1.5 + 1e-9, STEP), 6)


def sweep_like(regime, period, impacts, direction="up"):
    """A one-direction dataset shaped like a sweep's (only what the claims read), on the
    first ``len(regime)`` points of ETA."""
    label = np.array([f"r{r} p{p} i{i}" for r, p, i in zip(regime, period, impacts)])
    ds = xr.Dataset({"regime": ("eta", np.asarray(regime, dtype="i1")),
                     "period": ("eta", np.asarray(period, dtype="i4")),
                     "impacts_per_period": ("eta", np.asarray(impacts, dtype=float)),
                     "contact": ("eta", (np.asarray(impacts) > 0).astype("i1")),
                     "label": ("eta", label)}, coords={"eta": ETA[:len(label)]})
    ds.attrs["sweep_direction"] = direction
    return ds


def background():
    n = ETA.size
    return np.ones(n, int), np.ones(n, int), np.full(n, 2.0)


def chaos_between(lo, hi):
    reg, per, imp = background()
    sel = (ETA >= lo - 1e-9) & (ETA <= hi + 1e-9)
    reg[sel], per[sel], imp[sel] = 3, 0, 3.7
    return sweep_like(reg, per, imp)


CHAOS = C.Claim("t-chaos", "fig8", "chaos in (1.21, 1.29)", "irregular", 1.21, 1.29)


def test_exact_reproduction_scores_one_and_agrees():
    """Chaos on exactly the claimed grid points gives Jaccard 1 and agreement."""
    d = C.detect_one(chaos_between(1.21, 1.29), CHAOS)
    assert d.score == pytest.approx(1.0)
    assert d.agree and (d.start, d.end) == (pytest.approx(1.21), pytest.approx(1.29))


def test_one_step_off_agrees_two_steps_do_not():
    """An end one sweep step off still agrees; two steps off do not, and the
    Jaccard index is the exact ratio of shared to united grid points."""
    one = C.detect_one(chaos_between(1.215, 1.29), CHAOS)
    assert one.agree
    assert one.score == pytest.approx(16 / 17)
    two = C.detect_one(chaos_between(1.21, 1.28), CHAOS)
    assert not two.agree
    assert two.score == pytest.approx(15 / 17)


def test_quasiperiodic_and_long_period_count_as_the_papers_chaos_but_not_impactless():
    """Irregular motion = chaotic, quasi-periodic or periodic without a resolved period, and
    only with impacts."""
    reg = np.array([3, 2, 1, 1, 3])
    per = np.array([0, 0, 0, 1, 0])
    imp = np.array([3.0, 2.5, 2.0, 2.0, 0.0])
    ok = C.match_points(sweep_like(reg, per, imp), CHAOS)
    np.testing.assert_array_equal(ok, [True, True, True, False, False])


def test_periodic_claim_needs_the_period_the_impacts_and_contact():
    """"P3 with 8 impacts" matches P3/8 only: not P3/6, not P1/8, not an impactless P3."""
    claim = C.Claim("t-p3", "fig10", "P3, 8 impacts", "periodic", 1.0, 1.02, period=3,
                    impacts=8)
    reg = np.ones(4, int)
    ds = sweep_like(reg, [3, 3, 1, 3], [8.0, 6.0, 8.0, 0.0])
    np.testing.assert_array_equal(C.match_points(ds, claim), [True, False, False, False])


def test_near_claim_accepts_a_start_within_near_distance():
    """A claim "near eta = 1.40" agrees with an interval starting 0.015 later, not with one
    starting 0.03 later."""
    claim = C.Claim("t-near", "fig10", "near 1.40", "irregular", 1.40, 1.44, near=True)
    assert C.detect_one(chaos_between(1.415, 1.45), claim).agree
    assert not C.detect_one(chaos_between(1.43, 1.45), claim).agree


def test_nothing_in_the_window_gives_nan_interval_and_zero_score():
    """Chaos far from the claim (beyond WINDOW) is not detected for it."""
    d = C.detect_one(chaos_between(1.40, 1.45), CHAOS)
    assert np.isnan(d.start) and d.score == 0.0 and not d.agree


def test_best_direction_first_and_objective_is_weighted_mean():
    """detect() returns the better direction first; score() is the weighted mean of
    1 - best Jaccard over the claims of the presets given."""
    up = chaos_between(1.21, 1.29)
    down = chaos_between(1.25, 1.29)
    ds = xr.concat([up, down], dim=xr.DataArray(["up", "down"], dims="direction",
                                                 name="direction"))
    best = C.detect(ds, CHAOS)
    assert best[0].direction == "up" and best[0].score > best[1].score
    obj, per = C.score({"fig8": ds})
    fig8 = C.claims("fig8")
    w = np.array([c.weight for c in fig8])
    s = np.array([per[c.key] for c in fig8])
    assert obj == pytest.approx(float(np.sum(w * (1 - s)) / w.sum()))


def test_every_claim_names_a_known_preset_and_motion():
    """The claim table is well-formed: known presets, motions, ordered bounds."""
    import vibimpact as vi

    for c in C.CLAIMS:
        assert c.preset in vi.presets.names()
        assert c.motion in C.MOTIONS and c.lo <= c.hi
    with pytest.raises(ValueError, match="motion"):
        C.match_points(chaos_between(1.2, 1.3), C.Claim("x", "fig8", "", "odd", 1, 1))


def test_subharmonic_window_with_another_period_earns_the_relaxed_credit():
    """A claimed "P6 with 8 impacts" window reproduced exactly as a P3 window with 6
    impacts scores RELAXED_CREDIT (the window is there, its period is not); a P1 window
    there scores 0."""
    claim = C.Claim("t-p6", "fig11", "P6, 8 impacts", "periodic", 1.05, 1.07, period=6,
                    impacts=8)
    reg, per, imp = background()
    sel = (ETA >= 1.05 - 1e-9) & (ETA <= 1.07 + 1e-9)
    per[sel], imp[sel] = 3, 6.0
    assert C.detect_one(sweep_like(reg, per, imp), claim).score == 0.0
    assert C.claim_score(sweep_like(reg, per, imp), claim) == pytest.approx(C.RELAXED_CREDIT)
    reg, per, imp = background()
    assert C.claim_score(sweep_like(reg, per, imp), claim) == 0.0


def test_claim_with_a_direction_ignores_the_other_sweep():
    """A claim about the up sweep is not satisfied by the down sweep's matching points."""
    claim = C.Claim("t-up", "fig8", "chaos, up sweep", "irregular", 1.21, 1.29,
                    direction="up")
    up = chaos_between(1.40, 1.45)
    down = chaos_between(1.21, 1.29)
    ds = xr.concat([up, down], dim=xr.DataArray(["up", "down"], dims="direction",
                                                 name="direction"))
    best = C.detect(ds, claim)
    assert [d.direction for d in best] == ["up"] and best[0].score == 0.0


AT = C.Claim("t-at", "fig8", "at 1.185 two impacts", "periodic", 1.185, 1.185, period=1,
             impacts=2)


def test_a_one_speed_claim_is_the_motion_at_that_speed_whatever_the_branch_around_it():
    """Hypothesis: a one-speed claim (lo == hi, not near) agrees and scores 1 when the
    grid point at its eta shows the motion, even inside a long branch of that motion
    (which an interval rule could never call 'agree'), and disagrees with score 0 when
    that point shows another motion, even with the motion one step beside it."""
    assert AT.at_speed and not CHAOS.at_speed
    reg, per, imp = background()            # P1 with 2 impacts everywhere: a long branch
    d = C.detect_one(sweep_like(reg, per, imp), AT)
    assert d.agree and d.score == 1.0 and d.start < 1.185 < d.end
    k = int(np.argmin(np.abs(ETA - 1.185)))
    imp[k] = 1.0                            # the point itself shows one impact
    d = C.detect_one(sweep_like(reg, per, imp), AT)
    assert not d.agree and d.score == 0.0
    from dataclasses import replace

    off = replace(AT, lo=1.1875, hi=1.1875)  # half a step off the grid: nearest point
    reg, per, imp = background()
    assert C.detect_one(sweep_like(reg, per, imp), off).agree
    off = replace(AT, lo=1.1885, hi=1.1885)  # beyond the last point (1.180) by > half a step
    assert not C.detect_one(sweep_like(reg, per, imp)[{"eta": slice(0, 37)}], off).agree


def test_the_papers_one_speed_claims_are_scored_as_one_speed():
    """Hypothesis: the paper's claim of the orbit with impacts A and B at eta = 1.185
    (fig8-AB) is a one-speed claim, so its verdict is whether the orbit is there."""
    ab = next(c for c in C.CLAIMS if c.key == "fig8-AB")
    assert ab.at_speed
