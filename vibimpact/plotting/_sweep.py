"""Helpers shared by the sweep figures: directions, colours, titles."""
from __future__ import annotations

import numpy as np

from ..base import _json
from ..base import _validate as _v

#: colour of each sweep direction
DIRECTION_COLORS = {"up": "tab:blue", "down": "tab:orange"}

#: regime code (CF flag of the ``regime`` variable) -> name
REGIME_NAMES = {0: "not computed", 1: "periodic", 2: "quasi-periodic", 3: "chaotic",
                4: "diverged", 5: "unsettled"}


def check_dataset(ds, what):
    """Raise TypeError unless ``ds`` is an xarray Dataset (``what``: "a sweep", "a map")."""
    import xarray as xr

    if not isinstance(ds, xr.Dataset):
        hint = ("; a Run is one simulation, not a sweep" if hasattr(ds, "strobe") else "")
        raise TypeError(f"ds must be the xarray.Dataset of {what}, got "
                        f"{type(ds).__name__}{hint}")


def check_sweep(ds, *names):
    """Raise TypeError unless ``ds`` is a Dataset, ValueError unless it is a sweep dataset
    holding ``names``."""
    check_dataset(ds, "a sweep (vibimpact.sweep)")
    if "eta" not in ds.dims:
        raise ValueError("not a sweep dataset (no dimension eta); use a file from "
                         "'vibimpact classify' or 'vibimpact bifurcation'")
    missing = [n for n in names if n not in ds]
    if missing:
        raise ValueError(f"the sweep dataset has no {', '.join(missing)}")
    check_contents(ds)


#: variables that hold a count (an integer >= 1) where they hold none of their
#: ``flag_values`` (``period``: 0 is "none", 1, 2, ... a period)
COUNT_FLAGS = ("period",)


def check_contents(ds, grids=("eta",), codes=("regime",), increasing=("eta",)):
    """Raise ValueError, naming the variable, for what a file written by vibimpact
    never holds: a grid (``grids``, coordinates or variables) with a NaN or infinite
    value, or (those in ``increasing``) not strictly increasing; a variable with a value
    outside its ``flag_values`` (those in ``codes`` that declare none:
    :data:`REGIME_NAMES`; those in :data:`COUNT_FLAGS`: or an integer >= 1).  A figure
    drawn from such a file would show what the file does not say; the figures refuse it
    instead.  (A value outside ``valid_min``/``valid_max`` is a missing value to CF, as
    the writers mean it: -1 "not counted" below ``valid_min = 0``; it is not refused.)

    Parameters
    ----------
    ds : xarray.Dataset
    grids, codes, increasing : sequence of str
        The grids, the flag variables without ``flag_values`` of their own and the grids
        that must increase (those ``ds`` lacks are skipped).  Every variable with
        ``flag_values`` is checked whatever these say.
    """
    for name in grids:
        if name in ds.variables:
            _check_grid(name, np.asarray(ds[name].values), name in increasing)
    for name, var in ds.variables.items():
        declared = var.attrs.get("flag_values")
        if declared is None and name in codes:
            declared = list(REGIME_NAMES)
        if declared is None and name in COUNT_FLAGS:
            declared = [0]
        if declared is not None:
            _check_codes(name, np.asarray(var.values), np.asarray(declared).reshape(-1))
    for name, var in ds.data_vars.items():
        if _drawn_value(name):
            _check_no_inf(name, np.asarray(var.values))
    check_fractions(ds)


#: variables a figure draws as values (responses, Poincare samples, basin fractions):
#: NaN is a missing value, an infinite one is never written by vibimpact
DRAWN = ("X_m", "Y_m", "fraction", "fraction_se", "failed_fraction")


def _drawn_value(name):
    return name in DRAWN or name.startswith("poincare_")


def _check_no_inf(name, values):
    if values.dtype.kind not in "iuf":
        raise ValueError(f"{name} must hold numbers, got {values.dtype} values")
    bad = np.isinf(values.astype(float))
    if bad.any():
        raise ValueError(f"{name} holds {int(bad.sum())} infinite value(s): the file is "
                         f"damaged or was not written by vibimpact")


#: what the basin fractions of one eta may add up to above 1 (rounding)
FRACTION_SUM_TOL = 1e-9


def check_fractions(ds):
    """Raise ValueError, naming the variable, unless every basin fraction (``fraction``
    over ``attractor``, and ``failed_fraction``, the share of failed starts) lies in
    ``[0, 1]`` (or is NaN: no attractor in that slot) and those of one eta add up to at
    most 1 (a census's fractions and its failed fraction add up to 1)."""
    if "fraction" not in ds.data_vars or "attractor" not in ds["fraction"].dims:
        return
    frac = ds["fraction"]
    parts = [("fraction", frac.values)]
    if "failed_fraction" in ds.data_vars:
        parts.append(("failed_fraction", ds["failed_fraction"].values))
    for name, values in parts:
        v = np.asarray(values, dtype=float)
        if np.any((v < 0) | (v > 1)):
            raise ValueError(f"{name} holds values outside [0, 1]: the file is damaged or "
                             f"was not written by vibimpact")
    total = np.nansum(np.asarray(frac.values, dtype=float),
                      axis=frac.dims.index("attractor"))
    if len(parts) > 1:
        total = total + np.nan_to_num(np.asarray(parts[1][1], dtype=float))
    if np.any(total > 1.0 + FRACTION_SUM_TOL):
        what = "fraction and failed_fraction add" if len(parts) > 1 else "fraction adds"
        raise ValueError(f"{what} up to {float(np.max(total)):.6g} > 1 (the basin "
                         f"fractions of one eta): the file is damaged or was not written "
                         f"by vibimpact")


