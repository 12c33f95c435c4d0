"""One vocabulary of bifurcations: :class:`vibimpact.base.bifurcation_kinds.BifurcationKind`
(issue 29, point 4).

The kinds named by continuation, by the transitions of a sweep and by a branch file are
the members of one enum; a branch file stores each kind's code, and the codes files held
before grazing joined are unchanged.
"""
import subprocess
import sys

import numpy as np
import pytest

import vibimpact as vi
from vibimpact.analysis import Branch
from vibimpact.base.bifurcation_kinds import BRANCH_KINDS, BifurcationKind, branch_flags, kinds_in
from vibimpact.continuation.branches import branch_from_dataset, branch_to_dataset

#: the codes of the files written before this vocabulary (vibimpact.continuation.branches'
#: BIFURCATION_CODES then): such files must read the same
STORED_BEFORE = {"?": 0, "fold (turning point)": 1, "fold": 2, "period doubling": 3,
                 "Neimark-Sacker": 4}


def test_codes_of_existing_files_are_kept_and_every_code_is_unique():
    """Hypothesis: the five kinds branch files held keep their codes (0 to 4), every
    kind has its own code and its own short name, and from_code inverts code."""
    for name, code in STORED_BEFORE.items():
        assert BifurcationKind(name).code == code
    codes = [k.code for k in BifurcationKind]
    assert len(set(codes)) == len(codes)
    assert len({str(k) for k in BifurcationKind}) == len(codes)
    for kind in BifurcationKind:
        assert BifurcationKind.from_code(kind.code) is kind
    with pytest.raises(ValueError, match="code"):
        BifurcationKind.from_code(99)


def test_floquet_signatures_name_the_stability_changes():
    """Hypothesis: a multiplier through -1 is a period doubling, through +1 a fold, a
    complex pair a Neimark-Sacker bifurcation; each kind with a signature is found
    from it (the turning point shares the fold's +1); grazing has none: its impacts
    change with every multiplier inside the unit circle."""
    assert BifurcationKind.by_multiplier("-1") is BifurcationKind.PERIOD_DOUBLING
    assert BifurcationKind.by_multiplier("+1") is BifurcationKind.FOLD
    assert BifurcationKind.by_multiplier("complex") is BifurcationKind.NEIMARK_SACKER
    assert BifurcationKind.by_multiplier("") is BifurcationKind.UNKNOWN
    for kind in BifurcationKind:
        if kind.signature is not None:
            expect = (BifurcationKind.FOLD if kind is BifurcationKind.TURNING_POINT
                      else kind)
            assert BifurcationKind.by_multiplier(kind.signature) is expect
    assert BifurcationKind.TURNING_POINT.signature == "+1"
    assert BifurcationKind.GRAZING.signature is None
    assert "impacts" in BifurcationKind.GRAZING.words


def test_a_kind_is_its_short_name_in_text():
    """Hypothesis: a kind equals, prints and formats as its short name (what reports,
    the CLI and the transitions table show), and a chain of kinds splits back into
    kinds; a word that is no kind is refused naming text."""
    kind = BifurcationKind.PERIOD_DOUBLING
    assert kind == "period doubling" and str(kind) == "period doubling"
    assert f"{kind} at" == "period doubling at"
    assert type(str(kind)) is str
    assert kinds_in("grazing + period doubling") == [BifurcationKind.GRAZING,
                                                     BifurcationKind.PERIOD_DOUBLING]
    with pytest.raises(ValueError, match="text"):
        kinds_in("grazing + wobble")


def test_branch_flags_declare_every_kind_a_branch_holds():
    """Hypothesis: the CF flags of bifurcation_kind list each kind a branch can hold
    (grazing included) once, one word each, in code order."""
    values, meanings = branch_flags()
    assert values == tuple(k.code for k in BRANCH_KINDS)
    assert meanings.split() == [k.flag for k in BRANCH_KINDS]
    assert BifurcationKind.GRAZING in BRANCH_KINDS
    assert all(isinstance(k, BifurcationKind) for k in BRANCH_KINDS)


