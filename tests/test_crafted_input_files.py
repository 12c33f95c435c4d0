"""Crafted input files (issue 44, class 10): every value a command or an API function
takes from a file is validated as if typed on the command line -- a sweep's parameters
(its ``params`` JSON and ``param_NAME`` attributes, which must agree), its
``final_state``, eta grid and regime codes, the start a ``simulate --from`` file records
for ``rerun``, and the parameters a plot's title shows.  A crafted file is refused
before any work: one line, exit 2, no file."""
import json
import shutil

import netCDF4
import numpy as np
import pytest
import xarray as xr

import vibimpact as vi
from vibimpact.io.recorded import (check_recorded, recorded_params, recorded_state,
                                   recorded_values)
from vibimpact.sweeps import SweepStart

from test_bad_input import assert_refused, run_cli  # noqa: F401

FROM = ["--eta", "1.01", "--periods", "2", "--transient", "0", "-o", "o.nc"]


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """A two-point sweep ``s.nc`` (with responses, to plot) and the run ``r.nc`` that
    ``simulate --from s.nc`` made from it, in a directory of their own."""
    from vibimpact.cli import main

    d = tmp_path_factory.mktemp("crafted")
    mp = pytest.MonkeyPatch()
    mp.chdir(d)
    try:
        assert main(["classify", "--eta", "1.0,1.01", "--analyses", "period,response",
                     "--workers", "1", "--no-progress", "-o", "s.nc"]) == 0
        assert main(["simulate", "--from", "s.nc", *FROM[:-1], "r.nc"]) == 0
    finally:
        mp.undo()
    return d


def _attrs(**changes):
    """A change of global attributes by netCDF4 (None: delete)."""
    def change(nc):
        for key, value in changes.items():
            if value is None:
                nc.delncattr(key)
            else:
                nc.setncattr(key, value)
    return change


def _json(key, **entries):
    """A change of entries of the JSON attribute ``key``."""
    def change(nc):
        values = json.loads(nc.getncattr(key))
        values.update(entries)
        nc.setncattr(key, json.dumps(values))
    return change


def _no_param_attrs(nc):
    for key in list(nc.ncattrs()):
        if key.startswith("param_"):
            nc.delncattr(key)


def _variable(name, make):
    """A change of a variable, through xarray (new type or shape)."""
    def change(ds):
        ds[name] = make(ds[name])
        return ds
    return change


def _crafted(src, dst, change):
    """A copy of ``src`` at ``dst`` with ``change`` applied: to the attributes in place
    (netCDF4) or, for a function of a Dataset, to the dataset (rewritten)."""
    if getattr(change, "dataset", False):
        with xr.open_dataset(src) as ds:
            ds = change(ds.load())
        ds.to_netcdf(dst)
    else:
        shutil.copy(src, dst)
        with netCDF4.Dataset(dst, "a") as nc:
            change(nc)
    return dst


def _ds_change(func):
    func.dataset = True
    return func


#: crafted sweep -> what the one line names
SWEEPS = {
    "no params attribute": (_attrs(params=None), "no 'params' attribute"),
    "no param_* attributes": (_no_param_attrs, "no param_B attribute"),
    "one param_* attribute missing": (_attrs(param_G=None), "no param_G attribute"),
    "param_kh = -5 beside params kh = 120": (_attrs(param_kh=-5.0),
                                             "two values of kh"),
    "kh = -5 in both records": (lambda nc: (_json("params", kh=-5.0)(nc),
                                            nc.setncattr("param_kh", -5.0)),
                                "param_kh = -5: kh must be >= 0"),
    "param_B = NaN": (_attrs(param_B=np.nan), "param_B is nan"),
    "param_G = inf": (_attrs(param_G=np.inf), "param_G is inf"),
    "param_kh as text": (_attrs(param_kh="120"), "param_kh is text"),
    "param_kh two numbers": (_attrs(param_kh=np.array([120.0, 1.0])),
                             "param_kh is not one real number"),
    "params entry as text": (_json("params", kh="120"), "'params' entry 'kh' is text"),
    "params entry null": (_json("params", B=None), "'params' entry 'B' is None"),
    "params not an object": (_attrs(params="[1, 2]"), "not a JSON object"),
    "params not JSON": (_attrs(params="{kh: 1"), "is not JSON"),
    "params with an unknown parameter": (lambda nc: (_json("params", zz=1.0)(nc),
                                                     nc.setncattr("param_zz", 1.0)),
                                         "'zz'"),
    "another model's name": (_attrs(model="duffing"), "model 'duffing' has 2 states"),
    "a model not installed": (_attrs(model="nosuch"), "records model 'nosuch'"),
    "model as a number": (_attrs(model=3), "not a model's name"),
    "final_state as text": (_ds_change(_variable(
        "final_state", lambda v: v.astype(str))), "final_state holds <U"),
    "final_state of three states": (_ds_change(lambda ds: ds.isel(state=slice(0, 3))),
                                    "final_state has shape (2, 3)"),
    "final_state infinite": (_ds_change(_variable(
        "final_state", lambda v: v + np.inf)), "did not compute"),
    "eta grid as text": (_ds_change(lambda ds: ds.assign_coords(
        eta=ds["eta"].astype(str))), "eta holds"),
    "regime as floats": (_ds_change(_variable("regime", lambda v: v.astype(float))),
                         "regime holds float64"),
}


