"""A bounded JSON reader for text a file brings in.  Standard library only.

Python's :mod:`json` parses nested arrays and objects by recursion: text nested a few
thousand levels deep (a crafted checkpoint's ``request.json``, a sweep's ``settings``
attribute) ends in a ``RecursionError``, and text of any size is read whole.  Every JSON
the toolkit reads from a file or a file's attribute goes through :func:`loads` or
:func:`load_file`: the size and the nesting depth are checked first (a linear scan of
the brackets outside strings), and any failure is one ``ValueError`` naming the file or
attribute.
"""
from __future__ import annotations

import json
import re

from ._regular import read_regular

__all__ = ["MAX_DEPTH", "MAX_BYTES", "loads", "load_file", "nesting_over"]

#: the deepest nesting accepted (vibimpact writes at most 5 levels)
MAX_DEPTH = 100
#: the largest JSON text accepted, in bytes (a checkpoint's request of a hunt for many
#: orbits is a few megabytes)
MAX_BYTES = 64 << 20

_STRING = re.compile(r'"[^"\\]*(?:\\.[^"\\]*)*"', re.S)
_BRACKET = re.compile(r"[\[\]{}]")


def nesting_over(text: str, limit: int) -> bool:
    """Whether ``text`` nests arrays and objects more than ``limit`` levels deep
    (brackets inside strings do not count; stops at the first level too deep)."""
    depth = 0
    for m in _BRACKET.finditer(_STRING.sub('""', text)):
        if m.group() in "[{":
            depth += 1
            if depth > limit:
                return True
        else:
            depth -= 1
    return False


def loads(text, what: str, *, max_depth: int = MAX_DEPTH, max_bytes: int = MAX_BYTES):
    """The value of the JSON ``text`` (str or bytes) that ``what`` holds.

    Parameters
    ----------
    text : str or bytes
    what : str
        The file or attribute, as the messages name it (``"'s.nc' attribute
        'settings'"``).
    max_depth, max_bytes : int
        The deepest nesting and the largest size accepted.

    Raises
    ------
    ValueError
        Naming ``what``: not text, not UTF-8, larger than ``max_bytes``, nested deeper
        than ``max_depth``, or not JSON.
    """
    if isinstance(text, (bytes, bytearray)):
        if len(text) > max_bytes:
            raise ValueError(f"{what} is larger than {max_bytes} bytes")
        try:
            text = bytes(text).decode("utf-8")
        except UnicodeDecodeError:
            raise ValueError(f"{what} is not UTF-8 text (not JSON)") from None
    if not isinstance(text, str):
        raise ValueError(f"{what} is not text (JSON), but {type(text).__name__}")
    if len(text) > max_bytes:
        raise ValueError(f"{what} is larger than {max_bytes} bytes")
    if nesting_over(text, max_depth):
        raise ValueError(f"{what} is JSON nested more than {max_depth} levels deep")
    try:
        return json.loads(text)
    except (ValueError, RecursionError) as exc:
        raise ValueError(f"{what} is not JSON ({exc})"[:300]) from None


def load_file(path, what: str | None = None, *, dir_fd: int | None = None,
              follow: bool = True, max_depth: int = MAX_DEPTH,
              max_bytes: int = MAX_BYTES):
    """The value of the JSON file ``path``, a regular file read without blocking
    (:func:`vibimpact.base._regular.read_regular`) and bounded (:func:`loads`).

    Parameters
    ----------
    path : str or os.PathLike
        Relative to ``dir_fd`` when given.
    what : str, optional
        How the messages name it (``repr(path)`` by default).
    dir_fd : int, optional
    follow : bool
        False: a symbolic link is refused.

    Raises
    ------
    ValueError
        Naming it: not a regular file, too large, too deep, not JSON.
    OSError
        It cannot be opened or read.
    """
    import os

    what = repr(os.fspath(path)) if what is None else what
    data = read_regular(path, what, max_bytes, dir_fd=dir_fd, follow=follow)
    return loads(data, what, max_depth=max_depth, max_bytes=max_bytes)
