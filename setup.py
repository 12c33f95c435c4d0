"""Install-time step: numba's on-disk cache filled with the kernel.

Everything else about the package is declared in ``pyproject.toml``.  An editable install
(``pip install -e .``) runs ``python -m vibimpact._kernel.aot_build`` with this
environment's own Python and packages (not the build's isolated ones): it compiles the
integration loop and the array routines a rotor run needs into numba's cache beside the
sources, keyed by the kernel sources and the numba, llvmlite, NumPy and Python versions,
so that the first run loads them instead of compiling them (the two are timed in
``reports/performance.md``, section first_run, and ``reports/kernel_install.md``).  With the key
unchanged (installing an extra, say) it compiles nothing.  It says what it does and how
long it took (``pip install -v`` shows it; ``vibimpact --version`` says whether the
cache is in use).  It cannot fail the install: where it does not run (the dependencies
not installed yet, a regular wheel, whose sources move when installed) numba compiles
the kernel on first use and caches it, and ``python -m vibimpact._kernel.aot_build``
fills the cache by hand.
"""
import os
import subprocess
import sys
import time

from setuptools import setup
from setuptools.command.build_py import build_py

ROOT = os.path.dirname(os.path.abspath(__file__))

#: run in this environment's interpreter: -E ignores the build's PYTHONPATH (pip's
#: isolated build environment), -P keeps the working directory off sys.path
FILL = ("import sys; sys.path.insert(0, sys.argv[1]); "
        "from vibimpact._kernel.aot_build import main; main([])")


def say(text, said=None):
    """A line of the install's output (``pip install -v`` shows it), kept in ``said``."""
    line = f"vibimpact install: {text}"
    print(line, file=sys.stderr, flush=True)
    if said is not None:
        said.append(line)


def fill_kernel_cache(root=ROOT):
    """Run the cache fill of the sources under ``root``; say what it did, never raise.

    Returns
    -------
    list of str
        The lines it said.
    """
    said = []
    say("filling numba's cache with the kernel (python -m vibimpact._kernel.aot_build)",
        said)
    t0 = time.perf_counter()
    try:
        done = subprocess.run([sys.executable, "-E", "-P", "-c", FILL, root],
                              capture_output=True, text=True)
    except OSError as exc:
        say(f"the kernel was not compiled ({exc}); numba compiles it on first use", said)
        return said
    seconds = time.perf_counter() - t0
    for line in done.stdout.splitlines():
        say(line, said)
    if done.returncode != 0:
        last = (done.stderr.strip().splitlines() or ["no output"])[-1]
        say(f"the kernel was not compiled ({last}); numba compiles it on first use and "
            f"caches it, or run: python -m vibimpact._kernel.aot_build", said)
    else:
        say(f"kernel cache step done in {seconds:.1f} s", said)
    return said


class BuildPyFillingKernelCache(build_py):
    """``build_py`` that fills numba's cache with the kernel in an editable install."""

    def run(self):
        super().run()
        if getattr(self, "editable_mode", False):
            fill_kernel_cache()
        else:
            say("a regular install: numba compiles the kernel on first use and caches "
                "it; python -m vibimpact._kernel.aot_build does it now")


if __name__ == "__main__":  # setuptools runs this file as __main__; tests import it
    setup(cmdclass={"build_py": BuildPyFillingKernelCache})
