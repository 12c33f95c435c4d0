"""The kernel compiled ahead of time, at install time, and the choice of it at run time.

Compiling the integration loop with numba takes most of a first run (about 10 to 15 s on
a 2-core machine; the disk cache makes later runs fast).  Installing the package therefore
compiles the functions a rotor run needs -- the integration loop for the rotor and its
variational equations, the rotor's initial mode and the small array routines of the
analyses -- into an extension module, ``vibimpact._kernel._aot`` (numba's ahead-of-time
compiler, :mod:`numba.pycc`, driven by :mod:`.aot_build` from ``setup.py``).  Beside the
module a JSON file records what it was built from.

At run time :func:`routine` gives, for each of these functions, a callable that runs the
precompiled code when

* the module was built (the build is optional: without a C compiler the install goes on
  and numba compiles on first use, as before),
* the kernel's sources are the ones it was built from (:func:`.cache_guard.sources_digest`),
* numba and llvmlite are the versions that built it and the processor is the one it was
  built for (the code is the code numba's JIT would generate here: the same bits), and
* the arguments have exactly the types it was compiled for (numba's type fingerprint of
  the arguments; a precompiled function does not check its arguments itself),

and numba's JIT-compiled function otherwise.  Neither checks array sizes or indices:
every call is checked first by :mod:`.argcheck` (the array routines by the
:class:`Routine` itself, the integration loop where :mod:`.boundary` builds its
arguments), and a wrong shape, dtype or memory order is a ``ValueError``.
``VIBIMPACT_PRECOMPILED=0`` turns it off.
Which of the two runs never changes a number: both are the same numba code compiled by
the same compiler for the same processor.
"""
from __future__ import annotations

import importlib.util
import json
import logging
import os

from .argcheck import ROUTINES
from .cache_guard import current_digest
from .dispatch import BuiltinModel

try:  # numba's own type fingerprint of call arguments (what its dispatcher keys on)
    from numba._dispatcher import compute_fingerprint
except ImportError:  # a numba without it: the precompiled kernel is not used
    compute_fingerprint = None

log = logging.getLogger("vibimpact")

#: the extension module's name, in this package
MODULE = "_aot"
#: environment variable that turns the precompiled kernel off when set to 0
ENV = "VIBIMPACT_PRECOMPILED"

_state = None


def metadata_path(so_path):
    """The JSON file beside the extension module ``so_path``."""
    return str(so_path) + ".json"


def host():
    """The processor numba compiles for here: ``{"cpu": name, "features": str}``."""
    from llvmlite import binding as llb

    return {"cpu": llb.get_host_cpu_name(), "features": llb.get_host_cpu_features().flatten()}


def versions():
    """The compiler versions the precompiled code depends on."""
    import llvmlite
    import numba

    return {"numba": numba.__version__, "llvmlite": llvmlite.__version__}


def mismatch(meta):
    """Why a module described by ``meta`` (its JSON description) must not be used here,
    or None: other kernel sources, other compiler versions or another processor."""
    if not isinstance(meta, dict):
        return "its description is not a JSON object"
    if meta.get("sources") != current_digest():
        return "built from other kernel sources (reinstall the package to rebuild it)"
    if meta.get("versions") != versions():
        return f"built with {meta.get('versions')}, running {versions()}"
    if meta.get("host") != host():
        cpu = meta.get("host", {}).get("cpu") if isinstance(meta.get("host"), dict) else None
        return f"built for another processor ({cpu!r}, this one is {host()['cpu']!r})"
    return None


def _load():
    """``(module, exports, reason)``: the extension module and its export table, or
    ``(None, {}, why not)``."""
    if os.environ.get(ENV, "1").strip() == "0":
        return None, {}, f"turned off ({ENV}=0)"
    spec = importlib.util.find_spec(f"{__package__}.{MODULE}")
    if spec is None or spec.origin is None:
        return None, {}, "not built (numba compiles the kernel on first use)"
    try:
        with open(metadata_path(spec.origin)) as fh:
            meta = json.load(fh)
    except (OSError, ValueError) as exc:
        return None, {}, f"its description is unreadable ({exc})"
    reason = mismatch(meta)
    if reason is not None:
        return None, {}, reason
    if compute_fingerprint is None:
        return None, {}, "this numba has no type fingerprint of arguments to check calls with"
    try:
        module = importlib.import_module(f"{__package__}.{MODULE}")
    except ImportError as exc:
        return None, {}, f"cannot be loaded ({exc})"
    exports = {}
    for name, entry in meta.get("exports", {}).items():
        fn = getattr(module, name, None)
        if fn is not None:
            exports[name] = (fn, entry.get("family"), bytes.fromhex(entry["fingerprint"]))
    return module, exports, "loaded"


def state():
    """``(exports, reason)``, loaded once per process."""
    global _state
    if _state is None:
        _state = _load()[1:]
        log.debug("precompiled kernel: %s", _state[1])
    return _state


def status():
    """Why the precompiled kernel is used or not (one line, for reports and ``-vv``)."""
    return state()[1]


def available(name):
    """Whether the precompiled ``name`` is loaded."""
    return name in state()[0]


def key(args, family):
    """numba's type fingerprint of ``args`` (bytes), or None when it has none.

    ``family`` (a built-in model family) means the first argument is the kernel's
    ``(model, ...)`` tuple: its model must be a built-in model of that family and is left
    out of the fingerprint (numba has none for it)."""
    try:
        if family is not None:
            lead = args[0]
            model = lead[0]
            if type(model) is not BuiltinModel or model.family != family:
                return None
            args = (lead[1:],) + tuple(args[1:])
        return compute_fingerprint(args)
    except (ValueError, TypeError, NotImplementedError, IndexError):
        return None


class Routine:
    """A kernel function that runs its precompiled version where it can (see the
    module's docstring) and its numba dispatcher ``jit`` otherwise.

    Attribute access falls through to the dispatcher (``.py_func``, ``.signatures``).
    """

    __slots__ = ("name", "jit", "check", "_aot")

    def __init__(self, name, jit):
        self.name = name
        self.jit = jit
        # the shapes and sizes its loops use (neither version checks indices)
        self.check = ROUTINES.get(name)
        self._aot = False  # not looked up yet

    def _precompiled(self):
        if self._aot is False:
            self._aot = state()[0].get(self.name)
        return self._aot

    def pick(self, args):
        """The function that runs for ``args``: the precompiled one or the dispatcher."""
        aot = self._precompiled()
        if aot is not None:
            fn, family, fingerprint = aot
            if key(args, family) == fingerprint:
                return fn
        return self.jit

    def __call__(self, *args):
        if self.check is not None:
            self.check(*args)
        return self.pick(args)(*args)

    def __getattr__(self, attr):
        if attr in Routine.__slots__:  # not set yet (unpickling)
            raise AttributeError(attr)
        return getattr(self.jit, attr)

    def __reduce__(self):
        return routine, (self.name, self.jit)

    def __repr__(self):
        return f"Routine({self.name!r})"


def routine(name, jit):
    """The :class:`Routine` of the kernel function ``jit`` exported as ``name``."""
    return Routine(name, jit)
