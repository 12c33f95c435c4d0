"""The line a first run prints when numba must compile the kernel.

The install fills numba's on-disk cache with the kernel (``vibimpact --version`` says
whether it is in use).  Where it is not (another numba, Python or processor, a cache
directory that was emptied, an install that skipped the fill), numba compiles what a
command needs on first use, silently, for a while.  :func:`listen` registers a listener
for numba's own compile event, which numba raises only when a function is compiled
rather than loaded from its cache, so that the first compile of the process prints one
line on stderr before it starts; a run whose cache is in use prints nothing.

Like :mod:`vibimpact.cli`, only the standard library is imported at module level;
numba in :func:`listen`.
"""
import sys

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


def listen(command):
    """Print :func:`compile_line` on stderr before numba's first compile in this process,
    for a ``command`` of :data:`COMPUTING` (once per process; nothing when every
    function loads from the cache)."""
    if command not in COMPUTING or _STATE["listening"]:
        return
    from numba.core import event

    class _FirstCompile(event.Listener):
        def on_start(self, ev):
            if _of_kernel(ev):
                _say()

        def on_end(self, ev):
            pass

    event.register("numba:compile", _FirstCompile())
    _STATE["listening"] = True


__all__ = ["listen", "compile_line", "COMPUTING"]
