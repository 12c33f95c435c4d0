"""Every attractor, not only the one a sweep lands on: the attractor census
(:func:`attractors`), its starting states (:mod:`.starts`), the library of found
attractors (:mod:`.library`), the census dataset (:mod:`.dataset`) and which of its
attractors a sweep followed (:func:`locate`)."""
from .census import attractors
from .locate import locate
from .reach import CensusSettings
from .starts import Box, default_box, grid_starts, random_starts

__all__ = ["attractors", "locate", "CensusSettings", "Box", "default_box", "grid_starts",
           "random_starts"]
