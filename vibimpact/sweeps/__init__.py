"""Frequency sweeps: per-point analysis, continuation in blocks (run by
:mod:`vibimpact.engine`), datasets and the labelled interval map."""
from .dataset import format_intervals, intervals, sweep_params, to_dataset
from ..points.point import ANALYSES, SweepSettings, analyse_point
from .start import SweepStart, sweep_start
from .sweep import DIRECTIONS, continued_state, parse_range, sweep

__all__ = ["ANALYSES", "DIRECTIONS", "SweepSettings", "analyse_point", "continued_state",
           "format_intervals",
           "intervals", "parse_range", "sweep", "SweepStart", "sweep_params", "sweep_start",
           "to_dataset"]
