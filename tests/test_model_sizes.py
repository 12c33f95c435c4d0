"""A user model's declared sizes are checked against what its functions read and write,
before the kernel runs them (vibimpact.models.model_probe), and its construction refuses
arguments the kernel cannot take."""
import math

import numpy as np
import pytest
from numba import njit

import vibimpact as vi

from test_user_model import _linear, _rhs


@njit
def _duffing_rhs(s, y, p, mode, out):
    out[0] = y[1]
    out[1] = p[4] * math.cos(p[5] * s) - p[0] * y[1] - p[1] * y[0] - p[2] * y[0] ** 3


@njit
def _duffing_jac(s, y, p, mode, J):
    J[0, 0] = 0.0
    J[0, 1] = 1.0
    J[1, 0] = -p[1] - 3.0 * p[2] * y[0] ** 2
    J[1, 1] = -p[0]


@njit
def _observer(s, y, p, mode, g):
    g[0] = y[1]


@njit
def _no_transition(s, y, p, mode, which):
    return


@njit
def _mode0(s, y, p, mode):
    mode[0] = 0


@njit
def _no_mode(s, y, p, mode):
    return


P6 = np.array([0.1, 1.0, 0.05, 0.0, 0.5, 0.9])
NAMES6 = ("d", "a", "b", "unused", "g", "w")


def _model(**changes):
    """The forced Duffing oscillator as a user model, with some of its pieces changed."""
    kw = dict(name="duffing", rhs=_duffing_rhs, jac=_duffing_jac, switches=_observer,
              transition=_no_transition, init_mode=_mode0, terminal=[0],
              state_names=("x", "v"), param_names=NAMES6, omega_index=5, n_mode=1)
    kw.update(changes)
    return vi.Model.from_functions(**kw)


@pytest.mark.slow
def test_a_model_of_the_right_sizes_runs_and_its_probe_changes_nothing():
    """The probe accepts a model whose functions stay inside the declared arrays (the
    linear oscillator of tests/test_user_model.py, whose kernel is compiled once for
    both files), and a run after it equals a run of a fresh model object (the probe
    leaves no state)."""
    p = np.array([0.3, 1.0, 0.5, 1.7])
    a = vi.simulate(p, periods=5, model=_linear(_rhs))
    b = vi.simulate(p, periods=5, model=_linear(_rhs))
    assert a.ok and np.all(np.isfinite(a.strobe))
    np.testing.assert_array_equal(a.strobe, b.strobe)


def test_a_state_declared_too_small_is_refused_before_the_kernel_writes_past_it():
    """The issue's reproducer: the Duffing right-hand side writes out[1] but the model
    declares one state entry.  simulate refuses it naming rhs, out[1] and state_names
    (the kernel ran it before and returned rows of zeros)."""
    model = _model(state_names=("x",))
    with pytest.raises(ValueError, match=r"rhs writes out\[1\].*state_names"):
        vi.simulate(P6, periods=20, model=model)


@pytest.mark.parametrize("entry", ["simulate", "monodromy", "lyapunov", "sweep",
                                   "shooting"])
def test_every_way_into_the_kernel_probes_the_model_first(entry):
    """Not only simulate: every analysis that runs the kernel on a user model (the
    monodromy's variational run, the Lyapunov spectrum, a sweep, shooting) refuses the
    model that lies about its state size, with the same message, and again on a second
    call (a failed probe is not remembered as passed)."""
    from vibimpact.analysis import Averaging, lyapunov_spectrum, shoot_periodic_orbit

    model = _model(state_names=("x",))
    system = vi.System(P6, model=model)
    calls = {
        "simulate": lambda: system.simulate(periods=3),
        "monodromy": lambda: system.monodromy(np.zeros(1), 1),
        "lyapunov": lambda: lyapunov_spectrum(system, averaging=Averaging(
            transient=2, min_periods=4, max_periods=4)),
        "sweep": lambda: vi.sweep(system, [0.9, 0.95]),
        "shooting": lambda: shoot_periodic_orbit(system, np.zeros(1)),
    }
    for _ in range(2):
        with pytest.raises(ValueError, match=r"model 'duffing': rhs writes out\[1\]"):
            calls[entry]()


@njit
def _rhs_contact_only(s, y, p, mode, out):
    out[0] = y[1]
    out[1] = -y[0]
    if abs(y[0]) > 2.0:  # a 'contact' branch that writes a third entry
        out[2] = 1.0


@njit
def _mode_writer(s, y, p, mode):
    mode[0] = 1


@njit
def _rhs_reads_y2(s, y, p, mode, out):
    out[0] = y[1]
    out[1] = -y[0] + 0.0 * y[2] + (y[2] if y[2] > 1e300 else 0.0)


@njit
def _rhs_reads_mode1(s, y, p, mode, out):
    out[0] = y[1]
    out[1] = -y[0] - 1e-9 * mode[1]


@njit
def _jac_3x3(s, y, p, mode, J):
    for i in range(3):
        for j in range(3):
            J[i, j] = 0.0


