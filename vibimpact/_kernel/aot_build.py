"""Fill numba's on-disk cache with the kernel a first run needs, ahead of that run.

Run by ``setup.py`` at install time (an editable install: the sources numba caches are
the ones the package will run) and by hand as ``python -m vibimpact._kernel.aot_build``
(any install; ``--force`` compiles even when the cache is up to date).

Every kernel function is an ``@njit(cache=True)`` dispatcher (:mod:`.jitopts`).  Calling
it with arguments of the types the package calls it with compiles it and writes the
machine code to numba's cache directory; a later process loads it from there instead of
compiling (numba's public caching, nothing else: no private API, no C compiler, and the
code is the JIT's own, so the numbers are the same bits).  What is called is
:func:`exports`: the integration loop of every built-in family (plain runs and the
variational model of the Lyapunov analyses have the same argument types), every family's
initial mode and the analyses' small array routines, each with an example call built by
the code that builds the real calls (:mod:`.boundary`).

The cache is *keyed*: a stamp file, :data:`STAMP`, in the cache directory records
:func:`cache_key` -- a SHA-256 of the kernel sources, the numba, llvmlite, NumPy and
Python versions and the processor -- and what the fill took.  :func:`build` compiles
nothing when the stamp holds the current key and the cache files are there, so
installing an extra (``pip install -e ".[test]"``) does not compile the kernel again.
:mod:`.cache_stamp` holds the stamp and reads it to say whether the filled cache is in use.
"""
from __future__ import annotations

import argparse
import datetime
import sys
import time

import numpy as np

from .cache_stamp import (STAMP, cache_dir, cache_key, cached_functions,  # noqa: F401
                          read_stamp, write_stamp)


def _integrate_example(family):
    """A plain run of a built-in family's model through :func:`.boundary.integrate`'s
    argument list (the Benettin mode and the model's variational equations have the same
    types)."""
    from . import boundary as kb
    from .driver import workspace

    km = kb.kernel_family(family)
    n = km.n_state
    problem = kb.Problem(kb.builtin(family), km.terminal, km.n_mode,
                         np.zeros(len(km.param_names)), 1.0, n_state=n)
    method = kb.Method.named("dop853")
    options = kb.Options(rtol=1e-9, atol=1e-12, h_fixed=0.01, max_step=0.1, bound=1e3,
                         event_tol=1e-12, max_steps_per_period=100_000)
    mode = np.zeros(km.n_mode, dtype=np.int64)
    return kb.integrate_args(problem, method, options,
                             workspace(n, problem.terminal.size, mode.size), np.zeros(n),
                             mode, kb.new_clock(problem, options), 1, 0, np.empty((1, n)),
                             kb.EventLog(64, n, km.n_mode).arrays(), 0,
                             np.empty((1, n)), kb.counters())


def exports():
    """``{name: (dispatcher, example arguments, model family or None)}``: the kernel
    functions the fill compiles, each with a call of the types the package makes: the
    integration loop and the initial mode of every built-in family
    (:func:`.registry.families`), the array routines."""
    from . import boundary, driver, registry

    out: dict[str, tuple[object, tuple[object, ...], str | None]] = {}
    for family in registry.families():
        km = registry.family(family)
        out[f"integrate[{family}]"] = (driver.integrate, _integrate_example(family), family)
        init = boundary.initial_mode(family)
        out[init.name] = (init.jit, (0.0, np.zeros(km.n_state), np.zeros(
            len(km.param_names)), np.zeros(km.n_mode, dtype=np.int64)), None)
    for routine, args in boundary.array_routine_calls():
        out[routine.name] = (routine.jit, args, None)
    return out


def _exported_names():
    """The cache index names of :func:`exports` (``module.function``), spelled as numba
    names the index files: a function made inside another (a model's functions built by a
    factory, ``stop_model.<locals>.rhs``) without the angle brackets
    (``stop_model.locals.rhs``)."""
    return {f"{fn.py_func.__module__.rsplit('.', 1)[-1]}."
            f"{fn.py_func.__qualname__.replace('<', '').replace('>', '')}"
            for fn, _, _ in exports().values()}


def up_to_date(directory=None):
    """Whether ``directory``'s stamp holds the current :func:`cache_key` and every
    function of :func:`exports` has its cache index there."""
    stamp = read_stamp(directory)
    if stamp is None or stamp.get("key") != cache_key()["key"]:
        return False
    return _exported_names() <= set(cached_functions(directory))


def build(force=False):
    """Fill numba's cache with :func:`exports` unless it is :func:`up_to_date` (or
    ``force``), and stamp it.

    Returns
    -------
    dict
        ``{"compiled": bool, "seconds": float, "cache_dir": str, "key": str,
        "functions": [names]}``; ``seconds`` is the time the fill took now (0.0 when
        nothing was compiled).
    """
    directory = cache_dir()
    key = cache_key()
    if not force and up_to_date(directory):
        return {"compiled": False, "seconds": 0.0, "cache_dir": str(directory),
                "key": key["key"], "functions": cached_functions(directory)}
    t0 = time.perf_counter()
    for fn, args, _ in exports().values():
        fn(*args)
    seconds = time.perf_counter() - t0
    functions = cached_functions(directory)
    write_stamp(directory, {
        **key, "seconds": round(seconds, 1), "functions": functions,
        "exported": sorted(_exported_names()),
        "filled_at": datetime.datetime.now(datetime.UTC).isoformat(
            timespec="seconds")})
    return {"compiled": True, "seconds": seconds, "cache_dir": str(directory),
            "key": key["key"], "functions": functions}


def describe(result):
    """One line saying what :func:`build` did."""
    where = f"numba's cache {result['cache_dir']} (key {result['key'][:12]})"
    if not result["compiled"]:
        return f"vibimpact: kernel already compiled for these sources and versions in {where}"
    return (f"vibimpact: compiled the kernel ({len(exports())} entry points) into {where} "
            f"in {result['seconds']:.1f} s")


def main(argv=None):
    """``python -m vibimpact._kernel.aot_build [--force]``: fill the cache, say what
    was done on stdout."""
    parser = argparse.ArgumentParser(prog="python -m vibimpact._kernel.aot_build",
                                     description=__doc__.splitlines()[0])
    parser.add_argument("--force", action="store_true",
                        help="compile even when the cache is up to date")
    args = parser.parse_args(argv)
    if args.force or not up_to_date():
        print(f"vibimpact: compiling the numba kernel into its on-disk cache "
              f"({', '.join(exports())}), once for these sources and versions", flush=True)
    print(describe(build(force=args.force)), flush=True)


if __name__ == "__main__":
    sys.exit(main())
