"""Install-time build step: the kernel compiled ahead of time.

Everything else about the package is declared in ``pyproject.toml``.  The one extension
module, ``vibimpact._kernel._aot``, is the integration loop and the array routines a rotor
run needs, compiled by numba's ahead-of-time compiler for this machine's processor
(``vibimpact/_kernel/aot_build.py``), so that the first run does not spend 10-20 s
compiling them.  The build is optional: where it fails (no C compiler, say) the install
goes on with a warning and numba compiles the kernel on first use, as it would without
this step.
"""
import os
import shutil
import sys
import tempfile

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext


class BuildPrecompiledKernel(build_ext):
    """``build_ext`` that runs ``vibimpact._kernel.aot_build`` for the kernel module."""

    def build_extension(self, ext):
        path = os.path.abspath(self.get_ext_fullpath(ext.name))
        os.makedirs(os.path.dirname(path), exist_ok=True)
        # the sources being installed, and a numba cache of the build's own (nothing is
        # left in the source tree but the module and its description)
        sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
        cache = tempfile.mkdtemp(prefix="vibimpact-aot-cache-")
        os.environ["NUMBA_CACHE_DIR"] = cache
        try:
            from vibimpact._kernel import aot_build

            seconds = aot_build.build(path)
        except Exception as exc:  # optional: the JIT path works without it
            print(f"warning: the precompiled kernel was not built ({type(exc).__name__}: "
                  f"{exc}); numba will compile the kernel on first use", file=sys.stderr)
        else:
            print(f"precompiled kernel built in {seconds:.0f} s: {path}")
        finally:
            shutil.rmtree(cache, ignore_errors=True)

    # the description travels with the module: into the wheel, and back into the source
    # tree for an editable install (setuptools copies only the module itself)
    def _pairs(self):
        build_py = self.get_finalized_command("build_py")
        for ext in self.extensions:
            fullname = self.get_ext_fullname(ext.name)
            filename = self.get_ext_filename(fullname)
            package = ".".join(fullname.split(".")[:-1])
            inplace = os.path.join(build_py.get_package_dir(package),
                                   os.path.basename(filename))
            yield os.path.join(self.build_lib, filename), inplace

    def copy_extensions_to_source(self):
        super().copy_extensions_to_source()
        for regular, inplace in self._pairs():
            if os.path.exists(regular + ".json"):
                self.copy_file(regular + ".json", inplace + ".json")

    def get_outputs(self):
        outputs = list(super().get_outputs())
        if not self.inplace:
            outputs += [regular + ".json" for regular, _ in self._pairs()]
        return outputs

    def get_output_mapping(self):
        mapping = dict(super().get_output_mapping())
        if self.inplace:
            mapping.update({regular + ".json": inplace + ".json"
                            for regular, inplace in self._pairs()})
        return mapping


setup(
    ext_modules=[Extension("vibimpact._kernel._aot", sources=[], optional=True)],
    cmdclass={"build_ext": BuildPrecompiledKernel},
)
