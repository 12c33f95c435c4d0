"""The line a first run prints when numba must compile the kernel.

The install fills numba's on-disk cache with the kernel (``vibimpact --version`` says
whether it is in use).  Where it is not (another numba, Python or processor, a cache
directory that was emptied, an install that skipped the fill), numba compiles what a
command needs on first use, silently, for a while.  :func:`listen` registers a listener
for numba's own compile event, which numba raises only when a function is compiled
rather than loaded from its cache, so that the first compile of the process prints one
line on stderr before it starts; a run whose cache is in use prints nothing.

Importing numba and what a command needs takes a while before the first compile starts;
where the compile is certain -- numba's cache directory for the kernel holds no index of
the integration loop, which every computing command runs -- :func:`listen` prints the
line at once, before it imports numba (:func:`compile_is_certain`).

Like :mod:`vibimpact.cli`, only the standard library is imported at module level;
numba in :func:`listen`.
"""
import os
import sys
from pathlib import Path

#: the kernel's sources, and the index file numba writes for the integration loop there
#: (``driver.integrate-<line>.py311.nbi``)
KERNEL = Path(__file__).resolve().parents[2] / "_kernel"
INDEX = "driver.integrate-*.nbi"

#: the commands that run the kernel (and so may compile it)
COMPUTING = frozenset({"simulate", "classify", "bifurcation", "map", "continue", "orbits",
                       "basins", "continue2", "attractors", "rerun"})

_STATE = {"listening": False, "said": False}


def compile_line():
    """The line printed before the first compile."""
    return ("vibimpact: compiling the kernel for first use (numba, once); later runs "
            "load it from numba's cache ('vibimpact --version' says where)")


def _say():
    if _STATE["said"]:
        return
    _STATE["said"] = True
    try:
        print(compile_line(), file=sys.stderr, flush=True)
    except (OSError, ValueError):  # a stream that cannot be written: no line, no error
        pass


def _of_kernel(ev):
    """Whether numba's compile event ``ev`` compiles a function of the package's kernel
    (not a user model's, which numba compiles in every process)."""
    data = getattr(ev, "data", None) or {}
    func = getattr(data.get("dispatcher"), "py_func", None)
    return str(getattr(func, "__module__", "")).startswith("vibimpact._kernel")


def compile_is_certain(environ=os.environ, kernel=KERNEL):
    """Whether numba will certainly compile the integration loop in this process: the
    directory it caches the kernel in holds no index of it.  Read from the file system
    only (no numba): with ``NUMBA_CACHE_DIR`` set, no such index anywhere below it;
    otherwise none in the writable ``__pycache__`` beside the kernel's sources.  False
    where it cannot tell (``__pycache__`` not writable: numba then caches in a directory
    of its own)."""
    base = environ.get("NUMBA_CACHE_DIR")
    if base:
        try:
            return not any(next(Path(d).glob(INDEX), None) for d, _, _ in os.walk(base))
        except OSError:
            return False
    cache = kernel / "__pycache__"
    if not os.access(cache if cache.is_dir() else kernel, os.W_OK):
        return False
    return next(cache.glob(INDEX), None) is None


def listen(command):
    """Print :func:`compile_line` on stderr before numba's first compile in this process,
    for a ``command`` of :data:`COMPUTING` (once per process; nothing when every
    function loads from the cache): at once where :func:`compile_is_certain`, else when
    numba starts to compile a kernel function."""
    if command not in COMPUTING or _STATE["listening"]:
        return
    from numba.core import event

    if compile_is_certain():
        # numba takes its compiler lock before it readies its typing (a while) and before
        # its cache says the function must be compiled; the kernel's modules are
        # imported by now, so the next lock is the first call of a numba function
        class _FirstLock(event.Listener):
            def on_start(self, ev):
                _say()

            def on_end(self, ev):
                pass

        event.register("numba:compiler_lock", _FirstLock())

    class _FirstCompile(event.Listener):
        def on_start(self, ev):
            if _of_kernel(ev):
                _say()

        def on_end(self, ev):
            pass

    event.register("numba:compile", _FirstCompile())
    _STATE["listening"] = True


__all__ = ["listen", "compile_line", "compile_is_certain", "COMPUTING"]
