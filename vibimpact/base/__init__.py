"""The bottom layer: vocabulary every other layer may use, importing no vibimpact module
above it and none of numpy, numba, xarray or matplotlib at import.

Argument checks (``_validate``), number parsing and counted words (``_text``), limits on
sizes and run times (``_limits``), fill values (``_fill``), bounded JSON and regular
files read from disk (``_json``, ``_regular``), signal-safe file writes (``_writing``),
the kinds of bifurcation (``bifurcation_kinds``) and a file's provenance attributes
(``provenance``).
"""
