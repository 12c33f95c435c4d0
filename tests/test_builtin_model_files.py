"""A built-in model is its three files (issue 42): nothing else in the package names it.
The package's constants (``vi.ROTOR``, ``vi.RING``, ...) come from the registry, and the
commands' defaults that depend on the model (the basins' plane) come from what the model
declares."""
import vibimpact as vi
from vibimpact import models
from vibimpact.census.basins import default_plane, plane_axes
from vibimpact.cli import main


def test_every_built_in_model_is_a_constant_of_the_package():
    """Hypothesis: for every model of the registry ``vi.<NAME>`` (its name in capitals)
    is that model and ``vi.__all__`` lists it (the ring, missing before, included), and
    the package lists no model constant the registry lacks; an unknown capitalised name
    is an AttributeError."""
    names = models.names()
    assert "ring" in names and "soft_impact" in names
    for name in names:
        assert getattr(vi, name.upper()) is models.get(name)
        assert name.upper() in vi.__all__ and name.upper() in dir(vi)
    constants = {n for n in vi.__all__ if n.isupper() and n != "METHODS"}
    assert constants == {n.upper() for n in names}
    try:
        vi.NO_SUCH_MODEL
    except AttributeError:
        pass
    else:
        raise AssertionError("vi.NO_SUCH_MODEL did not raise")


def test_basins_default_to_the_plane_the_model_draws(tmp_path, capsys):
    """Hypothesis: without ``--plane`` (or ``plane=``) the basins are in the plane of the
    model's XY plots: X, Y for the rotor, x, dx for the soft-impact oscillator (whose
    states have no X, Y: the old default X,Y refused it)."""
    assert default_plane(vi.ROTOR) == ("X", "Y")
    assert default_plane(vi.SOFT_IMPACT) == ("x", "dx")
    assert plane_axes(vi.SOFT_IMPACT, None) == (0, 1)
    out = tmp_path / "b.nc"
    assert main(["basins", "--preset", "soft-impact", "--grid", "5x5", "--no-progress",
                 "-o", str(out)]) == 0
    assert vi.io.read_netcdf(out).attrs["plane"] == "x,dx"
