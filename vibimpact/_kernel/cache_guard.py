"""Drop numba's on-disk cache of the kernel when any kernel source has changed.

numba checks a cached function against its *own* source file only (its modification time
and size), not against the functions it calls: after an edit of ``driver.py`` the cached
``lyapunov.benettin``, which calls ``driver.integrate``, would still run the old
integration loop, silently.  This happens to anyone who updates an editable install
(``git pull``) as much as to a developer.  So on import of the kernel package, a digest of
all its sources is compared with the one stamped in each cache directory; on a mismatch
the directory's cache files (``*.nbi``, ``*.nbc``) are deleted and the new digest
stamped, and numba recompiles on first use.

The cache directories checked are numba's default one beside the sources
(``__pycache__``) and, when ``NUMBA_CACHE_DIR`` is set, the one numba derives from it for
this package (``<NUMBA_CACHE_DIR>/_kernel_<sha1 of the package's absolute path>``, see
``numba.core.caching._UserProvidedCacheLocator``).  A directory that cannot be written is
left alone (numba then uses a cache of its own elsewhere, which this guard does not see).
"""
from __future__ import annotations

import functools
import hashlib
import os
from pathlib import Path

#: the kernel package's source directory
HERE = Path(__file__).resolve().parent
#: name of the stamp file holding the digest the cache was built from
STAMP = "kernel-sources.sha256"
#: suffixes of numba's cache files (index and data)
CACHE_SUFFIXES = (".nbi", ".nbc")


def sources_digest(src_dir=HERE):
    """SHA-256 over the names and contents of the ``*.py`` files of ``src_dir``."""
    h = hashlib.sha256()
    for f in sorted(Path(src_dir).glob("*.py")):
        h.update(f.name.encode())
        h.update(f.read_bytes())
    return h.hexdigest()


@functools.lru_cache(maxsize=1)
def current_digest():
    """:func:`sources_digest` of the installed kernel, computed once per process."""
    return sources_digest(HERE)


def cache_dirs(src_dir=HERE, environ=os.environ):
    """numba's cache directories for the functions defined in ``src_dir``."""
    src_dir = Path(src_dir)
    dirs = [src_dir / "__pycache__"]
    base = environ.get("NUMBA_CACHE_DIR")
    if base:
        tag = hashlib.sha1(str(src_dir).encode()).hexdigest()
        dirs.append(Path(base) / f"{src_dir.name}_{tag}")
    return dirs


def drop_stale_cache(src_dir=HERE, dirs=None):
    """Delete the cache files of every directory in ``dirs`` whose stamp is not the
    digest of ``src_dir``'s sources, and stamp it (atomically: a temporary file renamed).

    Returns
    -------
    int
        Number of cache files deleted.
    """
    digest = current_digest() if Path(src_dir) == HERE else sources_digest(src_dir)
    dropped = 0
    for d in (cache_dirs(src_dir) if dirs is None else dirs):
        d = Path(d)
        stamp = d / STAMP
        try:
            if stamp.read_text() == digest:
                continue
        except OSError:
            pass
        try:
            if d.is_dir():
                for f in d.iterdir():
                    if f.suffix in CACHE_SUFFIXES:
                        f.unlink(missing_ok=True)
                        dropped += 1
            d.mkdir(parents=True, exist_ok=True)
            tmp = d / f"{STAMP}.{os.getpid()}.tmp"
            tmp.write_text(digest)
            os.replace(tmp, stamp)
        except OSError:
            continue
    return dropped
