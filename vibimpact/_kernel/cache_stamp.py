"""The stamp of the kernel's numba cache: what it was filled from, and whether a run
finds it in use.

The install fills numba's on-disk cache with the kernel (:mod:`.aot_build`) and writes
a stamp file, :data:`STAMP`, beside the cache files: :func:`cache_key` (a SHA-256 of the
kernel sources, the numba, llvmlite, NumPy and Python versions and the processor), the
functions it compiled and how long it took.  :func:`status` says in one line whether the
filled cache is in use and why not (``vibimpact --version`` prints it).  Nothing here
compiles anything; the fill itself is :mod:`.aot_build`'s.
"""
from __future__ import annotations

import hashlib
import json
import os
import platform
from pathlib import Path

import numpy as np

#: the stamp file, in numba's cache directory of the kernel
STAMP = "kernel-cache.json"


def cache_dir():
    """The directory numba caches the kernel in, as numba itself reports it (the
    dispatcher's public ``stats``): ``NUMBA_CACHE_DIR``'s when set, else ``__pycache__``
    beside the sources when it can be written, else numba's per-user directory."""
    from . import driver

    return Path(driver.integrate.stats.cache_path)


def versions():
    """The versions the cached machine code depends on."""
    import llvmlite
    import numba

    return {"numba": numba.__version__, "llvmlite": llvmlite.__version__,
            "numpy": np.__version__, "python": platform.python_version()}


def host():
    """The processor numba compiles for here: ``{"cpu": name, "features": str}``."""
    from llvmlite import binding as llb

    return {"cpu": llb.get_host_cpu_name(), "features": llb.get_host_cpu_features().flatten()}


def cache_key():
    """``{"key": hex digest, "sources": ..., "versions": ..., "host": ...}``: what the
    cached kernel was compiled from; ``key`` is the SHA-256 of the rest."""
    from .cache_guard import current_digest

    parts = {"sources": current_digest(), "versions": versions(), "host": host()}
    digest = hashlib.sha256(json.dumps(parts, sort_keys=True).encode()).hexdigest()
    return {"key": digest, **parts}


def read_stamp(directory=None):
    """The stamp of ``directory`` (by default :func:`cache_dir`) as a dict, or None
    when there is none or it cannot be read."""
    path = Path(directory or cache_dir()) / STAMP
    try:
        stamp = json.loads(path.read_text())
    except (OSError, ValueError):
        return None
    return stamp if isinstance(stamp, dict) else None


def cached_functions(directory=None):
    """Names of the kernel functions with a cache index in ``directory`` (by default
    :func:`cache_dir`): ``driver.integrate`` for ``driver.integrate-414.py311.nbi``."""
    directory = Path(directory or cache_dir())
    try:
        return sorted({f.name.split("-")[0] for f in directory.iterdir()
                       if f.suffix == ".nbi"})
    except OSError:
        return []


def write_stamp(directory, record):
    """Write ``record`` as :data:`STAMP` in ``directory`` atomically."""
    tmp = Path(directory) / f".{STAMP}.{os.getpid()}.tmp"
    try:
        tmp.write_text(json.dumps(record, indent=1))
        os.replace(tmp, Path(directory) / STAMP)
    finally:
        tmp.unlink(missing_ok=True)


def _differs(stamp, key):
    """What differs between a stamp and the current cache key (words), or None."""
    if stamp.get("sources") != key["sources"]:
        return "other kernel sources (edited since)"
    if stamp.get("versions") != key["versions"]:
        return f"{stamp.get('versions')}, running {key['versions']}"
    if stamp.get("host") != key["host"]:
        cpu = stamp.get("host", {}).get("cpu") if isinstance(stamp.get("host"), dict) else None
        return f"another processor ({cpu!r}, this one is {key['host']['cpu']!r})"
    return None


def cache_state():
    """``(in_use, reason)``: whether numba's cache holds the kernel filled for these
    sources, versions and processor (:mod:`.aot_build`), and one line saying so or why
    not."""
    directory = cache_dir()
    stamp = read_stamp(directory)
    refill = "python -m vibimpact._kernel.aot_build fills it"
    if stamp is None:
        cached = cached_functions(directory)
        earlier = f"; {len(cached)} functions cached by earlier runs" if cached else ""
        return False, (f"not filled at install (no {STAMP} in {directory}): "
                       f"numba compiles the kernel on first use and caches it{earlier}; "
                       f"{refill}")
    key = cache_key()
    if stamp.get("key") != key["key"]:
        why = _differs(stamp, key) or "another cache key"
        return False, (f"filled for {why}: numba compiles the kernel again on first use; "
                       f"{refill}")
    if not set(stamp.get("exported", stamp.get("functions", []))) <= set(
            cached_functions(directory)):
        return False, (f"filled, but its cache files are gone from {directory}: numba "
                       f"compiles the kernel again on first use; {refill}")
    return True, (f"in use: numba's cache {directory}, filled {stamp.get('filled_at')} "
                  f"in {stamp.get('seconds')} s (key {key['key'][:12]})")


def status():
    """Whether the kernel compiled ahead of the first run is in use, and why not (one
    line, for ``vibimpact --version``, reports and ``-vv``)."""
    return cache_state()[1]
