"""The bottom layer: vocabulary every other layer may use.  It imports nothing of the
package outside this folder but the package's ``__version__`` (``provenance``), and none
of numba, xarray or matplotlib (``_validate`` and ``_fill`` import numpy).

Argument checks (``_validate``), number parsing and counted words (``_text``), limits on
sizes and run times (``_limits``), fill values (``_fill``), bounded JSON and regular
files read from disk (``_json``, ``_regular``), signal-safe file writes (``_writing``),
the kinds of bifurcation (``bifurcation_kinds``) and a file's provenance attributes
(``provenance``).
"""
