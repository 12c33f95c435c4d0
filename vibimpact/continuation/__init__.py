"""Studies along a curve of solutions: a branch of periodic orbits continued in one
parameter (``branches``: follow, refine, write as a dataset) and bifurcation curves
continued in two (``curves``), built on the analysers' continuation
(:func:`vibimpact.analysis.continue_orbit`, :func:`vibimpact.analysis.continue_bifurcation`).
"""
