"""Cases of :mod:`reliability` that are requests, not faults: requests refused before
any computing, continuations from a parameter's bound, refusals that must speak the
command line's words, and user models that lie about their sizes (with the pattern of
API words a command's line must not use)."""
import re

#: continuations that start on a parameter's bound (0 in every preset) or run down to it:
#: they must run (exit 0) and write their branch
BOUNDS = {
    f"continue --param {name} from 0": ["continue", "--eta", "1.12", "--approach", "1.1",
                                        "--param", name, "--stop", "0.1", "--max-points",
                                        "12", "-o", "br.nc"]
    for name in ("BT", "f", "Bh", "Rr")}
BOUNDS["continue --param B down to 0"] = ["continue", "--eta", "1.12", "--approach", "1.1",
                                          "--param", "B", "--stop", "0", "-o", "br.nc"]

#: refusals whose line must name the command line's options: (arguments, output made
#: beforehand; a trailing '/' makes a directory)
WORDING = {
    "simulate over an existing file": (["simulate", "--eta", "1.2", "-o", "s.nc"], "s.nc"),
    "classify over an existing file": (["classify", "--eta", "1.0:1.02:0.01", "-o", "c.nc"],
                                       "c.nc"),
    "bifurcation over an existing image": (["bifurcation", "--eta", "1.0:1.02:0.01", "-o",
                                            "b.png"], "b.png"),
    "map over an existing store": (["map", "--eta", "1.0:1.02:0.01", "--vary", "kh=50,60",
                                    "-o", "m.zarr"], "m.zarr"),
    "continue over an existing file": (["continue", "--eta", "1.12", "--stop", "1.13", "-o",
                                        "br.nc"], "br.nc"),
    "classify beside an interrupted checkpoint": (["classify", "--eta", "1.0:1.02:0.01",
                                                   "-o", "c.nc"], "c.nc.partial/"),
}

#: words of the Python API that a command line message must not use
API_WORDS = re.compile(r"\b\w+=(True|False|None)\b|\bpass \w+=|\bkeyword\b|"
                       r"\b(ValueError|TypeError|KeyError)\b")

#: user models that lie about their sizes, or cannot be compiled into the kernel: each
#: must be refused (the snippet exits 0 printing the error) before the kernel runs it
USER_MODEL = '''
import math, sys
import numpy as np
from numba import njit
import vibimpact as vi

@njit
def rhs(s, y, p, mode, out):
    out[0] = y[1]
    out[1] = p[4] * math.cos(p[5] * s) - p[0] * y[1] - p[1] * y[0] - p[2] * y[0] ** 3

@njit
def jac(s, y, p, mode, J):
    J[0, 0] = 0.0; J[0, 1] = 1.0; J[1, 0] = -p[1] - 3 * p[2] * y[0] ** 2; J[1, 1] = -p[0]

@njit
def switches(s, y, p, mode, g):
    g[0] = y[1]

@njit
def transition(s, y, p, mode, which):
    return

@njit
def init_mode(s, y, p, mode):
    mode[0] = 0

def plain(s, y, p, mode, out):
    out[0] = y[1]

kw = dict(rhs=rhs, jac=jac, switches=switches, transition=transition, init_mode=init_mode,
          terminal=[0], state_names=("x", "v"), param_names=("d", "a", "b", "u", "g", "w"),
          omega_index=5, n_mode=1)
kw.update(CHANGES)
p = np.array([0.1, 1.0, 0.05, 0.0, 0.5, 0.9])[:len(kw["param_names"])]
try:
    model = vi.Model.from_functions("duffing", **kw)
    run = ENTRY
except (TypeError, ValueError) as exc:
    print(f"refused: {type(exc).__name__}: {exc}")
    sys.exit(0)
print(f"ran: {run!r}"[:300])
sys.exit(3)
'''
USER_MODEL_CASES = {
    "state declared too small (simulate)": ('dict(state_names=("x",))',
                                            "vi.simulate(p, periods=20, model=model).status"),
    "state declared too small (Lyapunov)": (
        'dict(state_names=("x",))',
        "vi.analysis.lyapunov_spectrum(vi.System(p, model=model)).exponents"),
    "state declared too small (sweep)": ('dict(state_names=("x",))',
                                         "vi.sweep(vi.System(p, model=model), [0.9, 1.0])"),
    "n_mode = 0": ("dict(n_mode=0)", "vi.simulate(p, periods=20, model=model).status"),
    "parameters declared too few": (
        'dict(param_names=("d", "a", "b", "u", "g"), omega_index=4)',
        "vi.simulate(p, periods=20, model=model).status"),
    "omega_index -1": ("dict(omega_index=-1)", "vi.simulate(p, periods=20, model=model)"),
    "omega_index 6": ("dict(omega_index=6)", "vi.simulate(p, periods=20, model=model)"),
    "a plain Python rhs": ("dict(rhs=plain)", "vi.simulate(p, periods=20, model=model)"),
    "a complex state0": ("dict()", "vi.simulate(p, periods=2, model=model, "
                                   "state0=[1j, 0.0]).strobe"),
}


#: requests that must be refused before any computing (one line, exit 2, no file)
BAD = {
    "--dense 1000000000": ["simulate", "--eta", "1.2", "--dense", "1000000000", "-o", "s.nc"],
    "--blocks 1e20": ["classify", "--eta", "1.0:1.02:0.01", "--blocks",
                      "99999999999999999999", "-o", "c.nc"],
    "-o r.nc/": ["simulate", "--eta", "1.2", "-o", "r.nc/"],
    "-o ''": ["simulate", "--eta", "1.2", "-o", ""],
    "-o 240-character name": ["simulate", "--eta", "1.2", "-o", "r" * 240 + ".nc"],
    "-o dangling symlink": ["simulate", "--eta", "1.2", "-o", "dangling.nc"],
    "-o /dev/full --overwrite": ["simulate", "--eta", "1.2", "-o", "/dev/full",
                                 "--overwrite"],
    "--set kh twice": ["simulate", "--eta", "1.2", "--set", "kh=10", "--set", "kh=200",
                       "-o", "s.nc"],
    # a speed of 1e300 is one point labelled diverged, as --eta 1e300 is (exit 0 or 2:
    # either way without numpy's overflow warnings)
    "--eta 1e300:1e300:1": ["classify", "--eta", "1e300:1e300:1", "-o", "c.nc"],
    "--eta step 1.5e-13": ["classify", "--eta", "1:1.00000001:1.5e-13", "-o", "c.nc"],
    "map --scheduler foo://bar": ["map", "--eta", "1.0:1.02:0.01", "--vary", "kh=50,60",
                                  "--scheduler", "foo://bar", "-o", "m.zarr"],
    "map --scheduler a directory": ["map", "--eta", "1.0:1.02:0.01", "--vary", "kh=50,60",
                                    "--scheduler", ".", "-o", "m.zarr"],
}


#: cases of :data:`BAD` that may also run (exit 0) as long as they say nothing misleading
RUNS = ("--eta 1e300:1e300:1",)
