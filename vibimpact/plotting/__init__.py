"""Figures drawn from datasets made by :mod:`vibimpact.io` and :func:`vibimpact.sweep`.

Every function takes an ``xarray.Dataset`` (:func:`plot_xy` also a
:class:`~vibimpact.Run`, drawn from :meth:`~vibimpact.Run.to_dataset`) and draws with
matplotlib's object API (a :class:`matplotlib.figure.Figure` rendered by Agg), so the
global pyplot state and the interactive backend are never touched.  Each takes ``figsize``, ``dpi``
and ``style``
(``"paper"``: a journal's look), checked and applied by :mod:`vibimpact.plotting.style`.
"""
from .bifurcation import plot_bifurcation
from .lyapunov_plot import plot_lyapunov
from .poincare import plot_poincare
from .response import plot_intervals, plot_response
from .style import save_figure
from .xy import plot_xy

__all__ = ["plot_bifurcation", "plot_intervals", "plot_lyapunov", "plot_poincare",
           "plot_response", "plot_xy", "save_figure"]
