"""Build the precompiled kernel (:mod:`.precompiled`): run by ``setup.py`` at install time.

``python -m vibimpact._kernel.aot_build [PATH]`` compiles the exported functions with
numba's ahead-of-time compiler (:mod:`numba.pycc`) for this processor into the extension
module ``PATH`` (by default ``_aot<suffix>`` beside this file) and writes the JSON
description :mod:`.precompiled` checks before using it.

Each export is compiled for the argument types of an *example call* built with the same
code that builds the real calls (:mod:`.boundary`), so that its signature is the one the
package calls it with; the description stores numba's type fingerprint of those
arguments, and a call with any other types runs the JIT-compiled function instead.
"""
from __future__ import annotations

import contextlib
import json
import os
import sys
import sysconfig
import time

import numpy as np


def _integrate_example():
    """A plain run of the rotor through :func:`.boundary.integrate`'s argument list (the
    Benettin mode and the variational rotor have the same types)."""
    from . import boundary as kb
    from . import dispatch, rotor
    from .driver import workspace

    n = 4
    problem = kb.Problem(dispatch.ROTOR, rotor.TERMINAL, rotor.N_MODE,
                         np.zeros(len(rotor.PARAM_NAMES)), 1.0, n_state=n)
    method = kb.Method.named("dop853")
    options = kb.Options(rtol=1e-9, atol=1e-12, h_fixed=0.01, max_step=0.1, bound=1e3,
                         event_tol=1e-12, max_steps_per_period=100_000)
    mode = np.zeros(rotor.N_MODE, dtype=np.int64)
    return kb.integrate_args(problem, method, options,
                             workspace(n, problem.terminal.size, mode.size), np.zeros(n),
                             mode, kb.new_clock(problem, options), 1, 0, np.empty((1, n)),
                             kb.EventLog(64, n, rotor.N_MODE).arrays(), 0,
                             np.empty((1, n)), kb.counters())


def exports():
    """``{name: (dispatcher, example arguments, model family or None)}``."""
    from . import boundary, driver, rotor

    out = {
        "integrate": (driver.integrate, _integrate_example(), "rotor"),
        "rotor_init_mode": (rotor.init_mode, (0.0, np.zeros(4), np.zeros(
            len(rotor.PARAM_NAMES)), np.zeros(rotor.N_MODE, dtype=np.int64)), None),
    }
    for routine, args in boundary.array_routine_calls():
        out[routine.name] = (routine.jit, args, None)
    return out


@contextlib.contextmanager
def _dispatcher_flags(options_by_func):
    """numba's AOT compiler compiles every export with one set of flags (the error model
    of Python, the runtime on) and for the features LLVM derives from the processor's
    name; compile each with its dispatcher's options instead (``error_model="numpy"``,
    ``_nrt``: :mod:`.jitopts`) and for the JIT's feature list of this processor, so that
    the precompiled code is the code the JIT compiles."""
    from numba.core.codegen import AOTCPUCodegen
    from numba.core.compiler import Flags
    from numba.core.registry import cpu_target
    from numba.pycc import compiler as pycc_compiler

    original = pycc_compiler.compile_extra
    original_features = AOTCPUCodegen._customize_tm_features

    def compile_extra(typingctx, targetctx, func, args, return_type, flags, locals,
                      library):
        options = options_by_func.get(func)
        if options is not None:
            own = Flags()
            cpu_target.options.parse_as_flags(own, options)
            for name in ("no_compile", "no_cpython_wrapper", "no_cfunc_wrapper"):
                setattr(own, name, getattr(flags, name))
            flags = own
        return original(typingctx, targetctx, func, args, return_type, flags,
                        locals=locals, library=library)

    def host_features(self):
        # the JIT's explicit feature list for this processor, not the one LLVM derives
        # from the processor's name (numba's AOT default)
        return self._get_host_cpu_features()

    pycc_compiler.compile_extra = compile_extra
    AOTCPUCodegen._customize_tm_features = host_features
    try:
        yield
    finally:
        pycc_compiler.compile_extra = original
        AOTCPUCodegen._customize_tm_features = original_features


def default_path():
    """``_aot<extension suffix>`` beside this file."""
    return os.path.join(os.path.dirname(os.path.abspath(__file__)),
                        "_aot" + sysconfig.get_config_var("EXT_SUFFIX"))


def build(path=None, verbose=False):
    """Compile the exports into the extension module ``path`` and describe it in
    ``path + ".json"``; both are written under temporary names and renamed at the end.
    Returns the seconds it took."""
    from numba import typeof
    from numba.core import types
    from numba.pycc import CC

    from . import precompiled
    from .cache_guard import current_digest
    from .precompiled import key

    t0 = time.perf_counter()
    path = os.path.abspath(path or default_path())
    out_dir, out_file = os.path.split(path)
    tmp_file = f".{out_file}.{os.getpid()}.tmp"
    cc = CC(precompiled.MODULE, source_module=__name__)
    cc.output_dir = out_dir
    cc.output_file = tmp_file
    cc.target_cpu = "host"
    cc.verbose = verbose
    table, options = {}, {}
    for name, (fn, args, family) in exports().items():
        argtypes = tuple(typeof(a) for a in args)
        if family is not None:  # the model's numba type (ModelFamily) in the lead tuple
            assert isinstance(argtypes[0], types.BaseTuple)
        cc.export(name, argtypes)(fn.py_func)
        options[fn.py_func] = dict(fn.targetoptions)
        table[name] = {"fingerprint": key(args, family).hex(), "family": family,
                       "function": f"{fn.py_func.__module__}.{fn.py_func.__qualname__}"}
    meta = {"sources": current_digest(), "versions": precompiled.versions(),
            "host": precompiled.host(), "exports": table}
    tmp_meta = os.path.join(out_dir, f".{out_file}.json.{os.getpid()}.tmp")
    try:
        with _dispatcher_flags(options):
            cc.compile()
        with open(tmp_meta, "w") as fh:
            json.dump(meta, fh, indent=1)
        os.replace(os.path.join(out_dir, tmp_file), path)
        os.replace(tmp_meta, precompiled.metadata_path(path))
    finally:
        for f in (os.path.join(out_dir, tmp_file), tmp_meta):
            if os.path.exists(f):
                os.unlink(f)
    return time.perf_counter() - t0


if __name__ == "__main__":
    seconds = build(sys.argv[1] if len(sys.argv) > 1 else None, verbose=False)
    print(f"precompiled kernel built in {seconds:.1f} s")
