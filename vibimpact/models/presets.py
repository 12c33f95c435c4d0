"""Named parameter sets: the paper's, one per figure, and those of the other built-in
models (each model declares its own: :attr:`vibimpact.models.Model.presets`).

All presets have ``k3 = -0.002``.  ``B`` and ``Ec`` are **not given in the paper**; every
preset uses :data:`vibimpact.models.params.DEFAULT_B` and
:data:`vibimpact.models.params.DEFAULT_EC`,
**calibrated** by ``analyses/paper/calibrate.py`` against the paper's interval claims
(``vibimpact.paper.claims``); they are not values from the paper, and the fit is partial: no
pair reproduces every claim (``reports/calibration.md``, ``reports/paper.md``).

Where the paper is silent about a figure's contact dampings, the presets switch ``Bh``,
``BT`` and ``f`` on one at a time on top of ``fig8`` (fig9: Bh, fig10: BT, fig11: f, each
0.05), as its discussion of "three kinds of damping" suggests.  The text can also be read
with dampings accumulating; the calibration scores every such reading, and this one
reproduces the most claims (reading (a) of ``reports/calibration.md``).
"""
from __future__ import annotations

from ..base._validate import WrongType
from .params import DEFAULT_B, DEFAULT_EC, Params

_TABLE = {
    #         kh     G    Bh    BT    f    Rr   what the paper shows
    "fig4": (10.0, 0.0, 0.0, 0.0, 0.0, 0.0,
             "very weak impacts; X and Y response curves identical"),
    "fig5": (10.0, 0.3, 0.0, 0.0, 0.0, 0.0,
             "Y differs from X; rising part in (0.97, 1.12); double line near 1.2"),
    "fig6": (40.0, 0.3, 0.0, 0.0, 0.0, 0.0, "double line gone; chaotic motion near 1.2"),
    "fig7": (80.0, 0.3, 0.0, 0.0, 0.0, 0.0, "no considerable change from fig6"),
    "fig8": (120.0, 0.3, 0.0, 0.0, 0.0, 0.0,
             "two bottom impacts at 1.185; chaos in (1.21, 1.29)"),
    "fig9": (120.0, 0.3, 0.05, 0.0, 0.0, 0.0, "insignificant change from fig8"),
    "fig10": (120.0, 0.3, 0.0, 0.05, 0.0, 0.0,
              "chaos at 1.2 on the whole circle; period 3 with 8 impacts near 1.40"),
    "fig11": (120.0, 0.3, 0.0, 0.0, 0.05, 0.0,
              "period 6 with 8 bottom impacts in 1.05-1.07; period 10 in 1.3-1.33"),
    "rr10": (120.0, 0.3, 0.0, 0.0, 0.05, 10.0, "shaft radius 10 x clearance: like fig11"),
}

#: the preset used when none is named
DEFAULT = "fig8"
#: rotor speed of a preset until changed (resonance: the rotor reaches the retainer)
DEFAULT_ETA = 1.0


def paper_names() -> list[str]:
    """Names of the paper's presets (the rotor's), in figure order."""
    return list(_TABLE)


def paper_values(name: str) -> dict:
    """The rotor parameters of the paper's preset ``name`` as ``{name: value}``."""
    kh, G, Bh, BT, f, Rr, _ = _TABLE[name]
    return dict(B=DEFAULT_B, k3=-0.002, kh=kh, Bh=Bh, BT=BT, f=f, Rr=Rr, Ec=DEFAULT_EC, G=G,
                eta=DEFAULT_ETA)


def _others():
    """``{preset: model}`` of the presets of the built-in models other than the rotor."""
    from .. import models

    return {name: model for mname in models.names() if mname != "rotor"
            for model in (models.get(mname),) for name in model.presets}


def names() -> list[str]:
    """Names of all presets: the paper's in figure order, then those of the other built-in
    models."""
    return list(_TABLE) + [n for n in _others() if n not in _TABLE]


def describe(name: str) -> str:
    """One line on what a preset shows."""
    if isinstance(name, str) and name not in _TABLE and name in _others():
        return _others()[name].presets[name][1]
    return _row(name)[6]


def _row(name):
    if not isinstance(name, str):
        raise WrongType(f"name must be a preset's name (str), got {type(name).__name__}")
    if name not in _TABLE:
        raise ValueError(f"unknown preset {name!r}; choose from {', '.join(names())}")
    return _TABLE[name]


def get(name: str = DEFAULT) -> object:
    """The parameter set of a preset: :class:`~vibimpact.Params` for the paper's, the
    model's own parameter set for another built-in model's.

    ``B`` and ``Ec`` of the paper's presets are our defaults, not values from the paper
    (see the module docstring).

    Raises
    ------
    ValueError
        For an unknown preset name.
    """
    if isinstance(name, str) and name not in _TABLE:
        others = _others()
        if name in others:
            model = others[name]
            return model.param_set(**model.presets[name][0])
    _row(name)
    return Params(**paper_values(name))