@pytest.mark.parametrize("case", list(SWEEPS))
def test_simulate_from_refuses_a_crafted_sweep_before_any_work(case, files, tmp_path,
                                                              monkeypatch, capfd):
    """Hypothesis: simulate --from read one of the sweep's two records of its parameters
    and took final_state with a float() conversion, so a sweep with param_kh = -5, NaN,
    text, no param_* attributes or a text final_state ran and wrote a file; now every
    value is checked as if typed (finite, real, in its domain, both records agreeing,
    the model's number of states): one line naming it, exit 2, no file."""
    change, needle = SWEEPS[case]
    _crafted(files / "s.nc", tmp_path / "c.nc", change)
    monkeypatch.chdir(tmp_path)
    rc, out, err = run_cli(["simulate", "--from", "c.nc", *FROM], capfd)
    assert_refused(rc, out, err, needle)
    assert not (tmp_path / "o.nc").exists()


def test_simulate_from_the_untouched_sweep_still_runs(files, tmp_path, monkeypatch,
                                                      capfd):
    """Hypothesis: the checks refuse only crafted values: the sweep as written starts a
    run (exit 0, file written)."""
    shutil.copy(files / "s.nc", tmp_path / "c.nc")
    monkeypatch.chdir(tmp_path)
    rc, out, err = run_cli(["simulate", "--from", "c.nc", *FROM], capfd)
    assert rc == 0 and (tmp_path / "o.nc").exists(), err


@pytest.mark.parametrize("case", ["param_kh = -5 beside params kh = 120",
                                  "param_B = NaN", "final_state as text",
                                  "another model's name"])
def test_the_api_sweep_start_refuses_a_crafted_sweep(case, files, tmp_path):
    """Hypothesis: vi.sweeps.sweep_start is the same reader as the command line: a
    crafted sweep is a ValueError naming what is wrong, not a start."""
    change, needle = SWEEPS[case]
    ds = vi.io.read_netcdf(_crafted(files / "s.nc", tmp_path / "c.nc", change))
    with pytest.raises(ValueError, match="ds"):
        vi.sweeps.sweep_start(ds, 1.01)
    with pytest.raises(ValueError) as info:
        vi.sweeps.sweep_start(ds, 1.01)
    assert needle in str(info.value)


#: crafted start record of a simulate --from file -> what the message names
STARTS = {
    "start_params kh = -5": (_json("start_params", kh=-5.0), "kh must be >= 0"),
    "start_params B as text": (_json("start_params", B="x"), "'start_params' entry 'B'"),
    "start_params without G": (lambda nc: nc.setncattr("start_params", json.dumps(
        {k: v for k, v in json.loads(nc.getncattr("start_params")).items() if k != "G"})),
        "records no G"),
    "start_eta disagreeing": (_attrs(start_eta=1.3), "start_eta = 1.3"),
    "start_eta NaN": (_attrs(start_eta=np.nan), "start_eta is nan"),
    "start_direction sideways": (_attrs(start_direction="sideways"), "not up or down"),
    "state0 NaN": (lambda nc: nc["state0"].__setitem__(0, np.nan), "state0 is not finite"),
    "start of another model": (_attrs(model="duffing"), "model 'duffing' does not have"),
}


