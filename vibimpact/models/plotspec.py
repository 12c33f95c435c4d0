"""What a model's plots, tables and files call things: :class:`PlotSpec`, declared by
each model (:attr:`vibimpact.models.Model.plot`) and read by :mod:`vibimpact.plotting`,
the tables of the command line and the words of the files
(:mod:`vibimpact.models.words`)."""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field


@dataclass(frozen=True)
class PlotSpec:
    """What plots and tables of a model show: the model's own names for them.

    Parameters
    ----------
    xy : tuple of str
        The two states drawn against each other (``("X", "Y")`` for the built-in rotor).
    circle : float, optional
        Radius of a circular obstacle centred at the origin, drawn with the orbit (the
        built-in rotor's retainer: 1); None: none.
    circle_label : str
        The circle's entry in the legend of an XY plot.
    circle_name : str
        What the circle's radius is, in the legend of a response plot (its line there).
    y_down : bool
        The second state points down (along gravity): XY plots invert that axis.
    y_note : str
        Added to the second axis's label of an XY plot (``"+Y down, along gravity"``).
    length_unit : str, optional
        The unit of the model's lengths, in axis labels (the built-in rotor's
        ``"clearance"``); None: lengths are dimensionless numbers.
    symbols : mapping
        ``{parameter name: symbol}`` for labels and titles (``{"eta": "η"}``); a parameter
        not in it is shown by its name.
    title : tuple of str
        Parameters a figure's title always shows (the forcing frequency besides, in a
        run's figure).
    title_nonzero : tuple of str
        Parameters a title shows where they are not 0.
    title_hidden : tuple of str
        Parameters a title never shows.  Those in none of the three are shown after the
        others (a model with no declaration: all of them).
    preset_columns : tuple of str
        The parameters ``vibimpact presets`` tabulates for the model's presets, one column
        each; empty: its presets are listed with all their values.
    preset_marked : tuple of str
        Columns marked ``*`` in that table, explained by ``preset_note``.
    preset_note : str
        A note printed under the model's table of presets.
    frequency_text : str
        What the forcing frequency is, in words: the ``long_name`` of a file's frequency
        coordinate; empty: ``"forcing frequency NAME"``.
    obstacle : str
        What the contact meets, in files' words (``"retainer"``; "loaded arcs of the
        retainer").
    angle_text : str
        What the contact angle is and how it runs, in files' words; empty: "the
        contact angle".
    time_name : str
        The name of the model's time in files' words (``"tau"``: "per unit tau").
    """

    xy: tuple
    circle: float | None = None
    circle_label: str = "obstacle"
    circle_name: str = "obstacle"
    y_down: bool = False
    y_note: str = ""
    length_unit: str | None = None
    symbols: Mapping = field(default_factory=dict)
    title: tuple = ()
    title_nonzero: tuple = ()
    title_hidden: tuple = ()
    preset_columns: tuple = ()
    preset_marked: tuple = ()
    preset_note: str = ""
    frequency_text: str = ""
    obstacle: str = "obstacle"
    angle_text: str = ""
    time_name: str = "time"

    def symbol(self, name: str) -> str:
        """How labels write parameter ``name``."""
        return self.symbols.get(name, name)

    def title_params(self, names) -> list[str]:
        """The parameters of ``names`` a title may show, in order: :attr:`title`, then
        :attr:`title_nonzero`, then the others not hidden (the caller leaves out a
        ``title_nonzero`` one that is 0)."""
        shown = [n for n in self.title + self.title_nonzero if n in names]
        return shown + [n for n in names if n not in shown and n not in self.title_hidden]
