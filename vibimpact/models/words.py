"""A model's words in the files it writes: the pieces of the ``long_name`` texts that
differ from one model to another, from what the model declares
(:class:`~vibimpact.models.PlotSpec`, :class:`~vibimpact.models.contact.Contact`), never
another model's.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:  # names of the annotations only
    from . import Model


def file_words(model: Model | None) -> dict[str, str]:
    """The words a file of ``model`` uses, for ``str.format`` templates.

    Returns
    -------
    dict
        ``obstacle`` (what the contact meets), ``unit`` (``" / UNIT"`` after a length,
        or ``""``), ``x`` and ``y`` (the names of the contact's two positions, else of
        the first two states), ``time`` (the name of the model's time), ``freq`` (the
        name of its forcing frequency), ``angle`` (what the contact angle is).  With no
        model: neutral words.
    """
    spec = getattr(model, "plot", None)
    names = tuple(getattr(model, "state_names", ()) or ("x0", "x1"))
    contact = getattr(model, "contact", None)
    cols = tuple(contact.positions) if contact is not None else (0, 1)
    pos = [names[i] for i in cols if i < len(names)] + list(names[:2])
    unit = getattr(spec, "length_unit", None)
    return dict(
        obstacle=getattr(spec, "obstacle", None) or "obstacle",
        unit=f" / {unit}" if unit else "",
        x=pos[0], y=pos[1] if len(pos) > 1 else pos[0],
        time=getattr(spec, "time_name", None) or "time",
        freq=(model.frequency_name if model is not None else "the forcing frequency"),
        angle=getattr(spec, "angle_text", None) or "the contact angle")

