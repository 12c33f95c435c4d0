"""Every attractor, not only the one a sweep lands on: the attractor census
(:func:`attractors`), its starting states (:mod:`.starts`), the library of found
attractors (:mod:`.library`) and the census dataset (:mod:`.dataset`)."""
from .census import attractors
from .reach import CensusSettings
from .starts import Box, default_box, grid_starts, random_starts

__all__ = ["attractors", "CensusSettings", "Box", "default_box", "grid_starts",
           "random_starts"]