def _check_grid(name, values, increasing):
    if values.dtype.kind not in "iuf":
        raise ValueError(f"{name} must hold numbers, got {values.dtype} values")
    bad = ~np.isfinite(values.astype(float))
    if bad.any():
        raise ValueError(f"{name} holds {int(bad.sum())} non-finite value(s) (NaN or "
                         f"inf): the file is damaged or was not written by vibimpact")
    if increasing and values.ndim == 1 and np.any(np.diff(values) <= 0):
        raise ValueError(f"{name} must be strictly increasing: the file is damaged or "
                         f"was not written by vibimpact")


def _damaged(name, values, rule):
    shown = ", ".join(f"{v:g}" for v in np.unique(values)[:5].astype(float))
    raise ValueError(f"{name} holds {rule.format(shown)}: the file is damaged or was not "
                     f"written by vibimpact")


def _check_codes(name, values, allowed):
    values = values.reshape(-1)
    if values.dtype.kind not in "iufb":
        raise ValueError(f"{name} must hold numbers, got {values.dtype} values")
    off = values[~np.isin(values, allowed)]
    if name in COUNT_FLAGS:  # a count: an integer >= 1 is a value, not a code
        off = off[~((off >= 1) & (off == np.round(off)))]
    if off.size:
        listed = ", ".join(str(v) for v in allowed.tolist())
        rule = (f"{{}}, neither an integer >= 1 nor among its flag_values ({listed})"
                if name in COUNT_FLAGS else
                f"code(s) {{}} not among its flag_values ({listed})")
        _damaged(name, off, rule)


def directions(ds):
    """``[(direction, dataset of that direction without the dim), ...]`` in the order up,
    down."""
    if "direction" in ds.dims:
        out = []
        for d in ds["direction"].values:
            sub = ds.sel(direction=d)
            if "direction" in sub.coords:
                sub = sub.drop_vars("direction")
            out.append((str(d), sub))
        return out
    return [(str(ds.attrs.get("sweep_direction", ds.attrs.get("direction", "up"))), ds)]


def spec(ds):
    """The :class:`~vibimpact.models.PlotSpec` of the model a dataset names (a user
    model's, or a model that declares none: the defaults, which show every parameter by
    its name); ValueError for a dataset that names no model."""
    from .. import models
    from ..io.recorded import model_name

    return models.spec_of(model_name(ds.attrs, "ds")) or models.PlotSpec(xy=())


def frequency_label(ds):
    """How the axis of a sweep's forcing frequency is labelled: the symbol the model
    declares for it, else its name (the ``frequency_name`` attribute, else the name of the
    dataset's frequency coordinate)."""
    from .. import models
    from ..io.recorded import model_name

    name = model_name(ds.attrs, "ds")
    if name in models.names():
        model = models.get(name)
        freq = model.param_names[model.omega_index]
    else:
        freq = str(ds.attrs.get("frequency_name", "eta"))
    return spec(ds).symbol(freq)


def title(ds):
    """``preset, NAME = .., ...`` from the dataset's attributes: the parameters the
    dataset's model declares a title shows (:class:`~vibimpact.models.PlotSpec`: always,
    where not 0), then every other parameter the dataset records that it does not
    hide."""
    from ..io.recorded import check_recorded

    a = ds.attrs
    check_recorded(a)  # what the title shows is what --set would accept
    parts = [str(a["preset"])] if a.get("preset") else []
    params = {}
    if "params" in a:
        try:
            params = _json.loads(a["params"], "the attribute 'params'")
        except (TypeError, ValueError):
            params = {}
    if not isinstance(params, dict):
        params = {}
    sp = spec(ds)
    for name in sp.title + sp.title_nonzero:
        v = a.get(f"param_{name}", params.get(name))
        if v is not None and (name in sp.title or float(v) != 0.0):
            parts.append(f"{name} = {float(v):g}")
    for name, v in params.items():
        if name not in sp.title + sp.title_nonzero + sp.title_hidden and \
                isinstance(v, (int, float)):
            parts.append(f"{name} = {float(v):g}")
    return ", ".join(parts)


def new_figure(lk, nrows, height, paper_height):
    """A figure of ``nrows`` axes sharing eta, 8 inches by ``height`` (one column by
    ``paper_height`` in the paper style), sized and styled by the Look ``lk``."""
    fig = lk.figure((8, height), paper_height)
    axes = fig.subplots(nrows, 1, sharex=True, squeeze=False)[:, 0]
    return fig, list(axes)


def axes_of(ax, n, what):
    """``(figure, list of n axes)`` from a caller's ``ax``; ValueError naming ``ax`` (a
    TypeError for something that holds no Axes)."""
    try:
        axes = list(ax) if not hasattr(ax, "plot") else [ax]
    except TypeError:
        axes = [ax]
    if not all(hasattr(a, "plot") and hasattr(a, "figure") for a in axes):
        raise _v.WrongType(f"ax must be {n} matplotlib Axes ({what}), got "
                           f"{type(ax).__name__} {ax!r}"[:200])
    if len(axes) != n:
        raise ValueError(f"ax must be {n} Axes ({what})")
    return axes[0].figure, axes


def grid_step(eta):
    eta = np.asarray(eta, dtype=float)
    if eta.size > 1:
        return float(np.median(np.diff(eta)))
    return 0.01 * float(eta[0]) if eta.size else 0.01
