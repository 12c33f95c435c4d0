"""Parameter maps: regime maps over eta and one other parameter, rows on the engine
(:func:`map2d`, :mod:`vibimpact.engine`) and map files (:mod:`vibimpact.maps.store`)."""
from ..engine.execution import DEFAULT_TASK_POINTS
from .map2d import MAP_ANALYSES, MAX_MAP_POINTS, map2d, parameter_names
from .store import open_map, write_map

__all__ = ["DEFAULT_TASK_POINTS", "MAP_ANALYSES", "MAX_MAP_POINTS", "map2d", "open_map",
           "parameter_names", "write_map"]
