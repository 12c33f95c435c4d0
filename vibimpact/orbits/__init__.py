"""The orbit hunt: periodic orbits of the stroboscopic map, stable or not, by multi-start
Newton shooting, each with its Floquet multipliers, impacts and contact arcs, and the
intervals of the forcing frequency where it exists and where it is stable.

* :func:`hunt_orbits` -- the hunt (:mod:`.hunt`), seeds from the user and random states
  (:mod:`.seeds`), continuation of each orbit (:func:`orbit_extent`, :mod:`.extent`);
* :func:`hunt_to_dataset`, :func:`write_orbits`, :func:`read_orbits` -- the result as a
  self-describing ``xarray.Dataset`` and NetCDF file (:mod:`.dataset`);
* :func:`find_orbit` -- questions over such a dataset ("is there a stable P6 with 8
  impacts on 1.05-1.07?"), answered with the evidence either way (:mod:`.query`).
"""
from .dataset import hunt_to_dataset, is_orbit_dataset, read_orbits, write_orbits
from .extent import orbit_extent
from .found import Extent, FoundOrbit, OrbitHunt
from .hunt import hunt_orbits, same_orbit
from .query import OrbitAnswer, find_orbit
from .seeds import random_seeds, seed_box, seeds_from_dataset

__all__ = ["hunt_orbits", "orbit_extent", "same_orbit", "random_seeds", "seed_box",
           "seeds_from_dataset", "hunt_to_dataset", "write_orbits", "read_orbits",
           "is_orbit_dataset", "find_orbit", "OrbitAnswer", "Extent", "FoundOrbit",
           "OrbitHunt"]
