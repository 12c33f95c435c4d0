"""Log text of one point (``vibimpact -vv``: each point's transient and decision) and the
pieces the engine's ``-v`` lines share (:mod:`vibimpact.engine.logtext`)."""
from __future__ import annotations

import numpy as np

__all__ = ["OVER_ATTEMPTS", "Lazy", "kind", "parameters", "point"]

#: how a point's transient is counted in every log line: the periods of all its attempts
#: (an attempt from the neighbouring point's orbit that is given up is discarded but
#: counted), against the plan's ``transient_max``, which is a budget per attempt
OVER_ATTEMPTS = "over all attempts"


class Lazy:
    """A log argument computed only when the record is formatted (a disabled level
    costs nothing): ``log.info("%s", Lazy(f, *args))``."""

    __slots__ = ("args", "func")

    def __init__(self, func, *args):
        self.func, self.args = func, args

    def __str__(self):
        try:
            return str(self.func(*self.args))
        except Exception as exc:  # a log line never ends a run
            return f"<{type(exc).__name__}: {exc}>"


def parameters(p, swept=True):
    """``"kh = 120, G = 0.3, ..."``: the parameters of a Params or a System, less the
    forcing frequency when it is ``swept`` (its value there is no point's)."""
    values = getattr(p, "params", p)
    values = values.as_dict() if hasattr(values, "as_dict") else values
    model = getattr(p, "model", None)
    freq = (model.param_names[model.omega_index] if model is not None else
            ("omega" if isinstance(values, dict) and "omega" in values else "eta"))
    if swept and isinstance(values, dict):
        values = {k: v for k, v in values.items() if k != freq}
    if isinstance(values, np.ndarray):
        return ", ".join(f"{v:g}" for v in values)
    try:
        return ", ".join(f"{k} = {float(v):g}" for k, v in dict(values).items())
    except (TypeError, ValueError):
        return repr(values)


def kind(res):
    """``"P2"``, ``"chaotic"``, ...: a point's regime in a word."""
    from .codes import REGIME_CODES

    code, n = int(res.get("regime", 0)), int(res.get("period", 0) or 0)
    name = {v: k.value for k, v in REGIME_CODES.items()}.get(code, "not computed")
    return (f"P{n}" if n else name) if name == "periodic" else name


def point(eta, res):
    """One line on a finished point: its transient and decision."""
    d = res.as_dict() if hasattr(res, "as_dict") else dict(res)
    return (f"point eta {float(eta):.6g}: {kind(d)} after a transient of "
            f"{int(d.get('transient', 0))} periods {OVER_ATTEMPTS}, "
            f"{int(d.get('recorded', 0))} recorded"
            + (f" ({d['reason']})" if d.get("reason") else ""))
