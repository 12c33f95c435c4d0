"""Two-parameter bifurcation curves as files: :func:`curve_to_dataset` turns a
:class:`~vibimpact.analysis.BifurcationCurve` (from
:func:`vibimpact.analysis.continue_bifurcation`) into an ``xarray.Dataset``, which
:func:`vibimpact.io.write_netcdf` writes atomically; :func:`is_curve_dataset` tells such
a file from the others.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from ..base import _validate as _v
from ..base.bifurcation_kinds import branch_flags

if TYPE_CHECKING:  # names of the annotations only
    from collections.abc import Mapping

    import xarray as xr

    from ..analysis import BifurcationCurve
    from ..core.system import System

__all__ = ["curve_to_dataset", "is_curve_dataset"]

_TITLE = "vibimpact two-parameter bifurcation curve"


def curve_to_dataset(curve: BifurcationCurve, system: System, *,
                     command: str | None = None,
                     attrs: Mapping[str, Any] | None = None) -> xr.Dataset:
    """A :class:`~vibimpact.analysis.BifurcationCurve` as an ``xarray.Dataset``.

    Parameters
    ----------
    curve : BifurcationCurve
    system : System or parameter set
        The system it was continued in (its other parameters, model, solver).
    command : str, optional
        The command line (attribute ``command``).
    attrs : dict, optional
        Further global attributes.

    Returns
    -------
    xarray.Dataset
        Dimension ``point`` (along the curve, by the second parameter): coordinates
        named after the two parameters; ``orbit_state`` (point, state),
        ``floquet_real``, ``floquet_imag`` (point, multiplier), ``test_function``,
        ``impacts_per_period``; the scalar ``bifurcation_kind`` (flag, the kind's code as
        in a branch file).  Global attributes ``curve_params`` (``"p1,p2"``),
        ``curve_kind``, ``period``, ``status``, ``model``, ``param_<name>``,
        ``solver_<key>``, ``command``.

    Raises
    ------
    ValueError
        Naming ``curve`` when it is not a BifurcationCurve.
    """
    import xarray as xr

    from ..analysis import BifurcationCurve
    from ..analysis.bifurcation import CONTINUATION_SOLVER
    from ..core.system import SOLVER_FIELDS, param_dict, to_system

    if not isinstance(curve, BifurcationCurve):
        raise _v.WrongType(f"curve must be a vibimpact.analysis.BifurcationCurve, got "
                           f"{type(curve).__name__}")
    system = to_system(system, "system")
    names = list(system.model.state_names)
    p1, p2 = curve.params
    mu = np.asarray(curve.multipliers, dtype=complex)
    values, meanings = branch_flags()
    data = {
        "orbit_state": (("point", "state"), np.asarray(curve.states, np.float64),
                        dict(units="1", long_name="stroboscopic point of the orbit")),
        "floquet_real": (("point", "multiplier"), mu.real.copy(),
                         dict(units="1", long_name="Floquet multipliers, real part")),
        "floquet_imag": (("point", "multiplier"), mu.imag.copy(),
                         dict(units="1", long_name="Floquet multipliers, imaginary part")),
        "test_function": ("point", np.asarray(curve.test, np.float64),
                          dict(units="1", long_name=_TEST_NAMES[curve.kind.flag])),
        "impacts_per_period": ("point", np.asarray(curve.impacts_per_period, np.int32),
                               dict(units="1", valid_min=np.int32(0),
                                    long_name="impacts per period of the "
                                              "orbit (-1: run stopped)")),
        "bifurcation_kind": ((), np.int8(curve.kind.code),
                             dict(long_name="kind of bifurcation along the curve",
                                  flag_values=np.array(values, dtype=np.int8),
                                  flag_meanings=meanings)),
    }
    coords = {p: ("point", np.asarray(curve.values[:, j], np.float64),
                  dict(units="1", long_name=f"parameter {p}"))
              for j, p in enumerate((p1, p2))}
    coords["state"] = ("state", np.array(names, dtype=object),
                       dict(long_name="state variable"))
    ds = xr.Dataset(data, coords=coords)
    glob = {"title": _TITLE, "model": system.model.name, "curve_params": f"{p1},{p2}",
            "curve_kind": curve.kind.value, "period": int(curve.n),
            "status": curve.status, "command": command}
    glob.update({f"param_{k}": v for k, v in param_dict(system).items()})
    glob.update({f"solver_{k}": v for k, v in system.settings(
        **CONTINUATION_SOLVER).as_dict(SOLVER_FIELDS).items()})
    glob.update(attrs or {})
    ds.attrs.update({k: "" if v is None else v for k, v in glob.items()})
    return ds


_TEST_NAMES = {"fold": "det(M - I): zero at a multiplier +1",
               "period_doubling": "det(M + I): zero at a multiplier -1",
               "grazing": "signed gap: penetration at the grazing extremum (0 at "
                          "grazing)"}


def is_curve_dataset(ds: xr.Dataset) -> bool:
    """True for a dataset of :func:`curve_to_dataset` (or its file read back)."""
    return ds.attrs.get("title") == _TITLE and "curve_params" in ds.attrs
