"""Provenance and CF global attributes of every file vibimpact writes.

Every writer (:func:`vibimpact.io.write_netcdf`, :func:`vibimpact.maps.write_map`) passes
the dataset's global attributes through :func:`file_attrs`, which adds

* the CF attributes ``Conventions`` (:data:`CONVENTIONS`), ``history`` (one line per
  write: the ISO-8601 UTC time and the command line or call that wrote the file, appended
  to an existing history), ``date_created`` (ISO-8601 UTC; kept when the dataset
  already has one, e.g. a file read and written again), ``title`` (kept when the dataset
  has one), ``source`` (the package and its version) and ``references`` (what the
  writer passes: the literature the file's model declares; kept when the dataset has
  its own; else :data:`REFERENCES`, the package);
* the provenance the bit-identity promise depends on (:func:`provenance`): the package
  version and, when the package runs from a git checkout, its commit; the versions of the
  numerical and I/O dependencies imported by this process; the Python version, the
  platform and the CPU model.

The attributes in :data:`VOLATILE` (the time stamps, the wall time) differ between two
writes of the same data, those in :data:`ENVIRONMENT` (the versions, the git commit, the
platform, the CPU) between two machines or installations, and ``command`` between a run
and its resumed or redirected repetition: :data:`NOT_COMPARED`, the deny-list of
:func:`vibimpact.io.differences` (``vibimpact rerun``, resumed runs), which compares every
other global attribute and every attribute of every variable.

Only the standard library is imported here.  The git commit and the CPU model are looked
up once per process (``git`` absent, not a checkout, or any failure: no commit recorded).
"""
from __future__ import annotations

import datetime
import functools
import os
import platform
import shlex
import subprocess
import sys
from collections.abc import Mapping
from typing import Any

#: the CF version the files follow
CONVENTIONS = "CF-1.8"
#: the CF ``references`` of a file whose model declares no literature (a user's model, a
#: file of no model): the package that computed it
REFERENCES = "vibimpact: bifurcation and chaos analysis of vibro-impact models"
#: distributions whose version is recorded, when this process has imported them
DEPENDENCIES = ("numpy", "scipy", "numba", "llvmlite", "xarray", "netCDF4", "zarr", "dask")
#: global attributes that change from one write of the same data to the next
VOLATILE = ("date_created", "history", "wall_time_s")
#: global attributes that say where and with what the file was written (versions of the
#: package and its dependencies, git commit, Python, platform, CPU), not what it holds
ENVIRONMENT = ("source", "vibimpact_version", "vibimpact_git_commit", "vibimpact_git_dirty",
               *(f"{name}_version" for name in DEPENDENCIES), "python_version", "platform",
               "cpu_model")
#: global attributes data comparisons (:func:`vibimpact.io.differences`) leave out: the
#: time stamps, the environment, and the command line (a resumed run adds --resume, a
#: rerun's -o names another file; the data and the other attributes say what was computed)
NOT_COMPARED = (*VOLATILE, *ENVIRONMENT, "command")


def utc_now() -> str:
    """The current UTC time as ISO-8601 text, to the second: ``2025-01-31T12:00:00Z``."""
    now = datetime.datetime.now(datetime.UTC).replace(microsecond=0)
    return now.isoformat().replace("+00:00", "Z")


@functools.cache
def git_commit() -> tuple[str | None, int | None]:
    """``(commit, dirty)`` of the package's git checkout, or ``(None, None)``.

    ``git rev-parse HEAD`` runs only when the directory above the package holds a
    ``.git`` (an editable install from a clone); an installed package (site-packages) has
    none.  ``dirty`` is 1 when tracked files differ from the commit.  Any failure (no
    ``git`` executable, a refused repository, a time-out) gives ``(None, None)``.
    """
    pkg = os.path.dirname(os.path.abspath(__file__))
    if not os.path.exists(os.path.join(os.path.dirname(pkg), ".git")):
        return None, None
    env = dict(os.environ, GIT_OPTIONAL_LOCKS="0", LC_ALL="C")  # never take index.lock
    try:
        head = subprocess.run(["git", "rev-parse", "HEAD"], cwd=pkg, env=env, timeout=10,
                              capture_output=True, text=True)
        commit = head.stdout.strip()
        if head.returncode != 0 or len(commit) not in (40, 64) or \
                any(c not in "0123456789abcdef" for c in commit):
            return None, None
        diff = subprocess.run(["git", "diff", "--quiet", "HEAD", "--"], cwd=pkg, env=env,
                              timeout=10, capture_output=True)
        dirty = {0: 0, 1: 1}.get(diff.returncode)
    except (OSError, subprocess.SubprocessError, ValueError):
        return None, None
    return commit, dirty