@pytest.mark.parametrize("case", list(STARTS))
def test_rerun_refuses_a_crafted_start_record(case, files, tmp_path, monkeypatch, capfd):
    """Hypothesis: rerun of a simulate --from file took its start_params, state0 and
    start_eta as they were (Params(**json), reshape(4)); now they are checked as if
    typed: one line naming the start record, exit 2, nothing left."""
    change, needle = STARTS[case]
    _crafted(files / "r.nc", tmp_path / "r.nc", change)
    monkeypatch.chdir(tmp_path)
    rc, out, err = run_cli(["rerun", "r.nc"], capfd)
    assert_refused(rc, out, err, needle)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.nc"]
    with pytest.raises(ValueError, match="damaged start record"):
        SweepStart.from_run_dataset(vi.io.read_netcdf(tmp_path / "r.nc"))


@pytest.mark.parametrize("src,case,needle", [
    ("s.nc", "kh = -5 in both records", "kh must be >= 0"),
    ("s.nc", "param_B = NaN", "param_B is nan"),
    ("r.nc", "param_kh = -5", "kh must be >= 0"),
    ("r.nc", "param_eta as text", "param_eta is text"),
])
def test_plot_refuses_crafted_parameters_in_its_title(src, case, needle, files, tmp_path,
                                                      monkeypatch, capfd):
    """Hypothesis: a plot's title showed whatever the file recorded (kh = -5); now the
    parameters it shows are checked as if typed: one line, exit 2, no image."""
    change = SWEEPS.get(case, (None,))[0] or _attrs(
        **({"param_kh": -5.0} if "kh" in case else {"param_eta": "fast"}))
    _crafted(files / src, tmp_path / "c.nc", change)
    monkeypatch.chdir(tmp_path)
    rc, out, err = run_cli(["plot", "c.nc", "-o", "p.png"], capfd)
    assert_refused(rc, out, err, needle)
    assert not (tmp_path / "p.png").exists()


def test_recorded_params_needs_every_parameter_and_agreeing_records():
    """Hypothesis: the one reader of recorded parameters returns the parameter set of a
    complete, agreeing record, and refuses a missing or disagreeing one."""
    p = vi.presets.get("fig8")
    params = {k: v for k, v in p.as_dict().items() if k != "eta"}
    attrs = {"model": "rotor", "params": json.dumps(params),
             **{f"param_{k}": v for k, v in params.items()}}
    assert recorded_params(attrs, omega=p.eta) == p
    with pytest.raises(ValueError, match="records no eta"):
        recorded_params(attrs)
    with pytest.raises(ValueError, match="two values of kh"):
        recorded_params({**attrs, "param_kh": params["kh"] * (1 + 1e-15)}, omega=1.0)
    with pytest.raises(ValueError, match="eta is 0.0|eta must be > 0"):
        recorded_params(attrs, omega=0.0)


@pytest.mark.parametrize("value,needle", [(True, "not a number"), (1 + 2j, "complex"),
                                          (np.array([[1.0]]), None), (None, "None")])
def test_recorded_values_take_only_one_real_number(value, needle):
    """Hypothesis: a boolean, a complex number or None is no parameter value; a
    1-element array (how NetCDF stores a number) is one."""
    if needle is None:
        assert recorded_values({"param_kh": value}) == {"kh": 1.0}
        return
    with pytest.raises(ValueError):
        check_recorded({"param_kh": value})


def test_recorded_state_is_the_models_size_of_finite_numbers():
    """Hypothesis: a state from a file has the model's number of values, numbers,
    finite."""
    rotor = vi.models.get("rotor")
    assert recorded_state([0, 0, 0, 0], rotor, "s").dtype == np.float64
    for bad in ([0.0] * 3, ["0"] * 4, [0, 0, 0, np.inf], [[0.0] * 4]):
        with pytest.raises(ValueError, match="^s "):
            recorded_state(bad, rotor, "s")
