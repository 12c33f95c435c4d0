"""
A model of your own
===================

The integrator is generic: a model is a set of numba functions — right-hand side,
Jacobian, switching functions, mode transitions and the initial mode — wrapped by
:meth:`vibimpact.Model.from_functions`.  Here: a forced linear oscillator hitting a soft
one-sided stop at ``x = d`` (an impact oscillator),

.. math::

   x'' + c x' + x + H(x - d)\\, k_s (x - d) = F \\cos \\omega t.

The stop makes the right-hand side switch at ``x = d``; the kernel locates each crossing
as an event and changes the mode there, so no step straddles the switch.
"""

# %%
# The model's functions
# ---------------------
# Every function receives the time ``s``, the state ``y``, the parameter vector ``p``
# and the discrete mode ``mode`` (here ``mode[0]``: 0 free, 1 on the stop).  A switching
# function is positive while the current mode is consistent; its crossing to negative
# values is an event.  Switch 0 (contact) is terminal and calls ``transition``; switch 1
# (the velocity) is an observer, logged only.
import math
import warnings

import matplotlib.pyplot as plt
import numpy as np
from numba import njit
from numba.core.errors import NumbaExperimentalFeatureWarning

import vibimpact as vi
from vibimpact.analysis import detect_period, shoot_periodic_orbit

# a user model is passed to the kernel as first-class functions, a numba feature that
# numba still calls experimental (and says so once per compiled function)
warnings.filterwarnings("ignore", category=NumbaExperimentalFeatureWarning)

C, KS, D, F, W = range(5)   # parameter vector: c, ks, d, F, w


@njit
def rhs(s, y, p, mode, out):
    out[0] = y[1]
    out[1] = p[F] * math.cos(p[W] * s) - p[C] * y[1] - y[0]
    if mode[0] == 1:
        out[1] -= p[KS] * (y[0] - p[D])


@njit
def jac(s, y, p, mode, J):
    J[0, 0] = 0.0
    J[0, 1] = 1.0
    J[1, 0] = -1.0 - (p[KS] if mode[0] == 1 else 0.0)
    J[1, 1] = -p[C]


@njit
def switches(s, y, p, mode, g):
    g[0] = (y[0] - p[D]) if mode[0] == 1 else (p[D] - y[0])
    g[1] = y[1]


@njit
def transition(s, y, p, mode, which):
    if which == 0:
        mode[0] = 1 - mode[0]


@njit
def init_mode(s, y, p, mode):
    mode[0] = 1 if y[0] > p[D] else 0


model = vi.Model.from_functions(
    "soft stop", rhs, jac, switches, transition, init_mode, terminal=[1, 0],
    state_names=("x", "v"), param_names=("c", "ks", "d", "F", "w"), omega_index=W)

# %%
# Simulate it
# -----------
# A user model takes its parameters as a plain vector.
params = np.array([0.1, 20.0, 1.0, 0.5, 1.0])
run = vi.simulate(params, periods=50, transient=200, model=model, dense=100)
print(run.status, "period", detect_period(run.strobe, tol=1e-6))
hits = run.events["which"] == 0
print(int(hits.sum()), "switches of the stop in 50 periods")

fig, ax = plt.subplots(figsize=(6, 4))
ax.plot(run.dense[:, 0], run.dense[:, 1], lw=0.8)
ax.axvline(params[D], color="k", ls="--", lw=0.8, label="stop x = d")
ax.plot(run.strobe[:, 0], run.strobe[:, 1], "o", ms=4, label="stroboscopic samples")
ax.set_xlabel("x")
ax.set_ylabel("x'")
ax.legend()

# %%
# The analysers work on it as on the rotor
# ----------------------------------------
# Wrapped in a :class:`vibimpact.System`, the model goes through shooting (the monodromy
# matrix from the variational equations, with a saltation matrix at every switch), the
# Lyapunov analysers and sweeps.
system = vi.System(params, model=model)
orbit = shoot_periodic_orbit(system, run.final_state, 1)
print("converged:", orbit.converged, " |mu|:", np.abs(orbit.multipliers).round(4))

w = vi.grid("0.8:1.3:0.02", name="w")
ds = vi.sweep(system, w, direction="up", analyses=("period",))
print(vi.intervals(ds).to_dataframe()[["start", "end", "label"]].to_string())