@functools.cache
def cpu_model() -> str:
    """The CPU model: ``model name`` of ``/proc/cpuinfo`` on Linux, otherwise
    :func:`platform.processor`, otherwise the machine type (``"unknown"`` if none)."""
    try:
        with open("/proc/cpuinfo", encoding="utf-8", errors="replace") as fh:
            for line in fh:
                key, sep, value = line.partition(":")
                if sep and key.strip() == "model name" and value.strip():
                    return " ".join(value.split())
    except OSError:
        pass
    return platform.processor() or platform.machine() or "unknown"


def dependency_versions() -> dict[str, str]:
    """``{name: version}`` of the :data:`DEPENDENCIES` this process has imported."""
    out = {}
    for name in DEPENDENCIES:
        mod = sys.modules.get(name)
        version = getattr(mod, "__version__", None) if mod is not None else None
        if version is not None:
            out[name] = str(version)
    return out


def provenance() -> dict[str, str | int]:
    """The provenance attributes: ``vibimpact_version``, ``vibimpact_git_commit`` and
    ``vibimpact_git_dirty`` (only from a git checkout), ``<dependency>_version`` for each
    imported dependency, ``python_version``, ``platform`` and ``cpu_model``."""
    from .. import __version__

    out: dict[str, str | int] = {"vibimpact_version": __version__}
    commit, dirty = git_commit()
    if commit is not None:
        out["vibimpact_git_commit"] = commit
        if dirty is not None:
            out["vibimpact_git_dirty"] = dirty
    out.update({f"{name}_version": v for name, v in dependency_versions().items()})
    out.update(python_version=platform.python_version(), platform=platform.platform(),
               cpu_model=cpu_model())
    return out


def _title(command: str) -> str:
    """``"vibimpact <subcommand> output"`` from a recorded command line, else ``"vibimpact
    output"`` (an API call)."""
    try:
        words = shlex.split(command)
    except ValueError:
        words = command.split()
    for i, word in enumerate(words[:-1]):
        if os.path.basename(word) in ("vibimpact", "__main__.py") or word == "vibimpact.cli":
            nxt = words[i + 1]
            if nxt.isidentifier():
                return f"vibimpact {nxt} output"
    return "vibimpact output"


def file_attrs(attrs: Mapping[str, Any], call: str,
               references: str | None = None) -> dict[str, Any]:
    """The global attributes of a file about to be written: ``attrs`` plus the CF and
    provenance attributes (a new dict; ``attrs`` is not changed).

    Parameters
    ----------
    attrs : Mapping
        The dataset's own global attributes.
    call : str
        The writing function, e.g. ``"vibimpact.io.write_netcdf"``: named in ``history``
        when the dataset records no ``command`` (an API call rather than the CLI).
    references : str, optional
        The CF ``references`` when ``attrs`` has none: the literature of the file's
        model (:attr:`vibimpact.models.Model.references`); None or empty:
        :data:`REFERENCES`.
    """
    from .. import __version__

    stamp = utc_now()
    out = dict(attrs)
    command = str(out.get("command") or "").strip()
    if not command:
        argv = shlex.join(sys.argv) if any(sys.argv) else "python"
        command = f"{call}() called from {argv}"
    line = f"{stamp} {command}"
    old = str(out.get("history") or "").rstrip("\n")
    out["Conventions"] = CONVENTIONS
    out["history"] = f"{old}\n{line}" if old else line
    out.setdefault("date_created", stamp)
    out.setdefault("source", f"vibimpact {__version__}")
    out.setdefault("references", references or REFERENCES)
    if not str(out.get("title") or "").strip():  # CF 2.6.2: a file says what it holds
        kind = str(out.get("kind") or "").strip()
        out["title"] = f"vibimpact {kind}".strip() if kind else _title(command)
    out.update(provenance())
    return out


__all__ = ["CONVENTIONS", "DEPENDENCIES", "ENVIRONMENT", "NOT_COMPARED", "REFERENCES",
           "VOLATILE", "cpu_model", "dependency_versions",
           "file_attrs", "git_commit", "provenance", "utc_now"]