def _branch_with_every_kind():
    """A made-up branch of fig8 (no computation) with one event of every branch kind."""
    k = len(BRANCH_KINDS) + 1
    vals = np.linspace(1.0, 1.1, k)
    events = tuple((i + 1, kind, float(vals[i] + 0.005))
                   for i, kind in enumerate(BRANCH_KINDS))
    brackets = tuple((float(vals[i]), float(vals[i + 1])) for i in range(len(events)))
    impacts = np.arange(k, dtype=np.int64)
    around = tuple((int(impacts[i - 1]), int(impacts[i])) for i, _, _ in events)
    mu = np.full((k, 4), 0.5 + 0.1j)
    return Branch("eta", vals, np.zeros((k, 4)), mu, np.ones(k, bool), {}, 1, events,
                  "made up", brackets, impacts, around)


def test_codes_round_trip_through_a_branch_file(tmp_path):
    """Hypothesis: every kind a branch can hold is written as its code and read back
    as the same BifurcationKind member, with the impacts before and after it, through
    a NetCDF file."""
    br = _branch_with_every_kind()
    system = vi.System(vi.presets.get("fig8"))
    path = tmp_path / "kinds.nc"
    vi.io.write_netcdf(branch_to_dataset(br, system), path)
    ds = vi.io.read_netcdf(path)
    assert list(ds["bifurcation_kind"].values) == [k.code for k in BRANCH_KINDS]
    assert tuple(ds["bifurcation_kind"].attrs["flag_values"]) == branch_flags()[0]
    assert ds["bifurcation_kind"].attrs["flag_meanings"] == branch_flags()[1]
    back = branch_from_dataset(ds)
    assert [k for _, k, _ in back.bifurcations] == list(BRANCH_KINDS)
    assert all(type(k) is BifurcationKind for _, k, _ in back.bifurcations)
    assert back.event_impacts == br.event_impacts
    np.testing.assert_array_equal(back.impacts_per_period, br.impacts_per_period)


def test_a_file_without_impacts_reads_with_impacts_not_counted(tmp_path):
    """Hypothesis: a branch file written before impacts were counted (no
    impacts_per_period, no bifurcation_impacts_*) still reads, its kinds from the same
    codes, its impacts -1 (not counted)."""
    br = _branch_with_every_kind()
    ds = branch_to_dataset(br, vi.System(vi.presets.get("fig8")))
    old = ds.drop_vars(["impacts_per_period", "bifurcation_impacts_before",
                        "bifurcation_impacts_after"])
    back = branch_from_dataset(old)
    assert [k for _, k, _ in back.bifurcations] == list(BRANCH_KINDS)
    assert (back.impacts_per_period == -1).all()
    assert back.event_impacts == ((-1, -1),) * len(BRANCH_KINDS)


def test_the_module_imports_nothing_heavy():
    """Hypothesis: the vocabulary is importable from any layer: it imports neither
    numpy, numba, xarray nor matplotlib."""
    code = ("import sys\nimport vibimpact.base.bifurcation_kinds\nprint('HEAVY', [m for m in "
            "('numpy', 'numba', 'xarray', 'matplotlib') if m in sys.modules])\n")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                       timeout=60)
    assert "HEAVY []" in r.stdout, r.stderr


def test_the_old_vocabularies_are_gone():
    """Hypothesis: no module keeps its own list of kinds next to BifurcationKind (the
    names that held them are gone)."""
    import vibimpact.analysis.bifurcation as bif
    import vibimpact.analysis.continuation as cont
    import vibimpact.continuation.branches as branches
    import vibimpact.plotting.branch as plot_branch
    import vibimpact.sweeps.transitions as transitions

    for module, name in ((bif, "KIND_BY_MULTIPLIER"), (cont, "KIND_BY_MULTIPLIER"),
                         (cont, "FOLD_TURNING"), (branches, "BIFURCATION_CODES"),
                         (branches, "BIFURCATION_FLAGS"), (transitions, "TYPES"),
                         (plot_branch, "BIFURCATION_LABELS")):
        assert not hasattr(module, name), (module.__name__, name)
    assert set(plot_branch.BIFURCATION_MARKERS) == set(BRANCH_KINDS)
