"""One parameter point: its transient settled, then measured, as a typed result.

* :mod:`~vibimpact.points.transient` -- ``settle``: the transient, with extrapolation
  jumps, shooting and the settled tests (:mod:`~vibimpact.points.settle`);
* :mod:`~vibimpact.points.measure` -- ``measure``: the analyses a request asks for;
* :mod:`~vibimpact.points.point` -- ``analyse_point`` = settle + measure ->
  :class:`~vibimpact.points.point.PointResult`, and the request's
  :class:`~vibimpact.points.point.SweepSettings`;
* :mod:`~vibimpact.points.predict` -- the continuation predictor of the next point;
* :mod:`~vibimpact.points.pipeline` -- ``classify_params``: one point, classified.

Sweeps and maps (:mod:`vibimpact.sweeps`, :mod:`vibimpact.maps`) run this pipeline at every
grid point through the engine (:mod:`vibimpact.engine`), which sits above it.
"""
from .pipeline import classify_params
from .point import ANALYSES, PointResult, SweepSettings, analyse_point

__all__ = ["ANALYSES", "PointResult", "SweepSettings", "analyse_point", "classify_params"]