@njit
def _two_switches(s, y, p, mode, g):
    g[0] = y[1]
    g[1] = y[0]


@njit
def _transition_writes_mode1(s, y, p, mode, which):
    mode[1] = 1


CASES = {
    # case: (changes, pattern the message must match)
    "write only in a contact branch": (dict(rhs=_rhs_contact_only),
                                       r"rhs writes out\[2\]"),
    "n_mode 0, init_mode writes mode[0]": (dict(init_mode=_mode_writer, n_mode=0),
                                           r"init_mode writes mode\[0\].*n_mode=0"),
    "parameters declared too few": (dict(param_names=NAMES6[:5], omega_index=4),
                                    r"reads past p.*5 parameters"),
    "reads a state entry it does not declare": (dict(rhs=_rhs_reads_y2),
                                                r"rhs reads past y.*2 state entries"),
    "reads a mode entry it does not declare": (dict(rhs=_rhs_reads_mode1),
                                               r"rhs reads past mode"),
    "Jacobian larger than the state": (dict(jac=_jac_3x3), r"jac writes J\[2, 0\]"),
    "more switches than terminal lists": (dict(switches=_two_switches),
                                          r"switches writes g\[1\].*terminal has 1"),
    "transition writes past the mode": (dict(transition=_transition_writes_mode1,
                                             terminal=[1]),
                                        r"transition writes mode\[1\].*n_mode=1"),
}


@pytest.mark.parametrize("case", list(CASES))
def test_functions_that_read_or_write_past_the_declared_arrays_are_refused(case):
    """Each way a model can lie about a size -- state, parameters, modes (also 0 modes),
    Jacobian, switching functions; in the right-hand side, the Jacobian, the switches,
    init_mode or a transition; a write reached only in a contact branch; reads as well as
    writes -- is a ValueError naming the function and the array, raised before any
    kernel call."""
    changes, pattern = CASES[case]
    p = P6[:5].copy() if "param_names" in changes else P6
    if "param_names" in changes:
        p[4] = 0.9
    with pytest.raises(ValueError, match=pattern):
        vi.simulate(p, periods=3, model=_model(**changes))


def _plain_rhs(s, y, p, mode, out):
    out[0] = y[1]


@pytest.mark.parametrize("arg", ["rhs", "jac", "switches", "transition", "init_mode"])
def test_a_plain_python_function_is_a_type_error_saying_it_must_be_compiled(arg):
    """A function not compiled with numba (a plain Python function, or not a function)
    is a TypeError naming the argument and numba, at construction, not numba's
    TypingError deep inside the kernel."""
    with pytest.raises(TypeError, match=rf"^{arg} must be compiled with numba.*plain"):
        _model(**{arg: _plain_rhs})
    with pytest.raises(TypeError, match=rf"^{arg} must be compiled with numba"):
        _model(**{arg: 3})


@pytest.mark.parametrize("value, error", [(6, ValueError), (-1, ValueError),
                                          (100, ValueError), (True, TypeError),
                                          (5.0, TypeError), ("5", TypeError)])
def test_omega_index_outside_the_parameter_vector_is_refused_naming_it(value, error):
    """An omega_index outside 0..len(param_names)-1 -- past the end, negative (which
    Python would count from the end), or not an integer -- is refused naming
    omega_index (an IndexError, or silently accepted when negative, before)."""
    with pytest.raises(error, match="omega_index"):
        _model(omega_index=value)


@pytest.mark.parametrize("changes, name", [
    (dict(state_names="xv"), "state_names"), (dict(state_names=()), "state_names"),
    (dict(state_names=("x", "x")), "state_names"), (dict(param_names=(1, 2)), "param_names"),
    (dict(terminal=[2]), "terminal"), (dict(terminal=[]), "terminal"),
    (dict(n_mode=-1), "n_mode"), (dict(n_mode=1.5), "n_mode"), (dict(bound=0.0), "bound"),
    (dict(name=""), "name")])
def test_declarations_the_kernel_cannot_take_are_refused_naming_them(changes, name):
    """Sizes and flags the kernel would misread (a string of state names, no or repeated
    names, a terminal flag other than 0/1, a negative or fractional mode count, a
    non-positive bound) are refused at construction, naming the argument."""
    with pytest.raises(ValueError, match=rf"^{name}"):
        _model(**changes)


@njit
def _rhs_untypable(s, y, p, mode, out):
    out[0] = y[1]
    out[1] = "text"


def test_a_function_that_does_not_compile_for_the_kernels_arguments_is_a_type_error():
    """A numba function that cannot be compiled for the arguments the kernel passes (it
    assigns a string to a float array) is a one-line TypeError naming the function and
    the signature, raised by the probe, not numba's multi-page TypingError from inside
    the kernel."""
    with pytest.raises(TypeError, match=r"^rhs does not compile for the kernel's "
                                        r"arguments \(s: float") as info:
        vi.simulate(P6, periods=3, model=_model(rhs=_rhs_untypable))
    assert "\n" not in str(info.value) and "\x1b" not in str(info.value)
